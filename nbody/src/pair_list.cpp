/// @file pair_list.cpp
/// The contact pair list of ContactSystem (its cell grids: pair_grid.hpp): the
/// incremental update (re-insertion of the spheres that moved more than skin/2, or skin/2 plus
/// the margin of an isolated sphere) and full rebuilds.
/// The rule and its no-miss criterion are stated in contacts.hpp.
#include "pair_grid.hpp"

#include <algorithm>
#include <cassert>
#include <iterator>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <unordered_map>

#include "byte_flags.hpp"
#include "common/status.hpp"
#include "omp_team.hpp"

namespace ssdem {
namespace {
using grid::kNone;
}  // namespace

bool ContactSystem::update_neighbors(const Spheres& sp, bool force) {
  sched_.invalidate();  // (a call of this form may follow any number of drifts)
  const std::size_t n = sp.size();
  if (force || xref_.size() != n || import_) {
    build_pairs(sp);
    return true;
  }
  return local_update(sp, true);
}

bool ContactSystem::update_neighbors(const Spheres& sp, const Drift& drift) {
  const std::size_t n = sp.size();
  assert(drift.level != nullptr);
#ifndef NDEBUG
  for (std::size_t r = 0; drift.kicked && r < drift.nkicked; ++r)  // ascending, so each once, < n
    assert(drift.kicked[r] < n && (r == 0 || drift.kicked[r - 1] < drift.kicked[r]));
#endif
  cand_.clear();
  const bool all = sched_.open(n, drift.kicked, drift.nkicked, drift.level, cand_);
  drift_ = &drift;
  struct Reset {  // (drift_ is this call's only)
    const Drift*& d;
    ~Reset() { d = nullptr; }
  } reset{drift_};
  if (xref_.size() != n || import_) {
    build_pairs(sp);
    return true;
  }
  return local_update(sp, all);
}

void ContactSystem::plan(const Spheres& sp, std::uint32_t i) {
  const double D = reinsert_frac_ * skin_ + (fast_[i] ? margin_ : 0.0);
  sched_.enter(i, sched_.wait(sp.x[i], xref_[i], Vec3(drift_->h * sp.v[i]), D, sched_.horizon(i)));
}

bool ContactSystem::listed(std::size_t a, std::size_t b) const {
  if (a > b) std::swap(a, b);
  if (a + 1 >= irow_.size()) return false;
  auto first = pj_.begin() + irow_[a], last = pj_.begin() + irow_[a + 1];
  return std::binary_search(first, last, static_cast<std::uint32_t>(b));
}

bool ContactSystem::local_update(const Spheres& sp, bool all) {
  const std::size_t n = sp.size();
  // re-insertion distance: f k, or f k + M for an isolated sphere (its margin)
  const double lim2[2] = {reinsert_frac_ * reinsert_frac_ * skin_ * skin_,
                          (reinsert_frac_ * skin_ + margin_) * (reinsert_frac_ * skin_ + margin_)};
  moved_.clear();
  bool marks = false;  // whether mark_ holds the moved set already
  tests_ += drift_ && !all ? cand_.size() : n;
  if (drift_ && !all) {  // the spheres the schedule names (the same test)
    for (std::uint32_t i : cand_) {
      if ((sp.x[i] - xref_[i]).squaredNorm() > lim2[fast_[i]])
        moved_.push_back(i);
      else
        plan(sp, i);
    }
    std::sort(moved_.begin(), moved_.end());
  } else if (use_team(n)) {
    mark_.resize(n);
    const Vec3* x = sp.x.data();  // (taken once: the byte stores may alias the vectors)
    const Vec3* xr = xref_.data();
    const std::uint8_t* fs = fast_.data();
    std::uint8_t* mk = mark_.data();
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < n; ++i) mk[i] = (x[i] - xr[i]).squaredNorm() > lim2[fs[i]] ? 1 : 0;
    for_each_flagged(mark_.data(), n, [&](std::size_t i) { moved_.push_back(static_cast<std::uint32_t>(i)); });
    marked_ = moved_;
    marks = true;
  } else {
    for (std::size_t i = 0; i < n; ++i)
      if ((sp.x[i] - xref_[i]).squaredNorm() > lim2[fast_[i]]) moved_.push_back(static_cast<std::uint32_t>(i));
  }
  if (drift_ && all && sched_.planning()) {  // every sphere tested: each planned (the moved again once re-inserted)
    for (std::size_t i = 0; i < n; ++i) plan(sp, static_cast<std::uint32_t>(i));
    sched_.set_valid();
  }
  // a waiting pair must be listed once its gap falls below (1 - 2 f) skin (the list's promise)
  const double gl = (1.0 - 2.0 * reinsert_frac_) * skin_;
  auto due = [&](std::uint64_t k) {
    const auto i = static_cast<std::uint32_t>(k >> 32), j = static_cast<std::uint32_t>(k & 0xFFFFFFFFu);
    const double r = sp.s[i] + sp.s[j] + gl;
    return (sp.x[j] - sp.x[i]).squaredNorm() < r * r;
  };
  if (moved_.empty()) {
    if (waiting_.empty() || std::none_of(waiting_.begin(), waiting_.end(), due)) return false;
  } else if (moved_.size() > std::max<std::size_t>(n / 4, 32)) {  // cheaper from scratch
    build_pairs(sp);
    return true;
  }
  reinserts_ += moved_.size();
  if (!marks) {  // (the parallel test above left mark_ holding the moved flags)
    if (mark_.size() != n) {
      mark_.assign(n, 0);
      marked_.clear();
    }
    for (std::uint32_t i : marked_) mark_[i] = 0;
    for (std::uint32_t i : moved_) mark_[i] = 1;
    marked_ = moved_;
  }
  for (std::uint32_t i : moved_) {  // back into the ordinary grid at its new position
    unlink(i);
    fast_[i] = 0;
    xref_[i] = sp.x[i];
    link(i);
  }
  // then the pairs within reach of each, and, in ascending order, each that has none and no
  // partner within the larger reach either takes the margin (each isolation test sees the earlier
  // ones' margins: at the end every isolated sphere is still isolated); the searches on a team
  // (search_moved, pair_grid.cpp)
  std::vector<std::uint64_t> nk;
  search_moved(sp, nk);
  if (drift_ && sched_.valid())
    for (std::uint32_t i : moved_) plan(sp, i);  // (new reference position, margin)
  std::vector<std::pair<std::uint64_t, std::uint32_t>> ok;  // listed pairs of M: key, index
  for (std::uint32_t i : moved_) {
    for (std::uint32_t p = irow_[i]; p < irow_[i + 1]; ++p) ok.emplace_back(grid::pair_key(pi_[p], pj_[p]), p);
    for (std::uint32_t q = jrow_[i]; q < jrow_[i + 1]; ++q) {
      const std::uint32_t p = jpair_[q];
      ok.emplace_back(grid::pair_key(pi_[p], pj_[p]), p);
    }
  }
  std::sort(nk.begin(), nk.end());
  nk.erase(std::unique(nk.begin(), nk.end()), nk.end());
  std::sort(ok.begin(), ok.end());
  ok.erase(std::unique(ok.begin(), ok.end()), ok.end());
  // New pairs (in nk, not listed) wait until one of them is due: until its gap falls below
  // (1 - 2 f) skin, a pair can be neither in contact nor near (multirate.hpp), so listing it earlier
  // would change no force, level or history; a merge costs O(pairs) (the history is carried).
  // They are merged together when one is due, or when they are an eighth of the list.
  {
    std::vector<std::uint64_t> fresh;
    std::size_t q = 0;
    for (std::uint64_t k : nk) {
      while (q < ok.size() && ok[q].first < k) ++q;
      if (q == ok.size() || ok[q].first != k) fresh.push_back(k);
    }
    // waiting pairs of a re-inserted sphere were recomputed into nk (or left its reach)
    std::vector<std::uint64_t> keep;
    for (std::uint64_t k : waiting_)
      if (!mark_[k >> 32] && !mark_[k & 0xFFFFFFFFu]) keep.push_back(k);
    waiting_.clear();
    std::merge(keep.begin(), keep.end(), fresh.begin(), fresh.end(), std::back_inserter(waiting_));
    const bool merge_now = std::any_of(waiting_.begin(), waiting_.end(), due) ||
                           8 * waiting_.size() > std::max<std::size_t>(pi_.size(), 64);
    // No merge: nothing to change but the reference positions (pairs that left the reach stay
    // listed until a merge or rebuild drops them; a listed pair out of contact contributes
    // nothing). Such pairs are flagged and counted; once they are an eighth of the list,
    // everything is rebuilt so that the list does not keep growing on an expanding cloud.
    if (!merge_now) {
      for (const auto& [k, p] : ok)
        if (!std::binary_search(nk.begin(), nk.end(), k) && !stale_flag_[p]) {
          stale_flag_[p] = 1;
          ++stale_;
        }
      if (8 * stale_ <= std::max<std::size_t>(pi_.size(), 64)) return false;
      build_pairs(sp);
      return true;
    }
  }
  // Merge: old pairs with no member in M, plus the recomputed pairs of M, sorted by (i, j).
  const std::size_t P = pi_.size();
  std::vector<std::uint32_t> npi, npj;
  std::vector<std::uint8_t> nflag;  // stale flags carried for the pairs kept
  npi.reserve(P - ok.size() + nk.size());
  npj.reserve(P - ok.size() + nk.size());
  nflag.reserve(P - ok.size() + nk.size());
  std::size_t q = 0, nstale = 0;
  auto emit_new_below = [&](std::uint64_t k) {
    while (q < nk.size() && nk[q] < k) {
      npi.push_back(static_cast<std::uint32_t>(nk[q] >> 32));
      npj.push_back(static_cast<std::uint32_t>(nk[q] & 0xFFFFFFFFu));
      nflag.push_back(0);
      ++q;
    }
  };
  // the recomputed pairs of M and the waiting pairs (which hold this update's new pairs of M too)
  std::vector<std::uint64_t> add;
  add.reserve(nk.size() + waiting_.size());
  std::set_union(nk.begin(), nk.end(), waiting_.begin(), waiting_.end(), std::back_inserter(add));
  waiting_.clear();
  nk.swap(add);
  for (std::size_t p = 0; p < P; ++p) {
    if (mark_[pi_[p]] || mark_[pj_[p]]) continue;
    emit_new_below((static_cast<std::uint64_t>(pi_[p]) << 32) | pj_[p]);
    npi.push_back(pi_[p]);
    npj.push_back(pj_[p]);
    nflag.push_back(stale_flag_[p]);
    nstale += stale_flag_[p];
  }
  emit_new_below(std::numeric_limits<std::uint64_t>::max());
  stale_flag_.swap(nflag);
  stale_ = nstale;
  ++local_updates_;
  install_pairs(sp, npi, npj);
  return false;
}

void ContactSystem::build_pairs(const Spheres& sp) {
  const std::size_t n = sp.size();
  if (n >= std::numeric_limits<std::uint32_t>::max())
    throw common::InputError("ssdem: more than 2^32-1 spheres are not supported");
  ++rebuilds_;
  rebuilt_since_compute_ = true;
  waiting_.clear();
  xref_ = sp.x;
  double smax = 0.0;
  for (std::size_t i = 0; i < n; ++i) smax = std::max(smax, sp.s[i]);
  cell_ = std::max(2.0 * smax + skin_, 1e-300);
  margin_ = cell_;  // M = c: an isolated sphere's reach in the ordinary grid is at most 2 c
  fcell_ = cell_ + 2.0 * margin_;
  head_.reset(n);
  fhead_.reset(0);
  fhead_count_ = 0;
  fast_.assign(n, 0);
  next_.assign(n, kNone);
  prev_.assign(n, kNone);
  ckey_.assign(n, 0);
  for (std::size_t i = 0; i < n; ++i) link(static_cast<std::uint32_t>(i));

  const std::size_t nchunk = std::max<std::size_t>(1, std::min<std::size_t>(256, n / 64 + 1));
  const std::size_t csize = (n + nchunk - 1) / nchunk;
  std::vector<std::vector<std::uint32_t>> cj(nchunk);
  std::vector<std::vector<std::uint32_t>> ccount(nchunk);
  auto chunk = [&](std::size_t ch) {
    const std::size_t b = ch * csize, e = std::min(n, b + csize);
    auto& J = cj[ch];
    auto& C = ccount[ch];
    C.assign(e > b ? e - b : 0, 0);
    std::vector<std::uint32_t> tmp;
    for (std::size_t i = b; i < e; ++i) {
      tmp.clear();
      for_each_near(sp, static_cast<std::uint32_t>(i), [&](std::uint32_t j) {
        if (j > i) tmp.push_back(j);
      });
      std::sort(tmp.begin(), tmp.end());
      C[i - b] = static_cast<std::uint32_t>(tmp.size());
      J.insert(J.end(), tmp.begin(), tmp.end());
    }
  };
  if (use_team(n)) {
#pragma omp parallel for schedule(dynamic, 1)
    for (std::size_t ch = 0; ch < nchunk; ++ch) chunk(ch);
  } else {
    for (std::size_t ch = 0; ch < nchunk; ++ch) chunk(ch);
  }
  // Concatenate in chunk order -> pair list sorted by (i, j).
  std::vector<std::uint32_t> npi, npj;
  std::size_t total = 0;
  for (auto& J : cj) total += J.size();
  npi.reserve(total);
  npj.reserve(total);
  for (std::size_t ch = 0; ch < nchunk; ++ch) {
    std::size_t q = 0;
    for (std::size_t ii = 0; ii < ccount[ch].size(); ++ii) {
      const std::size_t i = ch * csize + ii;
      for (std::uint32_t c = 0; c < ccount[ch][ii]; ++c, ++q) {
        npi.push_back(static_cast<std::uint32_t>(i));
        npj.push_back(cj[ch][q]);
      }
    }
  }
  stale_flag_.assign(npi.size(), 0);
  stale_ = 0;
  install_pairs(sp, npi, npj);
  if (drift_ && sched_.planning()) {  // every sphere ordinary at its reference position
    for (std::size_t i = 0; i < n; ++i) plan(sp, static_cast<std::uint32_t>(i));
    sched_.set_valid();
  } else {
    sched_.invalidate();
  }
}

void ContactSystem::install_pairs(const Spheres& sp, std::vector<std::uint32_t>& npi,
                                  std::vector<std::uint32_t>& npj) {
  const std::size_t n = sp.size();
  {  // CSR start of each sphere's range as the i member
    std::vector<std::uint32_t> cnt(n + 1, 0);
    for (auto i : npi) ++cnt[i + 1];
    for (std::size_t i = 0; i < n; ++i) cnt[i + 1] += cnt[i];
    irow_ = cnt;
  }
  // Carry history from the old list (both sorted by (i, j)).
  const std::size_t P = npi.size();
  ContactHistory nh(params_.parts);
  nh.assign(P);
  if (import_) {
    import_ = false;
    // Imported history: map ids to indices, orient each record as (lower index, higher).
    std::unordered_map<std::uint64_t, std::uint32_t> idx;
    idx.reserve(n * 2);
    for (std::size_t i = 0; i < n; ++i) idx.emplace(sp.id[i], static_cast<std::uint32_t>(i));
    struct Keyed {
      std::uint64_t key;
      const HistoryRecord* r;
      bool flip;
    };
    std::vector<Keyed> recs;
    for (const auto& r0 : pending_) {
      if (r0.id_b >= kWallIdBase) continue;
      auto ia = idx.find(r0.id_a), ib = idx.find(r0.id_b);
      if (ia == idx.end() || ib == idx.end())
        throw common::InputError("checkpoint contact history names an unknown sphere id");
      std::uint32_t a = ia->second, b = ib->second;
      const bool flip = a > b;  // swapping p and n flips the fields declared to flip
      if (flip) std::swap(a, b);
      recs.push_back({(static_cast<std::uint64_t>(a) << 32) | b, &r0, flip});
    }
    std::sort(recs.begin(), recs.end(), [](const Keyed& x, const Keyed& y) { return x.key < y.key; });
    std::size_t q = 0;
    for (std::size_t p = 0; p < P && q < recs.size(); ++p) {
      const std::uint64_t k = (static_cast<std::uint64_t>(npi[p]) << 32) | npj[p];
      while (q < recs.size() && recs[q].key < k) ++q;  // not a neighbour: cannot be in contact
      if (q < recs.size() && recs[q].key == k) nh.set_from(p, *recs[q].r, recs[q].flip);
    }
    // wall history
    const std::size_t nw = walls_.size();
    if (nw) {
      wh_.configure(params_.parts);
      wh_.assign(n * nw);
      for (const auto& r : pending_) {
        if (r.id_b < kWallIdBase) continue;
        const std::size_t w = r.id_b - kWallIdBase;
        auto ia = idx.find(r.id_a);
        if (ia == idx.end() || w >= nw)
          throw common::InputError("checkpoint wall history names an unknown sphere or wall");
        wh_.set_from(ia->second * nw + w, r, false);
      }
    }
    pending_.clear();
  } else {
    std::size_t q = 0;
    const std::size_t Q = pi_.size();
    for (std::size_t p = 0; p < P && q < Q; ++p) {
      const std::uint64_t k = (static_cast<std::uint64_t>(npi[p]) << 32) | npj[p];
      auto okey = [&](std::size_t t) { return (static_cast<std::uint64_t>(pi_[t]) << 32) | pj_[t]; };
      while (q < Q && okey(q) < k) ++q;
      if (q < Q && okey(q) == k && ph_.active[q]) nh.copy_row(p, ph_, q);
    }
  }
  pi_.swap(npi);
  pj_.swap(npj);
  ph_.swap(nh);
  ++version_;
  // (zero: a pair not in contact holds a zero record, which the sums may add; a pair in contact
  // is evaluated before its spheres sum it, since every pair of a summed sphere is evaluated)
  pres_.assign(P, PairForces{Vec3::Zero(), Vec3::Zero(), Vec3::Zero()});
  pD_.resize(P);
  pedge_.assign(P, 0);
  // CSR of pairs by their j member (ascending pair index = ascending partner i).
  jrow_.assign(n + 1, 0);
  for (std::size_t p = 0; p < P; ++p) ++jrow_[pj_[p] + 1];
  for (std::size_t i = 0; i < n; ++i) jrow_[i + 1] += jrow_[i];
  jpair_.resize(P);
  {
    std::vector<std::uint32_t> fill(jrow_.begin(), jrow_.end() - 1);
    for (std::size_t p = 0; p < P; ++p) jpair_[fill[pj_[p]]++] = static_cast<std::uint32_t>(p);
  }
  const std::size_t nw = walls_.size();
  if (nw && wh_.size() != n * nw) {
    wh_.configure(params_.parts);
    wh_.assign(n * nw);
  }
}
}  // namespace ssdem
