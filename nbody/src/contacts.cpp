/// @file contacts.cpp
/// Contact force assembly (equations in contact_law.hpp, design in contacts.hpp), elastic energy and
/// the history export/import of checkpoints. The pair list itself is maintained in pair_list.cpp.
#include "ssdem/contacts.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <type_traits>
#include <unordered_map>

#include "common/status.hpp"
#include "omp_team.hpp"
#include "pair_batch.hpp"

namespace ssdem {
namespace {
struct Worst {
  double frac = 0.0;
  std::size_t a = 0, b = 0;
  std::size_t key = std::numeric_limits<std::size_t>::max();
  void offer(double f, std::size_t aa, std::size_t bb, std::size_t k) {
    if (f > frac || (f == frac && k < key)) {
      frac = f;
      a = aa;
      b = bb;
      key = k;
    }
  }
};
}  // namespace

ContactSystem::ContactSystem(const ContactParams& p, std::vector<Plane> walls, double skin)
    : params_(p), coeffs_(p), walls_(std::move(walls)), skin_(skin), ph_(p.parts), wh_(p.parts) {
  if (!(p.parts & kPartHertz) && !(p.kn > 0.0)) throw common::InputError("contact.normal.kn must be > 0");
  if ((p.parts & kPartHertz) && !(p.E > 0.0)) throw common::InputError("contact.hertz.E must be > 0");
  if ((p.parts & kPartHertz) && !(p.vmax > 0.0))
    throw common::InputError("contact.vmax must be > 0 with the 'hertz' law (its contact time, and so the dt rule, depends on the impact speed)");
  if (!TableInfo::valid(p.parts)) throw common::InputError("contact.parts: not a valid set of parts");
  if (!(skin >= 0.0)) throw common::InputError("contact.skin must be >= 0");
  for (auto& w : walls_) {
    const double nn = w.normal.norm();
    if (!(nn > 0.0)) throw common::InputError("wall normal must be non-zero");
    w.normal /= nn;
  }
}



int ContactSystem::lanes() { return kLanes; }

ContactStats ContactSystem::compute(const Spheres& sp, const std::vector<Vec3>& vpred,
                                    const std::vector<Vec3>& wpred, double h,
                                    std::vector<Vec3>& F, std::vector<Vec3>& T, double* diss) {
  // one kernel per valid set of parts, generated from the table (contact/table.hpp)
  return dispatch_parts(params_.parts, [&](auto parts) {
    return compute_impl<decltype(parts)::value>(sp, vpred, wpred, h, F, T, nullptr, diss);
  });
}

ContactStats ContactSystem::compute(const Spheres& sp, const std::vector<Vec3>& vpred,
                                    const std::vector<Vec3>& wpred, const Subset& sub,
                                    std::vector<Vec3>& F, std::vector<Vec3>& T, double* diss) {
  return dispatch_parts(params_.parts, [&](auto parts) {
    return compute_impl<decltype(parts)::value>(sp, vpred, wpred, 0.0, F, T, &sub, diss);
  });
}

// sub == nullptr: all pairs and spheres with step h; else the pairs/spheres of the subset, each
// with its own step (multi-rate; the loops are the same, only the index and h come from sub).
template <unsigned PARTS>
ContactStats ContactSystem::compute_impl(const Spheres& sp, const std::vector<Vec3>& vpred,
                                         const std::vector<Vec3>& wpred, double h0,
                                         std::vector<Vec3>& F, std::vector<Vec3>& T,
                                         const Subset* sub, double* diss) {
  const std::size_t n = sp.size();
  if (xref_.size() != n || import_)
    throw std::logic_error("ContactSystem::compute: no pair list for these spheres (update_neighbors first)");
  ContactStats st;
  st.rebuilt = rebuilt_since_compute_;
  rebuilt_since_compute_ = false;
  const std::size_t P = sub ? sub->pairs.size() : pi_.size();
  F.resize(n);
  T.resize(n);
  std::size_t ncont = 0;
  Worst worst;
  const pair_batch::Arrays arr{sp, vpred, wpred, pi_.data(), pj_.data(), ph_, pres_.data(), pD_.data(), pedge_.data()};
  if (owned_ && owned_->size() != n) throw std::logic_error("ContactSystem::set_owned: the mask does not match the spheres");
  const std::uint8_t* own = owned_ && n > 0 ? owned_->data() : nullptr;
  std::size_t nforeign = 0, nkernel = 0, nshared = 0;
  // On a team each loop runs in contiguous blocks whose cuts follow the threads' measured times
  // (loop_split.hpp): a pair in contact costs the kernel, one whose gap is only tested a few
  // loads, and equal counts leave one thread waiting.
  const bool pair_team = use_team(P);
  pair_split_.begin(P, pair_team ? omp_get_max_threads() : 1);
  const auto slots = static_cast<std::size_t>(omp_get_max_threads());
  if (kept_.size() < slots) kept_.resize(slots);
  in_team(pair_team, [&] {
    Worst lw;
    std::size_t lc = 0, lforeign = 0, lkernel = 0, lshared = 0;
    auto on_contact = [&](std::uint32_t p, double frac) {  // overlap / smaller radius
      ++lc;
      lw.offer(frac, pi_[p], pj_[p], p);
    };
    // The pairs that overlap or were in contact, evaluated kLanes at a time (pair_batch.hpp); a
    // pair whose gap is open and that was not in contact has nothing to compute (no force, no
    // history change). Two passes: the positions q of the pairs to evaluate are listed, then
    // packed in that order (the same packs as one pass would make). Where the block's first
    // pairs are mostly not in contact (a resting remnant: ~43 % of its listed pairs touch, in no
    // order a branch predictor could learn) the listing has no branch on the test: every pair's
    // position is written and the count advanced by 0 or 1. Where they are mostly in contact (a
    // pile: all), a pair in contact skips the overlap test (its positions are not read) on a
    // branch that is then predicted. The arrays are read through local pointers: the byte stores
    // below may alias anything reached through a reference.
    const int tid = omp_get_thread_num(), nth = omp_get_num_threads();
    std::size_t q0, q1;
    pair_split_.block(P, tid, nth, q0, q1);
    const double t0 = nth > 1 ? omp_get_wtime() : 0.0;
    std::vector<std::uint32_t>& kept = kept_[static_cast<std::size_t>(tid)].q;
    if (kept.size() < q1 - q0) kept.resize(q1 - q0);
    std::uint32_t* kq = kept.data();
    std::size_t nk = 0;
    const std::uint32_t* subp = sub ? sub->pairs.data() : nullptr;
    {
      const std::uint32_t* pi = pi_.data();
      const std::uint32_t* pj = pj_.data();
      const double* s = sp.s.data();
      const Vec3* x = sp.x.data();
      const std::uint8_t* act = ph_.active.data();
      std::uint8_t* edge = pedge_.data();
      double* D = pD_.data();
      PairForces* res = pres_.data();
      // (a sample of the block's first pairs: speed only, the same packs either way)
      std::size_t sampled = 0, in_contact = 0;
      for (std::size_t q = q0; q < q1 && sampled < 64; ++q, ++sampled)
        in_contact += act[subp ? subp[q] : static_cast<std::uint32_t>(q)] != 0 ? 1 : 0;
      const bool dense = 4 * in_contact >= 3 * sampled;
      for (std::size_t q = q0; q < q1; ++q) {
        const std::uint32_t p = subp ? subp[q] : static_cast<std::uint32_t>(q);
        const std::uint32_t i = pi[p], j = pj[p];
        if (own && !own[i] && !own[j]) {  // both forces are other ranks' (set_owned)
          ++lforeign;
          continue;
        }
        auto overlaps = [&] {
          const double reach = s[i] + s[j];
          return !((x[j] - x[i]).squaredNorm() >= reach * reach);
        };
        const bool keep = dense ? (act[p] != 0 || overlaps()) : ((act[p] != 0) | overlaps());
        D[p] = 0.0;  // (an evaluated pair's is set by its evaluation)
        if (edge[p] && !keep) {  // last evaluation's edge force: spent
          res[p] = PairForces{Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
          edge[p] = 0;
        }
        if (own) lshared += (keep & !(own[i] && own[j])) ? 1 : 0;
        kq[nk] = static_cast<std::uint32_t>(q);
        nk += keep ? 1 : 0;
      }
    }
    lkernel = nk;
    std::uint32_t rows[kLanes];
    double hs[kLanes];
    std::uint8_t ws[kLanes];
    const std::uint8_t* whole = sub && !sub->whole.empty() ? sub->whole.data() : nullptr;
    const double* hp = sub ? sub->hpair.data() : nullptr;
    for (std::size_t k = 0; k < nk; k += kLanes) {
      const int nl = static_cast<int>(std::min<std::size_t>(kLanes, nk - k));
      for (int l = 0; l < nl; ++l) {
        const std::uint32_t q = kq[k + static_cast<std::size_t>(l)];
        rows[l] = subp ? subp[q] : q;
        hs[l] = hp ? hp[q] : h0;
        ws[l] = whole ? whole[q] : 1;
      }
      pair_batch::eval_pack<PARTS>(coeffs_, arr, rows, hs, whole ? ws : nullptr, nl, on_contact);
    }
    if (nth > 1) pair_split_.record(tid, omp_get_wtime() - t0);
#pragma omp critical(ssdem_contact_stats)
    {
      ncont += lc;
      nforeign += lforeign;
      nkernel += lkernel;
      nshared += lshared;
      worst.offer(lw.frac, lw.a, lw.b, lw.key);
    }
  });
  pair_split_.end();
  st.contacts = ncont;
  st.foreign_pairs = nforeign;
  st.kernel_pairs = nkernel;
  st.shared_pairs = nshared;
  const std::size_t nw = walls_.size();
  std::size_t nwc = 0;
  Worst wworst;
  const std::size_t ns = sub ? sub->spheres.size() : n;
  const PairForces* pres = pres_.data();
  const double* pD = pD_.data();
  const std::uint8_t* active = ph_.active.data();
  const std::uint8_t* edge = pedge_.data();
  // A sphere's sums over its listed pairs (j side, then i side: ascending partner). A pair not in
  // contact holds a zero record, and adding its +0 leaves f and t bit for bit as skipping it would
  // (a sum started at +0 is never -0). Where at least a quarter of the evaluated pairs are in
  // contact (a resting remnant: about half) every record is added without a test, which costs no
  // mispredicted branch; where few are (a cloud of fragments, a pile not yet touching), only the
  // records of pairs in contact are read. Same bits either way.
  auto sum_pairs = [&](auto every, std::size_t k, Vec3& f, Vec3& t, double& dk) {
    constexpr bool kEvery = decltype(every)::value;
    for (std::uint32_t q = jrow_[k]; q < jrow_[k + 1]; ++q) {
      const std::uint32_t p = jpair_[q];
      if (kEvery || active[p] || edge[p]) {
        f -= pres[p].F;
        t += pres[p].Tn;
      }
      dk += 0.5 * pD[p];
    }
    for (std::uint32_t p = irow_[k]; p < irow_[k + 1]; ++p) {
      if (kEvery || active[p] || edge[p]) {
        f += pres[p].F;
        t += pres[p].Tp;
      }
      dk += 0.5 * pD[p];
    }
  };
  const bool every = 4 * ncont >= P - nforeign;  // (the skipped pairs are no one's records here)
  const bool sphere_team = use_team(ns);
  sphere_split_.begin(ns, sphere_team ? omp_get_max_threads() : 1);
  in_team(sphere_team, [&] {
    Worst lw;
    std::size_t lc = 0;
    const int tid = omp_get_thread_num(), nth = omp_get_num_threads();
    std::size_t r0, r1;
    sphere_split_.block(ns, tid, nth, r0, r1);
    const double t0 = nth > 1 ? omp_get_wtime() : 0.0;
    for (std::size_t r = r0; r < r1; ++r) {
      const std::size_t k = sub ? sub->spheres[r] : r;
      const double h = sub ? sub->hsphere[r] : h0;
      Vec3 f = Vec3::Zero(), t = Vec3::Zero();
      if (own && !own[k]) {  // another rank's sphere: its force is its owner's (set_owned)
        F[k] = f;
        T[k] = t;
        continue;
      }
      double dk = 0.0;
      if (every)
        sum_pairs(std::true_type{}, k, f, t, dk);
      else
        sum_pairs(std::false_type{}, k, f, t, dk);
      for (std::size_t w = 0; w < nw; ++w) {
        const Plane& pl = walls_[w];
        double dist = (sp.x[k] - pl.point).dot(pl.normal);
        const std::size_t s = k * nw + w;
        if (dist >= sp.s[k] && !wh_.active[s]) continue;
        // in contact, or released now: the kernel gives the released contact's history energy as
        // dissipated and, with edges on, its edge force
        dist = std::max(dist, 1e-9 * sp.s[k]);
        bool act = wh_.active[s];
        PairResult res;
        static const Vec3 zero = Vec3::Zero();
        contact_pair<PARTS, true>(coeffs_, -dist * pl.normal, sp.s[k], 0.0, sp.m[k], vpred[k],
                                  zero, wpred[k], zero, sp.v[k], zero, sp.w[k], zero, h, act,
                                  wh_.row(s), res);
        wh_.active[s] = act ? 1 : 0;
        f += res.F;
        t += res.Tp;
        dk += res.diss;
        if (!act) continue;
        ++lc;
        lw.offer(res.overlap / sp.s[k], k, k, s);
      }
      F[k] = f;
      T[k] = t;
      if (diss) diss[k] += dk;
    }
    if (nth > 1) sphere_split_.record(tid, omp_get_wtime() - t0);
#pragma omp critical(ssdem_wall_stats)
    {
      nwc += lc;
      wworst.offer(lw.frac, lw.a, lw.b, lw.key);
    }
  });
  sphere_split_.end();
  st.wall_contacts = nwc;
  st.max_overlap_frac = worst.frac;
  st.worst_a = worst.a;
  st.worst_b = worst.b;
  if (wworst.frac > st.max_overlap_frac) {
    st.max_overlap_frac = wworst.frac;
    st.worst_a = st.worst_b = wworst.a;
  }
  return st;
}

void ContactSystem::add_elastic_energy(const Spheres& sp, common::ExactSum& e,
                                       const std::vector<std::uint8_t>* owned) const {
  dispatch_parts(params_.parts, [&](auto parts) {
    constexpr unsigned PARTS = decltype(parts)::value;
    for (std::size_t p = 0; p < pi_.size(); ++p) {
      if (!ph_.active[p]) continue;
      const std::size_t i = pi_[p], j = pj_[p];
      if (owned && !(*owned)[i]) continue;
      const double d = (sp.x[j] - sp.x[i]).norm();
      const double x = sp.s[i] + sp.s[j] - d;
      if (x <= 0.0) continue;
      e += contact_elastic_energy<PARTS>(coeffs_, x, sp.s[i] * sp.s[j] / (sp.s[i] + sp.s[j]), ph_.row(p));
    }
    const std::size_t nw = walls_.size();
    for (std::size_t k = 0; k < sp.size() && nw; ++k) {
      if (owned && !(*owned)[k]) continue;
      for (std::size_t w = 0; w < nw; ++w) {
        const std::size_t s = k * nw + w;
        if (!wh_.active[s]) continue;
        const double x = sp.s[k] - (sp.x[k] - walls_[w].point).dot(walls_[w].normal);
        if (x <= 0.0) continue;
        e += contact_elastic_energy<PARTS>(coeffs_, x, sp.s[k], wh_.row(s), true);
      }
    }
    return 0;
  });
}

std::vector<HistoryRecord> ContactSystem::export_history(const Spheres& sp) const {
  std::vector<HistoryRecord> out;
  for (std::size_t p = 0; p < pi_.size(); ++p) {
    if (!ph_.active[p]) continue;
    HistoryRecord r;
    r.id_a = sp.id[pi_[p]];
    r.id_b = sp.id[pj_[p]];
    ph_.get_into(p, r);
    out.push_back(r);
  }
  const std::size_t nw = walls_.size();
  for (std::size_t k = 0; k < sp.size() && nw && wh_.size() == sp.size() * nw; ++k)
    for (std::size_t w = 0; w < nw; ++w) {
      const std::size_t s = k * nw + w;
      if (!wh_.active[s]) continue;
      HistoryRecord r;
      r.id_a = sp.id[k];
      r.id_b = kWallIdBase + w;
      wh_.get_into(s, r);
      out.push_back(r);
    }
  return out;
}

void ContactSystem::import_history(const Spheres& sp, const std::vector<HistoryRecord>& recs) {
  pending_ = recs;
  import_ = true;
  wh_.assign(0);
  build_pairs(sp);
}

double ContactSystem::bytes_per_sphere(std::size_t n) const {
  if (n == 0) return 0.0;
  const double P = static_cast<double>(pi_.size());
  const double per_pair = 4 + 4 + 3 * 24 + 8 + 4 + ph_.bytes_per_row();  // pi, pj, results, jpair, history
  double b = P * per_pair + 8.0 * (n + 1) + 24.0 * n;  // irow/jrow, xref
  b += 17.0 * static_cast<double>(n) + static_cast<double>(head_.bytes() + fhead_.bytes());  // grids: links, keys, flags, tables
  b += static_cast<double>(wh_.size()) * wh_.bytes_per_row();
  return b / static_cast<double>(n) + sched_.bytes_per_sphere(n);
}

}  // namespace ssdem
