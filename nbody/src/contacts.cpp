/// @file contacts.cpp
/// Contact force assembly (equations in contact_law.hpp, design in contacts.hpp), elastic energy and
/// the history export/import of checkpoints. The pair list itself is maintained in pair_list.cpp.
#include "ssdem/contacts.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <unordered_map>

#include "common/status.hpp"

namespace ssdem {
namespace {
// Below this many items a loop runs serially (thread start-up would dominate).
constexpr std::size_t kOmpMin = 2048;
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
    : params_(p), coeffs_(p), walls_(std::move(walls)), skin_(skin) {
  tang_ = p.parts & kPartTangential;
  roll_ = p.parts & kPartRolling;
  twist_ = p.parts & kPartTwisting;
  hist_ = tang_ || roll_ || twist_;
  if (!(p.kn > 0.0)) throw common::InputError("contact.normal.kn must be > 0");
  if (!(skin >= 0.0)) throw common::InputError("contact.skin must be >= 0");
  for (auto& w : walls_) {
    const double nn = w.normal.norm();
    if (!(nn > 0.0)) throw common::InputError("wall normal must be non-zero");
    w.normal /= nn;
  }
}



ContactStats ContactSystem::compute(const Spheres& sp, const std::vector<Vec3>& vpred,
                                    const std::vector<Vec3>& wpred, double h,
                                    std::vector<Vec3>& F, std::vector<Vec3>& T) {
  switch (params_.parts & 15u) {
#define SSDEM_CASE(k) \
  case k:             \
    return compute_impl<k>(sp, vpred, wpred, h, F, T);
    SSDEM_CASE(0) SSDEM_CASE(1) SSDEM_CASE(2) SSDEM_CASE(3) SSDEM_CASE(4) SSDEM_CASE(5)
    SSDEM_CASE(6) SSDEM_CASE(7) SSDEM_CASE(8) SSDEM_CASE(9) SSDEM_CASE(10) SSDEM_CASE(11)
    SSDEM_CASE(12) SSDEM_CASE(13) SSDEM_CASE(14) SSDEM_CASE(15)
#undef SSDEM_CASE
  }
  return {};
}

template <unsigned PARTS>
ContactStats ContactSystem::compute_impl(const Spheres& sp, const std::vector<Vec3>& vpred,
                                         const std::vector<Vec3>& wpred, double h,
                                         std::vector<Vec3>& F, std::vector<Vec3>& T) {
  const std::size_t n = sp.size();
  if (xref_.size() != n || import_)
    throw std::logic_error("ContactSystem::compute: no pair list for these spheres (update_neighbors first)");
  ContactStats st;
  st.rebuilt = rebuilt_since_compute_;
  rebuilt_since_compute_ = false;
  const std::size_t P = pi_.size();
  F.resize(n);
  T.resize(n);
  std::size_t ncont = 0;
  Worst worst;
#pragma omp parallel if (P >= kOmpMin)
  {
    Worst lw;
    std::size_t lc = 0;
#pragma omp for schedule(static)
    for (std::size_t p = 0; p < P; ++p) {
      const std::size_t i = pi_[p], j = pj_[p];
      bool act = active_[p];
      PairHistoryRef hr;
      if (tang_) hr.S = &S_[p];
      if (hist_) hr.n_old = &nold_[p];
      if (roll_) hr.theta_r = &thr_[p];
      if (twist_) hr.theta_q = &thq_[p];
      PairResult res;
      const double mu = sp.m[i] * sp.m[j] / (sp.m[i] + sp.m[j]);
      const bool c = contact_pair<PARTS, false>(coeffs_, sp.x[j] - sp.x[i], sp.s[i], sp.s[j], mu,
                                                vpred[i], vpred[j], wpred[i], wpred[j], sp.v[i],
                                                sp.v[j], sp.w[i], sp.w[j], h, act, hr, res);
      active_[p] = act ? 1 : 0;
      if (c) {
        pF_[p] = res.F;
        pTp_[p] = res.Tp;
        pTn_[p] = res.Tn;
        ++lc;
        lw.offer(res.overlap / std::min(sp.s[i], sp.s[j]), i, j, p);
      }
    }
#pragma omp critical(ssdem_contact_stats)
    {
      ncont += lc;
      worst.offer(lw.frac, lw.a, lw.b, lw.key);
    }
  }
  st.contacts = ncont;
  const std::size_t nw = walls_.size();
  std::size_t nwc = 0;
  Worst wworst;
#pragma omp parallel if (n >= kOmpMin)
  {
    Worst lw;
    std::size_t lc = 0;
#pragma omp for schedule(static)
    for (std::size_t k = 0; k < n; ++k) {
      Vec3 f = Vec3::Zero(), t = Vec3::Zero();
      for (std::uint32_t q = jrow_[k]; q < jrow_[k + 1]; ++q) {
        const std::uint32_t p = jpair_[q];
        if (active_[p]) {
          f -= pF_[p];
          t += pTn_[p];
        }
      }
      for (std::uint32_t p = irow_[k]; p < irow_[k + 1]; ++p) {
        if (active_[p]) {
          f += pF_[p];
          t += pTp_[p];
        }
      }
      for (std::size_t w = 0; w < nw; ++w) {
        const Plane& pl = walls_[w];
        double dist = (sp.x[k] - pl.point).dot(pl.normal);
        const std::size_t s = k * nw + w;
        if (dist >= sp.s[k]) {
          wactive_[s] = 0;
          continue;
        }
        dist = std::max(dist, 1e-9 * sp.s[k]);
        bool act = wactive_[s];
        PairHistoryRef hr;
        if (tang_) hr.S = &wS_[s];
        if (hist_) hr.n_old = &wnold_[s];
        if (roll_) hr.theta_r = &wthr_[s];
        if (twist_) hr.theta_q = &wthq_[s];
        PairResult res;
        static const Vec3 zero = Vec3::Zero();
        contact_pair<PARTS, true>(coeffs_, -dist * pl.normal, sp.s[k], 0.0, sp.m[k], vpred[k],
                                  zero, wpred[k], zero, sp.v[k], zero, sp.w[k], zero, h, act, hr,
                                  res);
        wactive_[s] = act ? 1 : 0;
        f += res.F;
        t += res.Tp;
        ++lc;
        lw.offer(res.overlap / sp.s[k], k, k, s);
      }
      F[k] = f;
      T[k] = t;
    }
#pragma omp critical(ssdem_wall_stats)
    {
      nwc += lc;
      wworst.offer(lw.frac, lw.a, lw.b, lw.key);
    }
  }
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

double ContactSystem::elastic_energy(const Spheres& sp) const {
  double e = 0.0;
  for (std::size_t p = 0; p < pi_.size(); ++p) {
    if (!active_[p]) continue;
    const std::size_t i = pi_[p], j = pj_[p];
    const double d = (sp.x[j] - sp.x[i]).norm();
    const double x = sp.s[i] + sp.s[j] - d;
    if (x <= 0.0) continue;
    e += contact_elastic_energy(coeffs_, params_.parts, x, sp.s[i] * sp.s[j] / (sp.s[i] + sp.s[j]),
                                tang_ ? &S_[p] : nullptr, roll_ ? &thr_[p] : nullptr,
                                twist_ ? &thq_[p] : nullptr);
  }
  const std::size_t nw = walls_.size();
  for (std::size_t k = 0; k < sp.size() && nw; ++k)
    for (std::size_t w = 0; w < nw; ++w) {
      const std::size_t s = k * nw + w;
      if (!wactive_[s]) continue;
      const double x = sp.s[k] - (sp.x[k] - walls_[w].point).dot(walls_[w].normal);
      if (x <= 0.0) continue;
      e += contact_elastic_energy(coeffs_, params_.parts, x, sp.s[k], tang_ ? &wS_[s] : nullptr,
                                  roll_ ? &wthr_[s] : nullptr, twist_ ? &wthq_[s] : nullptr);
    }
  return e;
}

std::vector<HistoryRecord> ContactSystem::export_history(const Spheres& sp) const {
  std::vector<HistoryRecord> out;
  for (std::size_t p = 0; p < pi_.size(); ++p) {
    if (!active_[p]) continue;
    HistoryRecord r;
    r.id_a = sp.id[pi_[p]];
    r.id_b = sp.id[pj_[p]];
    if (tang_) r.S = S_[p];
    if (hist_) r.n_old = nold_[p];
    if (roll_) r.theta_r = thr_[p];
    if (twist_) r.theta_q = thq_[p];
    out.push_back(r);
  }
  const std::size_t nw = walls_.size();
  for (std::size_t k = 0; k < sp.size() && nw && wactive_.size() == sp.size() * nw; ++k)
    for (std::size_t w = 0; w < nw; ++w) {
      const std::size_t s = k * nw + w;
      if (!wactive_[s]) continue;
      HistoryRecord r;
      r.id_a = sp.id[k];
      r.id_b = kWallIdBase + w;
      if (tang_) r.S = wS_[s];
      if (hist_) r.n_old = wnold_[s];
      if (roll_) r.theta_r = wthr_[s];
      if (twist_) r.theta_q = wthq_[s];
      out.push_back(r);
    }
  return out;
}

void ContactSystem::import_history(const Spheres& sp, const std::vector<HistoryRecord>& recs) {
  pending_ = recs;
  import_ = true;
  wactive_.clear();
  build_pairs(sp);
}

double ContactSystem::bytes_per_sphere(std::size_t n) const {
  if (n == 0) return 0.0;
  const double P = static_cast<double>(pi_.size());
  double per_pair = 4 + 4 + 1 + 3 * 24 + 4;  // pi, pj, active, results, jpair
  if (tang_) per_pair += 24;
  if (hist_) per_pair += 24;
  if (roll_) per_pair += 24;
  if (twist_) per_pair += 8;
  double b = P * per_pair + 8.0 * (n + 1) + 24.0 * n;  // irow/jrow, xref
  b += static_cast<double>(wactive_.size()) * (1 + (tang_ ? 24 : 0) + (hist_ ? 24 : 0) +
                                               (roll_ ? 24 : 0) + (twist_ ? 8 : 0));
  return b / static_cast<double>(n);
}

}  // namespace ssdem
