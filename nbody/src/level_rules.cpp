/// @file level_rules.cpp
/// The multi-rate level rules (level_rules.hpp; rules and proofs in multirate.hpp): each listed
/// pair's l_c, the new level of the spheres synchronised at a base step, the equalisation of
/// near pairs to the fixed point, and the pair subset of a multi-rate force evaluation.
#include "ssdem/level_rules.hpp"

#include <omp.h>

#include <algorithm>
#include <cstdint>
#include <iterator>
#include <vector>

#include "byte_flags.hpp"
#include "omp_team.hpp"

namespace ssdem {
namespace {
constexpr std::uint8_t kNone = 255;  // no wall in reach (wall_level)
}  // namespace

void LevelRules::reset(std::size_t n, const std::vector<std::uint8_t>* levels) {
  if (levels && levels->size() == n)
    level = *levels;
  else
    level.assign(n, 0);
  sync.assign(n, 0);
  promoted.assign(n, 0);
  lflag.assign(n, 0);
  invalidate();
}

void LevelRules::cap(int L) {
  for (std::size_t i = 0; i < level.size(); ++i)
    if (level[i] > L) {
      level[i] = static_cast<std::uint8_t>(L);
      lflag[i] = 1;
    }
}

int LevelRules::pair_level(const Spheres& sp, std::uint32_t i, std::uint32_t j) const {
  const double mi = sp.m[i], mj = sp.m[j];
  return clock_.level(mi * mj / (mi + mj), sp.s[i] * sp.s[j] / (sp.s[i] + sp.s[j]));
}

int LevelRules::wall_level(const Spheres& sp, const ContactSystem& cs, std::uint32_t i) const {
  int l = kNone;
  for (const Plane& w : cs.walls())
    if ((sp.x[i] - w.point).dot(w.normal) < sp.s[i] + near_gap_) {
      l = std::min(l, clock_.level(sp.m[i], sp.s[i]));
      break;  // one wall law: the same level for every wall
    }
  return l;
}

// l_c of every listed pair, cached per pair (it depends only on the two masses and radii): the
// level rules below read it for every listed pair at every base step.
void LevelRules::update_pair_levels(const Spheres& sp, const ContactSystem& cs) {
  if (cs.list_version() == plev_version_) return;
  const auto& pi = cs.pair_i();
  const auto& pj = cs.pair_j();
  const std::size_t P = pi.size();
  plev_.resize(P);
  for_blocks(P, Work::items, [&](std::size_t lo, std::size_t hi) {
    for (std::size_t p = lo; p < hi; ++p) plev_[p] = static_cast<std::uint8_t>(pair_level(sp, pi[p], pj[p]));
  });
  // per sphere the lowest l_c of its listed pairs: assign() skips a sphere already at or below it
  const std::size_t n = level.size();
  pmin_.assign(n, kNone);
  for (std::size_t p = 0; p < P; ++p) {
    pmin_[pi[p]] = std::min(pmin_[pi[p]], plev_[p]);
    pmin_[pj[p]] = std::min(pmin_[pj[p]], plev_[p]);
  }
  plev_version_ = cs.list_version();
}

// The start of a level decision (sync = level <= tz, nothing promoted) and the new levels of the
// spheres synchronised now: min(L, tz, l_c of near pairs/walls), in one pass.
// Per sphere over its own pairs (both CSR directions): parallel, each sphere writes its own level.
// The distance test runs only for a pair whose l_c would lower the level, and the pairs are not
// visited at all once the level is at the lowest l_c of the sphere's pairs (a remnant at rest:
// every sphere already on its pairs' level).
void LevelRules::assign(const Spheres& sp, const ContactSystem* cs, int tz, int L, const BondTerms* bonds,
                        const std::uint8_t* mask) {
  const std::size_t n = level.size();
  const int top = std::min(tz, L);
  const bool ct = cs != nullptr;
  const std::vector<std::uint32_t> none;
  const auto& pi = ct ? cs->pair_i() : none;
  const auto& pj = ct ? cs->pair_j() : none;
  const auto& ri = ct ? cs->row_i() : none;
  const auto& rj = ct ? cs->row_j() : none;
  const auto& jp = ct ? cs->jpair() : none;
  const bool walls = ct && !cs->walls().empty();
  promo_.clear();
  // The loops read everything through a local copy of this view: the byte stores below may
  // alias anything, so whatever they read through a reference (a member, a captured variable)
  // would be reloaded after each store, and the first loop would not vectorise.
  struct View {
    std::uint8_t *lev, *syn, *pro, *flag;
    const std::uint8_t *pmin, *plev, *mask;
    const std::uint32_t *pid, *pjd, *rid, *rjd, *jpd;
    int tz, top;
    bool ct, walls;
  };
  const View view{level.data(), sync.data(), promoted.data(), lflag.data(), pmin_.data(), plev_.data(), mask,
                  pi.data(),    pj.data(),   ri.data(),       rj.data(),    jp.data(),    tz,           top,
                  ct,           walls};
  // (a scan of every sphere's level, a stream, then the synchronised spheres' pairs, items: as
  // many as at the last call with this tz, usually)
  const std::size_t tzi = static_cast<std::size_t>(std::clamp(tz, 0, kMaxLevel));
  const bool team = use_team(n, Work::stream) || use_team(synced_at_tz_[tzi]);
  // (grown only: a slot's storage is kept when a call runs without a team)
  const auto slots = static_cast<std::size_t>(team ? omp_get_max_threads() : 1);
  if (synced_by_thread_.size() < slots) synced_by_thread_.resize(slots);
  for (auto& v : synced_by_thread_) v.clear();
  // shared by count only where the blocks were skewed at the last call with this tz (threshold in
  // omp_team.hpp); the bits are the same
  const bool share = synced_skew_[tzi] >= team_thresholds().level_skew;
  in_team(team, [&] {
    const View a = view;
    // each thread its static block of spheres (consecutive, ascending with the thread number, so
    // the blocks' synchronised lists joined in thread order are ascending); each fills a vector of
    // its own, its slot's storage swapped in and out, so no two threads write one cache line while
    // listing (the shares below may write neighbouring level bytes at their boundaries)
    const int t = omp_get_thread_num(), T = omp_get_num_threads();
    std::size_t b, e;
    static_block(n, t, T, b, e);
    std::vector<std::uint32_t>& slot = synced_by_thread_[static_cast<std::size_t>(t)];
    std::vector<std::uint32_t> mine;
    mine.swap(slot);
    for (std::size_t k = b; k < e; ++k) {  // (branch-free: vectorised)
      a.syn[k] = a.lev[k] <= a.tz ? 1 : 0;
      a.pro[k] = 0;
    }
    append_at_most(a.lev, b, e, a.tz, mine);
    slot.swap(mine);
    // Each synchronised sphere's new level from its pairs' levels (it writes only its own level
    // and flag): shared by count among the threads where the blocks were skewed, since the
    // synchronised spheres of a pile lie together in memory (the 2.42 km 375 m row at t = 2 400 s:
    // one thread took 2.8x the other's perf samples here)
    if (T > 1 && share) {
#pragma omp barrier
    }
    auto level_of = [&](const std::uint32_t i) {
      if (a.mask && !a.mask[i]) return;
      int c = a.top;
      if (a.ct && c > 0) {
        const int floor = a.pmin[i];
        for (std::uint32_t p = a.rid[i]; p < a.rid[i + 1] && c > floor; ++p)
          if (a.plev[p] < c && near_pair(sp, i, a.pjd[p])) c = a.plev[p];
        for (std::uint32_t q = a.rjd[i]; q < a.rjd[i + 1] && c > floor; ++q)
          if (a.plev[a.jpd[q]] < c && near_pair(sp, a.pid[a.jpd[q]], i)) c = a.plev[a.jpd[q]];
        if (a.walls && c > 0) c = std::min(c, wall_level(sp, *cs, i));
        if (bonds && c > 0) c = bonds->cap(i, c);
      }
      if (a.lev[i] != c) {
        a.lev[i] = static_cast<std::uint8_t>(c);
        a.flag[i] = 1;
      }
    };
    if (T > 1 && share)
      for_joined_share(synced_by_thread_.data(), t, T, level_of);
    else
      for (const std::uint32_t i : slot) level_of(i);
  });
  if (team) synced_skew_[tzi] = list_skew(synced_by_thread_.data(), static_cast<int>(synced_by_thread_.size()));
  synced_.clear();
  for (const auto& v : synced_by_thread_) synced_.insert(synced_.end(), v.begin(), v.end());
  synced_at_tz_[tzi] = synced_.size();
}

void LevelRules::active(std::vector<std::uint32_t>& out) {
  out.clear();
  if (promo_.empty()) {
    out = synced_;
    return;
  }
  std::sort(promo_.begin(), promo_.end());
  out.reserve(synced_.size() + promo_.size());
  std::merge(synced_.begin(), synced_.end(), promo_.begin(), promo_.end(), std::back_inserter(out));
}

bool LevelRules::lower(std::uint32_t i, int target, int tz) {
  if (level[i] <= target) return false;
  lflag[i] = 1;
  if (sync[i]) {
    level[i] = static_cast<std::uint8_t>(target);
  } else {
    level[i] = static_cast<std::uint8_t>(std::min(target, tz));
    sync[i] = 1;
    promoted[i] = 1;
    promo_.push_back(i);
    ++promotions;
  }
  work_.push_back(i);
  return true;
}

// Near pairs: both on min(l_i, l_j, l_c) (walls: l_i <= l_c(wall)), to the fixed point.
// The rule is monotone (levels only drop; sphere i's bound f_i(min_j min(l_j, l_c(i, j))), with
// f_i(t) = t if i is synchronised, else min(t, tz)), so every order of applying it that stops at
// a fixed point stops at the same one: the largest fixed point below the starting levels.
// Only an unsettled pair, not (l_i = l_j <= l_c), can violate the rule; a settled pair holds it
// whether or not it is near. The unsettled pairs are kept from one call to the next and
// updated from the pairs of the spheres whose level changed since (lflag; rebuilt from all
// listed pairs when the list changes or more than 1/16 of the levels changed), so a pile at rest
// costs O(spheres) bytes per base step.
// The violations among them (the near ones) seed the serial worklist, with, where there are
// walls or bonds, the spheres above their wall or bond bound (a pair or bond with no lowered
// member satisfied the rule before and still does).
void LevelRules::equalise(const Spheres& sp, const ContactSystem& cs, int tz, BondTerms* bonds) {
  const auto& pi = cs.pair_i();
  const auto& pj = cs.pair_j();
  const auto& ri = cs.row_i();
  const auto& rj = cs.row_j();
  const auto& jp = cs.jpair();
  const bool walls = !cs.walls().empty();
  work_.clear();
  auto violated = [&](std::uint32_t p) {
    const std::uint32_t i = pi[p], j = pj[p];
    const int li = level[i], lj = level[j];
    const int t = std::min({li, lj, static_cast<int>(plev_[p])});
    return (t != li || t != lj) && near_pair(sp, i, j);
  };
  auto enforce = [&](std::uint32_t p) {
    if (!violated(p)) return;
    const int t = std::min({static_cast<int>(level[pi[p]]), static_cast<int>(level[pj[p]]),
                            static_cast<int>(plev_[p])});
    lower(pi[p], t, tz);
    lower(pj[p], t, tz);
  };
  const std::size_t P = pi.size(), n = level.size();
  auto unsettled = [&](std::uint32_t p) {
    const int li = level[pi[p]];
    return li != level[pj[p]] || plev_[p] < li;
  };
  const std::size_t nflag = count_flagged(lflag.data(), n);
  // many changed levels (a body breaking up): one parallel scan of all pairs is cheaper
  if (!unsettled_valid_ || unsettled_version_ != cs.list_version() || 16 * nflag > n) {
    unsettled_.clear();
    in_team(use_team(P), [&] {
      std::vector<std::uint32_t> mine;
#pragma omp for schedule(static) nowait
      for (std::size_t p = 0; p < P; ++p)
        if (unsettled(static_cast<std::uint32_t>(p))) mine.push_back(static_cast<std::uint32_t>(p));
#pragma omp critical(ssdem_level_unsettled)
      unsettled_.insert(unsettled_.end(), mine.begin(), mine.end());
    });
    std::sort(unsettled_.begin(), unsettled_.end());
    std::fill(lflag.begin(), lflag.end(), 0);
    unsettled_valid_ = true;
    unsettled_version_ = cs.list_version();
  } else if (nflag > 0) {  // (no level changed: the unsettled set is the same)
    fresh_.clear();
    for_each_flagged(lflag.data(), n, [&](std::size_t k) {
      const auto i = static_cast<std::uint32_t>(k);
      lflag[i] = 0;
      for (std::uint32_t p = ri[i]; p < ri[i + 1]; ++p) fresh_.push_back(p);
      for (std::uint32_t q = rj[i]; q < rj[i + 1]; ++q) fresh_.push_back(jp[q]);
    });
    std::sort(fresh_.begin(), fresh_.end());
    cand_.clear();
    std::merge(unsettled_.begin(), unsettled_.end(), fresh_.begin(), fresh_.end(), std::back_inserter(cand_));
    cand_.erase(std::unique(cand_.begin(), cand_.end()), cand_.end());
    unsettled_.clear();
    for (std::uint32_t p : cand_)
      if (unsettled(p)) unsettled_.push_back(p);
  }
  seeds_.clear();
  const std::size_t U = unsettled_.size();
  in_team(use_team(U), [&] {
    std::vector<std::uint32_t> mine;
#pragma omp for schedule(static) nowait
    for (std::size_t u = 0; u < U; ++u)
      if (violated(unsettled_[u])) mine.push_back(unsettled_[u]);
#pragma omp critical(ssdem_level_seeds)
    seeds_.insert(seeds_.end(), mine.begin(), mine.end());
  });
  std::sort(seeds_.begin(), seeds_.end());  // (the fixed point is order-free; this fixes the path)
  for (std::uint32_t p : seeds_) enforce(p);
  if (walls || bonds) {
    lnew_.resize(n);
    for_blocks(n, Work::items, [&](std::size_t lo, std::size_t hi) {
      for (std::size_t k = lo; k < hi; ++k) {
        const auto i = static_cast<std::uint32_t>(k);
        int t = level[i];
        if (walls && t > 0) t = std::min(t, wall_level(sp, cs, i));
        if (bonds && t > 0) t = bonds->bound(i, t);
        lnew_[k] = static_cast<std::uint8_t>(t);
      }
    });
    for (std::uint32_t i = 0; i < n; ++i)
      if (lnew_[i] < level[i]) lower(i, lnew_[i], tz);
  }
  while (!work_.empty()) {
    const std::uint32_t k = work_.back();
    work_.pop_back();
    for (std::uint32_t p = ri[k]; p < ri[k + 1]; ++p) enforce(p);
    for (std::uint32_t q = rj[k]; q < rj[k + 1]; ++q) enforce(jp[q]);
    if (walls && level[k] > 0) lower(k, wall_level(sp, cs, k), tz);
    if (bonds) bonds->enforce(k, tz, *this);
  }
}

void multirate_subset(const ContactSystem& cs, const std::vector<std::uint32_t>& active,
                      const std::vector<std::uint8_t>& sync, const std::vector<std::int64_t>& topen,
                      std::int64_t step, double h, std::vector<std::size_t>& off, ContactSystem::Subset& sub) {
  const auto& pi = cs.pair_i();
  const auto& pj = cs.pair_j();
  const auto& ri = cs.row_i();
  const auto& rj = cs.row_j();
  const auto& jp = cs.jpair();
  const std::size_t na = active.size();
  auto hpair = [&](std::uint32_t p) {
    const std::uint32_t i = pi[p], j = pj[p];
    const std::int64_t ti = sync[i] ? step - topen[i] : INT64_MAX;
    const std::int64_t tj = sync[j] ? step - topen[j] : INT64_MAX;
    return static_cast<double>(std::min(ti, tj)) * h;
  };
  // (in parallel: per active sphere its count, an exclusive prefix sum, then each sphere fills its
  // own slots, in the order of the serial loop over active spheres)
  off.resize(na + 1);
  off[0] = 0;
  for_blocks(na, Work::items, [&](std::size_t lo, std::size_t hi) {
    for (std::size_t r = lo; r < hi; ++r) {
      const std::uint32_t k = active[r];
      std::size_t c = ri[k + 1] - ri[k];
      for (std::uint32_t q = rj[k]; q < rj[k + 1]; ++q) c += sync[pi[jp[q]]] ? 0 : 1;
      off[r + 1] = c;
    }
  });
  for (std::size_t r = 0; r < na; ++r) off[r + 1] += off[r];
  sub.pairs.resize(off[na]);
  sub.hpair.resize(off[na]);
  sub.whole.resize(off[na]);
  for_blocks(na, Work::items, [&](std::size_t lo, std::size_t hi) {
    for (std::size_t r = lo; r < hi; ++r) {
      const std::uint32_t k = active[r];
      std::size_t o = off[r];
      for (std::uint32_t p = ri[k]; p < ri[k + 1]; ++p, ++o) {
        sub.pairs[o] = p;
        sub.hpair[o] = hpair(p);
        sub.whole[o] = sync[pj[p]];
      }
      for (std::uint32_t q = rj[k]; q < rj[k + 1]; ++q)
        if (!sync[pi[jp[q]]]) {  // else added from its i member
          sub.pairs[o] = jp[q];
          sub.whole[o] = 0;
          sub.hpair[o++] = hpair(jp[q]);
        }
    }
  });
}

void take_subset(SubsetCache& c, int tz, const ContactSystem& cs, const std::vector<std::uint32_t>& active,
                 const std::vector<std::uint8_t>& sync, const std::vector<std::int64_t>& topen, std::int64_t step,
                 double h, std::vector<std::size_t>& off, ContactSystem::Subset& sub) {
  if (c.by_tz.size() <= static_cast<std::size_t>(tz)) c.by_tz.resize(static_cast<std::size_t>(tz) + 1);
  SubsetCache::Entry& e = c.by_tz[static_cast<std::size_t>(tz)];
  const std::size_t na = active.size();
  bool same = !e.lent && cs.list_version() == e.version && active == e.active;
  for (std::size_t r = 0; r < na && same; ++r) same = step - topen[active[r]] == e.steps[r];
  e.lent = true;
  if (same) {
    ++c.reuses;
    sub.pairs.swap(e.pairs);
    sub.hpair.swap(e.hpair);
    sub.whole.swap(e.whole);
    return;
  }
  ++c.builds;
  multirate_subset(cs, active, sync, topen, step, h, off, sub);
  e.version = cs.list_version();
  e.active = active;
  e.steps.resize(na);
  for (std::size_t r = 0; r < na; ++r) e.steps[r] = step - topen[active[r]];
}

void keep_subset(SubsetCache& c, int tz, ContactSystem::Subset& sub) {
  SubsetCache::Entry& e = c.by_tz[static_cast<std::size_t>(tz)];
  e.pairs.swap(sub.pairs);
  e.hpair.swap(sub.hpair);
  e.whole.swap(sub.whole);
  e.lent = false;
}

}  // namespace ssdem
