/// @file contact_law.hpp
/// The soft-sphere pair kernel (force and torques on one contact), assembled at compile time from
/// the parts enabled in the set PARTS (contact/table.hpp), so that parts that are off cost nothing.
///
/// The kernel does what every law shares; the laws themselves are in contact/<part>.hpp.
/// Geometry and kinematics (S12 = Schwartz, Richardson & Michel 2012, Granular Matter 14:363;
/// the pkdgrav implementation `smoothfcn.c:DoDEM` as summarised in shared/reference/ssdem.md §1):
///   rho = x_n - x_p, d = |rho|, n = rho/d, overlap x = s_p + s_n - d  (contact iff x > 0)
///   lever arms l_p = (s_p^2 - s_n^2 + d^2)/(2d), l_n = d - l_p                    (S12 eqs 8-12)
///   u = v_n - v_p - l_n (w_n x n) - l_p (w_p x n)                                 (predicted v, w)
///   u_h: the same with the half-step velocities and spins (history increments)
/// Order: (1) normal phase of every enabled part in table order (the normal law, then the
/// dashpot, ...): F_N and |F_N|, the reference of the friction limits; (2) the history of a
/// contact that was not active is reset (n_old = n, all fields 0), else the transported fields
/// (tangent-plane vectors: S, theta_r) are rotated with the contact frame: about
/// nbar = (n_old + n)/|.| by (h/2)(w_p + w_n).nbar (half-step spins), then by the rotation
/// taking n_old to n (S12 eqs 17-19); n_old = n; (3) tangent phase of every enabled part in
/// table order. Force on p: F (n gets -F); torques Tp, Tn.
/// Velocities and spins entering the dashpots (and the Coulomb test) are the *predicted* ones at
/// t_{n+1}, as in pkdgrav. The history increments use the half-step (drift) velocities and spins
/// v_{n+1/2}, w_{n+1/2}, so that they are the midpoint rule for int u dt over [t_n, t_{n+1}], like
/// the positions that give the overlap (deviation from pkdgrav, which increments with the
/// predicted u: that puts the springs h/2 ahead of the motion and makes the tangential response
/// first order in h; measured in test_nbody_contact_oblique).
/// A plane wall is the limit s_n -> infinity with zero wall velocity: l_p = distance from the
/// centre to the plane, Rbar = s_p, the lever-arm correction in v_roll becomes 1/(2 l_p), and
/// the wall takes no torque. (Deviation: pkdgrav's wall law differs in details that are not
/// in the reference notes; this limit is the natural one for the sphere-sphere law.)
/// Dissipation. Each part adds the energy it dissipates over the step to PairCtx::diss (the
/// dashpots: C u^2 h with the velocities they act on; a slider: the work done on it minus the
/// change of its spring's energy; see each part). Summed over the run (ContactSystem::compute,
/// Spheres::dissipated) it closes the energy balance E_conservative + D = E_0 up to the
/// integration error, which is what the run reports as its energy error. Springs are never
/// counted, except the energy left in the history springs when a contact ends (lost with the
/// history): their discretisation error (the first-order onset/release error, the Mindlin
/// stiffness change) shows in that error rather than being hidden in D.
/// Per-pair step: h is an argument of the kernel, so a later per-pair rung only has to pass its
/// own h (and keep its rung in one more history column).
#pragma once
#include <Eigen/Geometry>
#include <cmath>

#include "ssdem/contact/history.hpp"
#include "ssdem/contact_params.hpp"
#include "ssdem/spheres.hpp"

namespace ssdem {

/// Coefficients shared by all pairs (precomputed once): every part's Coeffs, plus beta.
struct ContactCoeffs : TableInfo::Coeffs {
  double beta;
  explicit ContactCoeffs(const ContactParams& p) : TableInfo::Coeffs(p), beta(p.beta) {}
};

/// Result of one pair evaluation.
struct PairResult {
  Vec3 F = Vec3::Zero();   ///< force on p (n receives -F)
  Vec3 Tp = Vec3::Zero();  ///< torque on p
  Vec3 Tn = Vec3::Zero();  ///< torque on n
  double overlap = 0.0;
  double diss = 0.0;       ///< energy dissipated over the step [J]
};

namespace contact_kernel {
/// The normal law of a set of parts.
template <unsigned PARTS>
using NormalLaw = std::conditional_t<(PARTS & kPartHertz) != 0u, HertzNormal, LinearNormal>;

template <class Part>
using View = HistView<HistCols, TableInfo::vec_base<Part>(), TableInfo::scal_base<Part>()>;

template <unsigned PARTS, bool WALL, class N, class... P>
inline void normal_phase(PartList<P...>, const ContactCoeffs& c, PairCtx& k, const HistRow& r) {
  ((TableInfo::enabled<P>(PARTS) ? P::template normal_phase<PARTS, WALL, N>(c, k, View<P>{r.c, r.row})
                                 : void()),
   ...);
}
template <unsigned PARTS, bool WALL, class N, class... P>
inline void tangent_phase(PartList<P...>, const ContactCoeffs& c, PairCtx& k, const HistRow& r) {
  ((TableInfo::enabled<P>(PARTS) ? P::template tangent_phase<PARTS, WALL, N>(c, k, View<P>{r.c, r.row})
                                 : void()),
   ...);
}
template <unsigned PARTS, class N, class... P>
inline double energy(PartList<P...>, const ContactCoeffs& c, const EnergyCtx& e, const HistRow& r) {
  double s = 0.0;
  bool first = true;
  auto add = [&](double x) {
    s = first ? x : s + x;
    first = false;
  };
  ((TableInfo::enabled<P>(PARTS) ? add(P::template energy<N>(c, e, View<P>{r.c, r.row})) : void()), ...);
  return s;
}
/// Transported vector columns of a set of parts.
template <unsigned PARTS>
constexpr auto transported_columns() {
  constexpr auto f = kHistVecFields;
  constexpr int n = [] {
    int k = 0;
    for (int i = 0; i < kHistVec; ++i)
      k += (kHistVecFields[i].transported && vec_column_enabled(i, PARTS)) ? 1 : 0;
    return k;
  }();
  std::array<int, n> out{};
  int k = 0;
  for (int i = 0; i < kHistVec; ++i)
    if (f[i].transported && vec_column_enabled(i, PARTS)) out[k++] = i;
  return out;
}
}  // namespace contact_kernel

/// Evaluate one contact. `active` is the history flag (true if the pair was in contact at the
/// previous step); on return it says whether it is in contact now. Returns false when there is
/// no overlap. For WALL, rho points to the foot of the perpendicular from x_p onto the plane,
/// s_n = 0, v_n = w_n = 0 and mu = m_p. v/w are the predicted velocities and spins at t_{n+1};
/// v_half/w_half the half-step ones (history increments, transport). `hist` is the pair's row in
/// its history container (unused if the parts keep none).
template <unsigned PARTS, bool WALL>
inline bool contact_pair(const ContactCoeffs& c, const Vec3& rho, double sp, double sn,
                         double mu, const Vec3& vp, const Vec3& vn, const Vec3& wp,
                         const Vec3& wn, const Vec3& vp_half, const Vec3& vn_half,
                         const Vec3& wp_half, const Vec3& wn_half, double h, bool& active,
                         HistRow hist, PairResult& out) {
  using N = contact_kernel::NormalLaw<PARTS>;
  constexpr bool HIST = TableInfo::has_history(PARTS);
  const double d2 = rho.squaredNorm();
  const double reach = sp + sn;
  if (d2 >= reach * reach) {
    // a contact that ends takes the energy left in its history springs (tangential, rolling,
    // twisting) with it: counted as dissipated (the springs' energy at x = 0)
    if constexpr (HIST) {
      if (active)
        out.diss = contact_kernel::energy<PARTS, N>(ContactTable{}, c, EnergyCtx{0.0, WALL ? sp : sp * sn / reach, WALL},
                                                    hist);
    }
    active = false;
    return false;
  }
  PairCtx k;
  k.d2 = d2;
  k.d = std::sqrt(d2);
  k.x = reach - k.d;
  k.n = rho / k.d;
  k.mu = mu;
  k.h = h;
  k.wp = &wp;
  k.wn = &wn;
  k.wp_half = &wp_half;
  k.wn_half = &wn_half;
  const Vec3& n = k.n;
  if constexpr (WALL) {
    k.lp = k.d;
    k.ln = 0.0;
    k.Rbar = sp;
  } else {
    k.lp = (sp * sp - sn * sn + d2) / (2.0 * k.d);
    k.ln = k.d - k.lp;
    k.Rbar = sp * sn / reach;
  }
  if constexpr (WALL)
    k.u = -vp - k.lp * wp.cross(n);
  else
    k.u = vn - vp - k.ln * wn.cross(n) - k.lp * wp.cross(n);
  k.un_s = k.u.dot(n);
  if constexpr (HIST) {
    if constexpr (WALL)
      k.uh = -vp_half - k.lp * wp_half.cross(n);
    else
      k.uh = vn_half - vp_half - k.ln * wn_half.cross(n) - k.lp * wp_half.cross(n);
  } else {
    k.uh.setZero();
  }
  contact_kernel::normal_phase<PARTS, WALL, N>(ContactTable{}, c, k, hist);
  k.FNmag = k.FN.norm();
  k.F = k.FN;
  k.Tp.setZero();
  k.Tn.setZero();

  if constexpr (HIST) {
    const HistCols& cols = *hist.c;
    const std::size_t r = hist.row;
    Vec3& no = cols.v[0][r];
    constexpr auto tcols = contact_kernel::transported_columns<PARTS>();
    if (!active) {
      no = n;
      for (int i = 1; i < kHistVec; ++i)
        if (vec_column_enabled(i, PARTS)) cols.v[i][r].setZero();
      for (int i = 0; i < kHistScal; ++i)
        if (scal_column_enabled(i, PARTS)) cols.q[i][r] = 0.0;
    } else if constexpr (tcols.size() > 0) {
      // Transport the tangent-plane history with the contact frame.
      Vec3 wsum;
      if constexpr (WALL)
        wsum = wp_half;
      else
        wsum = wp_half + wn_half;
      const FrameTransport tr(no, n, wsum, h);
      for (int i : tcols) cols.v[i][r] = tr(cols.v[i][r]);
      no = n;
    }
  }
  active = true;
  contact_kernel::tangent_phase<PARTS, WALL, N>(ContactTable{}, c, k, hist);
  out.F = k.F;
  out.Tp = k.Tp;
  out.Tn = k.Tn;
  out.overlap = k.x;
  out.diss = k.diss;
  return true;
}

/// Elastic energy stored in one contact of overlap x and reduced radius Rbar: the sum of the
/// enabled parts' energies (normal law first, table order).
template <unsigned PARTS>
inline double contact_elastic_energy(const ContactCoeffs& c, double x, double Rbar, HistRow hist,
                                     bool wall = false) {
  return contact_kernel::energy<PARTS, contact_kernel::NormalLaw<PARTS>>(ContactTable{}, c,
                                                                         EnergyCtx{x, Rbar, wall}, hist);
}
/// The same for a run-time set of parts.
inline double contact_elastic_energy(const ContactCoeffs& c, unsigned parts, double x, double Rbar,
                                     HistRow hist, bool wall = false) {
  return dispatch_parts(parts, [&](auto P) {
    return contact_elastic_energy<decltype(P)::value>(c, x, Rbar, hist, wall);
  });
}

}  // namespace ssdem
