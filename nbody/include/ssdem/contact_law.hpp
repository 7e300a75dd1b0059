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
/// history): their discretisation error (the onset/release error, "Contact edges", the Mindlin
/// stiffness change) shows in that error rather than being hidden in D.
/// Contact edges (contact.resolve_edges, default on; a deviation from pkdgrav for accuracy). A
/// contact starts and ends inside a step, but the kick of step n (window [t_n - h/2, t_n + h/2])
/// takes the force at x_n as if it acted over the whole window. For the normal dashpot, whose
/// force jumps to C_n u_n at touch, that makes e_n's error first order in h (0.55 at 50.5 steps
/// per contact: 6.7e-3; at integer step counts the onset and release errors cancel). The kernel
/// adds at each edge the missing impulse of the exact (linear-in-time) overlap x = w t:
///   onset (x_n > 0, not in contact at the previous evaluation): approach speed w = -u.n,
///     time since touch s = min(x_n / w, h) (s = h when w = 0); the kick owes the impulse over
///     [t_n - s, t_n + h/2] (the previous kick saw no contact), sig = s;
///   release (x_n <= 0, in contact at the previous evaluation): separation speed w = u.n, time
///     since separation q = min(-x_n / w, h); the previous kick took [t_{n-1} - h/2, t_{n-1} + h/2]
///     but the contact lasted until t_{n-1} + sig, sig = h - q, so this kick owes the difference;
/// in both cases the edge force (over h) is the integral of the law over the edge interval minus
/// what the midpoint took: for F = K x^a, K w^a [(sig + h/2)^{a+1}/(a+1) - sig^a h]/h, and the
/// same for the dashpot C_0 x^p u_n (the laws' edge_spring / edge_dashpot). Linear law: spring
/// k_n w (sig - h/2)^2/(2h), dashpot C_n u_n (sig/h - 1/2): the impulses of a contact are then
/// exact for a linear approach and release, and the e_n error is second order (measured in
/// tests/nbody/test_contact_edges.cpp).
/// No edge force where the linear history does not apply: a pair not approaching at its onset or
/// not separating at its release (w <= 0), the first evaluation of a run (its overlaps are not
/// onsets: ContactSystem::set_edges), and a multi-rate pair evaluated with one member only
/// (ContactSystem::Subset::whole: the force would reach one sphere). Multi-rate: the owed impulse
/// is divided by the pair's step h; if a member changes level at that very step, its kick window
/// is (h + h')/2 and the edge impulse arrives scaled by (h + h')/(2h) (between 0.75 and 1.5 for
/// one level): the correction is then approximate, still of second order.
/// The edge force acts along n (no torque); its dashpot part counts as dissipated (cd u_n^2 h,
/// negative when it returns an earlier kick's excess). A released pair's edge force is its record
/// for this step (pair_batch.hpp). The tangential spring and dashpot and the cohesion part keep
/// their first-order edges, and the friction limits (mu |F_N|) take the step's F_N without the
/// edge force, consistently with them: with the limit raised by the edge force while the
/// tangential spring is not, the energy balance of a settling heap stopped converging
/// (error/D -4.6e-4, -3.0e-4, -1.8e-4 at 40, 80, 160 steps per contact; with the step's F_N
/// 2.1e-4, 9.4e-5 at 40, 80, as without edges: test_nbody_energy_balance).
/// Per-pair step: h is an argument of the kernel (multi-rate: each pair its own level's step).
/// Lanes. The kernel is written once in lane arithmetic (contact/lanes.hpp): contact_lanes<R>
/// evaluates one pair (R = double; contact_pair() is its Eigen-facing wrapper, used for walls and
/// tests) or a pack of kLanes pairs (R = Lanes; ContactSystem's pair loop, pair_batch.hpp), whose
/// history is gathered from and scattered back to the structure-of-arrays columns. Branches are
/// masks: a lane not in contact computes and discards, a lane whose contact starts has its
/// history reset by select. Each lane performs exactly the operations of the one-pair kernel in
/// the same order, so results do not depend on the lane count (tested bit for bit).
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
  bool edges;  ///< resolve the contact edges within the step (contact.resolve_edges)
  explicit ContactCoeffs(const ContactParams& p) : TableInfo::Coeffs(p), beta(p.beta), edges(p.resolve_edges) {}
};

/// Result of one pair evaluation (the Eigen-facing wrapper).
struct PairResult {
  Vec3 F = Vec3::Zero();   ///< force on p (n receives -F)
  Vec3 Tp = Vec3::Zero();  ///< torque on p
  Vec3 Tn = Vec3::Zero();  ///< torque on n
  double overlap = 0.0;
  double diss = 0.0;       ///< energy dissipated over the step [J]
};

/// A pair's (or a pack's) history while the kernel works on it.
template <class R>
using HistOf = HistLocal<R, kHistVec, kHistScal>;

/// Inputs of the kernel: rho = x_n - x_p, radii, reduced mass, step; predicted velocities and
/// spins (t_{n+1}) and the half-step ones (history increments, transport).
template <class R>
struct PairIn {
  V3<R> rho;
  R sp, sn, mu, h;
  V3<R> vp, vn, wp, wn, vp_half, vn_half, wp_half, wn_half;
  R edge = splat<R>(1.0);  ///< 0: no edge force for this pair now (a multi-rate pair with one member)
};
/// Outputs: force on p, torques, overlap (meaningful in lanes in contact only: a pack's other
/// lanes hold whatever they computed, except a released lane with edges on, whose F is its edge
/// force and Tp = Tn = 0) and the energy dissipated over the step (every lane: in contact, the
/// parts'; released, the energy its history springs held plus its edge dashpot's; else 0).
template <class R>
struct PairOut {
  V3<R> F, Tp, Tn;
  R overlap, diss;
};

namespace contact_kernel {
/// The normal law of a set of parts.
template <unsigned PARTS>
using NormalLaw = std::conditional_t<(PARTS & kPartHertz) != 0u, HertzNormal, LinearNormal>;

template <class Part, class R>
using View = HistView<HistOf<R>, TableInfo::vec_base<Part>(), TableInfo::scal_base<Part>()>;

template <unsigned PARTS, bool WALL, class N, class R, class... P>
[[gnu::always_inline]] inline void normal_phase(PartList<P...>, const ContactCoeffs& c, PairCtx<R>& k, HistOf<R>& h) {
  ((TableInfo::enabled<P>(PARTS) ? P::template normal_phase<PARTS, WALL, N>(c, k, View<P, R>{&h}) : void()), ...);
}
template <unsigned PARTS, bool WALL, class N, class R, class... P>
[[gnu::always_inline]] inline void tangent_phase(PartList<P...>, const ContactCoeffs& c, PairCtx<R>& k, HistOf<R>& h) {
  ((TableInfo::enabled<P>(PARTS) ? P::template tangent_phase<PARTS, WALL, N>(c, k, View<P, R>{&h}) : void()), ...);
}
template <unsigned PARTS, class N, class R, class... P>
[[gnu::always_inline]] inline R energy(PartList<P...>, const ContactCoeffs& c, const EnergyCtx<R>& e, HistOf<R>& h) {
  R s = splat<R>(0.0);
  bool first = true;
  auto add = [&](const R& x) {
    s = first ? x : s + x;
    first = false;
  };
  ((TableInfo::enabled<P>(PARTS) ? add(P::template energy<N>(c, e, View<P, R>{&h})) : void()), ...);
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
/// The edge force of the lanes in `onset` (in contact now, not at the previous evaluation) and
/// of the released ones (the others): see "Contact edges" in the file comment. F: force on p;
/// diss: the edge dashpot's energy over the step.
template <unsigned PARTS, class N, class C, class R, class M>
[[gnu::always_inline]] inline void edge_force(const C& c, const PairCtx<R>& k, const M& onset, V3<R>& F, R& diss) {
  const R w0 = select(onset, -k.un_s, k.un_s);  // approach / separation speed
  const auto moving = w0 > 0.0;                   // else no linear history to go by: no edge force
  const R w = select(moving, w0, splat<R>(1.0));
  const R tau0 = select(onset, k.x, -k.x);        // overlap / gap
  const R tau = select(tau0 < 0.0, splat<R>(0.0), tau0);
  const R s = lmin(tau / w, k.h);                 // time since the edge
  const R sig = select(onset, s, k.h - s);
  F = (-N::edge_spring(c, k, w, sig)) * k.n;
  diss = splat<R>(0.0);
  if constexpr ((PARTS & kPartDamping) != 0u) {
    const R cd = N::edge_dashpot(c, k, w, sig);
    F = F + (cd * k.un_s) * k.n;
    diss = cd * k.un_s * k.un_s * k.h;
  }
  F = select(moving, F, V3<R>::zero());
  diss = select(moving, diss, splat<R>(0.0));
}
}  // namespace contact_kernel

/// Lane l of a history (enabled columns of PARTS) from / to row `row` of a container.
template <unsigned PARTS, class R>
[[gnu::always_inline]] inline void load_hist(const HistCols& cols, std::size_t row, HistOf<R>& h, int l) {
  for (int i = 0; i < kHistVec; ++i)
    if (vec_column_enabled(i, PARTS)) h.v[i].set(l, cols.v[i][row]);
  for (int i = 0; i < kHistScal; ++i)
    if (scal_column_enabled(i, PARTS)) set_lane(h.q[i], l, cols.q[i][row]);
}
template <unsigned PARTS, class R>
[[gnu::always_inline]] inline void store_hist(const HistCols& cols, std::size_t row, const HistOf<R>& h, int l) {
  for (int i = 0; i < kHistVec; ++i)
    if (vec_column_enabled(i, PARTS)) cols.v[i][row] = h.v[i].at(l);
  for (int i = 0; i < kHistScal; ++i)
    if (scal_column_enabled(i, PARTS)) cols.q[i][row] = lane(h.q[i], l);
}

/// Evaluate one contact or a pack (lanes.hpp). `active` is the history flag (in contact at the
/// previous step); returns whether each lane is in contact now (its new flag). For WALL, rho
/// points to the foot of the perpendicular from x_p onto the plane, s_n = 0, v_n = w_n = 0 and
/// mu = m_p. `hist` holds the lanes' history (unused if the parts keep none); lanes not in
/// contact must not be stored back (their history is left as it was).
/// Lanes released now: in contact at the previous evaluation, not now.
template <class M>
[[gnu::always_inline]] inline M rel_of(const M& active, const M& contact) {
  return mand(active, mnot(contact));
}

template <unsigned PARTS, bool WALL, class R>
[[gnu::always_inline]] inline MaskOf<R> contact_lanes(const ContactCoeffs& c, const PairIn<R>& in,
                                                      const MaskOf<R>& active, HistOf<R>& hist,
                                                      PairOut<R>& out) {
  using N = contact_kernel::NormalLaw<PARTS>;
  constexpr bool HIST = TableInfo::has_history(PARTS);
  const R d2 = in.rho.squaredNorm();
  const R reach = in.sp + in.sn;
  const auto contact = mnot(d2 >= reach * reach);
  out.F = out.Tp = out.Tn = V3<R>::zero();
  out.overlap = out.diss = splat<R>(0.0);
  R Rbar;
  if constexpr (WALL)
    Rbar = in.sp;
  else
    Rbar = in.sp * in.sn / reach;
  if constexpr (HIST) {
    // a contact that ends takes the energy left in its history springs (tangential, rolling,
    // twisting) with it: counted as dissipated (the springs' energy at x = 0)
    const auto rel = rel_of(active, contact);
    if (any(rel))
      out.diss = select(rel, contact_kernel::energy<PARTS, N>(ContactTable{}, c, EnergyCtx<R>{splat<R>(0.0), Rbar, WALL}, hist),
                        out.diss);
  }
  const auto eok = in.edge > 0.0;  // edges wanted for this pair (and on: c.edges)
  const auto onset = mand(mand(contact, mnot(active)), eok);
  const auto released = mand(rel_of(active, contact), eok);
  const bool edges = c.edges && (any(onset) || any(released));
  if (none(contact) && !edges) return contact;
  PairCtx<R> k;
  k.d2 = d2;
  k.d = lsqrt(d2);
  k.x = reach - k.d;
  k.n = in.rho / k.d;
  k.mu = in.mu;
  k.h = in.h;
  k.wp = &in.wp;
  k.wn = &in.wn;
  k.wp_half = &in.wp_half;
  k.wn_half = &in.wn_half;
  k.Rbar = Rbar;
  const V3<R>& n = k.n;
  if constexpr (WALL) {
    k.lp = k.d;
    k.ln = splat<R>(0.0);
    k.u = -in.vp - k.lp * in.wp.cross(n);
  } else {
    k.lp = (in.sp * in.sp - in.sn * in.sn + d2) / (2.0 * k.d);
    k.ln = k.d - k.lp;
    k.u = in.vn - in.vp - k.ln * in.wn.cross(n) - k.lp * in.wp.cross(n);
  }
  k.un_s = k.u.dot(n);
  if constexpr (HIST) {
    if constexpr (WALL)
      k.uh = -in.vp_half - k.lp * in.wp_half.cross(n);
    else
      k.uh = in.vn_half - in.vp_half - k.ln * in.wn_half.cross(n) - k.lp * in.wp_half.cross(n);
  } else {
    k.uh = V3<R>::zero();
  }
  V3<R> Fedge = V3<R>::zero();
  R dedge = splat<R>(0.0);
  if (edges) contact_kernel::edge_force<PARTS, N>(c, k, onset, Fedge, dedge);
  if (none(contact)) {  // released lanes (edges on): the edge force, no torque
    out.F = Fedge;
    out.diss = select(released, out.diss + dedge, out.diss);
    return contact;
  }
  contact_kernel::normal_phase<PARTS, WALL, N>(ContactTable{}, c, k, hist);
  k.FNmag = lsqrt(k.FN.squaredNorm());
  if (edges) {  // after |F_N|: the friction limits see the step's normal force (see the file comment)
    k.FN = select(onset, k.FN + Fedge, k.FN);
    k.diss = select(onset, k.diss + dedge, k.diss);
  }
  k.F = k.FN;
  k.Tp = k.Tn = V3<R>::zero();

  if constexpr (HIST) {
    // a contact that starts has its history reset (n_old = n, all fields 0); one that goes on
    // has its tangent-plane fields transported with the contact frame
    V3<R>& no = hist.v[0];
    constexpr auto tcols = contact_kernel::transported_columns<PARTS>();
    const V3<R> z = V3<R>::zero();
    if constexpr (tcols.size() > 0) {
      if (any(active)) {
        V3<R> wsum;
        if constexpr (WALL)
          wsum = in.wp_half;
        else
          wsum = in.wp_half + in.wn_half;
        const FrameTransportT<R> tr(no, n, wsum, in.h);
        for (int i : tcols) hist.v[i] = select(active, tr(hist.v[i]), z);
      } else {
        for (int i : tcols) hist.v[i] = z;
      }
      no = n;
    } else {
      no = select(active, no, n);
    }
    for (int i = 1; i < kHistVec; ++i)
      if (vec_column_enabled(i, PARTS) && !kHistVecFields[i].transported) hist.v[i] = select(active, hist.v[i], z);
    for (int i = 0; i < kHistScal; ++i)
      if (scal_column_enabled(i, PARTS)) hist.q[i] = select(active, hist.q[i], splat<R>(0.0));
  }
  contact_kernel::tangent_phase<PARTS, WALL, N>(ContactTable{}, c, k, hist);
  out.F = k.F;
  out.Tp = k.Tp;
  out.Tn = k.Tn;
  out.overlap = k.x;
  if (edges) {
    out.F = select(released, Fedge, out.F);
    out.Tp = select(released, V3<R>::zero(), out.Tp);
    out.Tn = select(released, V3<R>::zero(), out.Tn);
    out.diss = select(released, out.diss + dedge, out.diss);
  }
  out.diss = select(contact, k.diss, out.diss);
  return contact;
}

/// One contact with Eigen vectors and its row in a history container: contact_lanes<double>.
/// Returns false when there is no overlap; `active` is updated (see contact_lanes).
template <unsigned PARTS, bool WALL>
inline bool contact_pair(const ContactCoeffs& c, const Vec3& rho, double sp, double sn,
                         double mu, const Vec3& vp, const Vec3& vn, const Vec3& wp,
                         const Vec3& wn, const Vec3& vp_half, const Vec3& vn_half,
                         const Vec3& wp_half, const Vec3& wn_half, double h, bool& active,
                         HistRow hist, PairResult& out) {
  constexpr bool HIST = TableInfo::has_history(PARTS);
  const PairIn<double> in{rho, sp, sn, mu, h, vp, vn, wp, wn, vp_half, vn_half, wp_half, wn_half};
  HistOf<double> hl;
  if constexpr (HIST) load_hist<PARTS>(*hist.c, hist.row, hl, 0);
  PairOut<double> o;
  const bool con = contact_lanes<PARTS, WALL>(c, in, active, hl, o);
  if constexpr (HIST)
    if (con) store_hist<PARTS>(*hist.c, hist.row, hl, 0);
  active = con;
  out.F = o.F.eigen();
  out.Tp = o.Tp.eigen();
  out.Tn = o.Tn.eigen();
  out.overlap = o.overlap;
  out.diss = o.diss;
  return con;
}

/// Elastic energy stored in one contact of overlap x and reduced radius Rbar: the sum of the
/// enabled parts' energies (normal law first, table order).
template <unsigned PARTS>
inline double contact_elastic_energy(const ContactCoeffs& c, double x, double Rbar, HistRow hist,
                                     bool wall = false) {
  HistOf<double> hl;
  if constexpr (TableInfo::has_history(PARTS)) load_hist<PARTS>(*hist.c, hist.row, hl, 0);
  return contact_kernel::energy<PARTS, contact_kernel::NormalLaw<PARTS>>(ContactTable{}, c,
                                                                         EnergyCtx<double>{x, Rbar, wall}, hl);
}
/// The same for a run-time set of parts.
inline double contact_elastic_energy(const ContactCoeffs& c, unsigned parts, double x, double Rbar,
                                     HistRow hist, bool wall = false) {
  return dispatch_parts(parts, [&](auto P) {
    return contact_elastic_energy<decltype(P)::value>(c, x, Rbar, hist, wall);
  });
}

}  // namespace ssdem
