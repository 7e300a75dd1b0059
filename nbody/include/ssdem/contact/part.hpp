/// @file part.hpp
/// What every contact sub-model (a "part") of the soft-sphere law shares: the per-pair working
/// context the pair kernel fills in (geometry, kinematics, stiffness, normal force, result), the
/// declaration of a history field, and the view of a pair's (or a pack's) history.
///
/// A part is a struct with (see normal_linear.hpp for the smallest one):
///   name, flag (its bit in ContactParams::parts; 0 = the default of its slot), slot, help
///   Params  (its resolved parameters, SI; composed into ContactParams by the table)
///   Coeffs  (constants precomputed once from the params; composed into ContactCoeffs)
///   declare(Schema&)  its keys, relative to `contact.<name>.`
///   read(Scene, prefix, ContactParams&)
///   history  (array of HistoryField: the per-contact state it keeps; may be empty)
///   normal_phase<PARTS, WALL, N>(coeffs, ctx, hist)  force terms along the normal (before the
///                     Coulomb/rolling/twisting limits, which use |F_N| of this phase)
///   tangent_phase<PARTS, WALL, N>(coeffs, ctx, hist) everything else (after the history has
///                     been transported with the contact frame)
///   energy<N>(coeffs, ectx, hist)  elastic energy it stores in one contact [J]
/// N is the normal law chosen for the kernel (stiffness and dashpot coefficients depend on it).
/// The phases are written once in lane arithmetic (lanes.hpp) on PairCtx<R>: R = double is one
/// pair, R = Lanes a pack of pairs evaluated together; branches are masks (select), so that each
/// lane does exactly what the one-pair kernel does.
/// The table (table.hpp) lists the parts; the kernel (contact_law.hpp) calls the phases in table
/// order. Equations and sources are in each part's header.
#pragma once
#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <cstddef>
#include <string>

#include "common/schema.hpp"
#include "ssdem/contact/frame_transport.hpp"
#include "ssdem/contact/lanes.hpp"
#include "ssdem/spheres.hpp"

namespace ssdem {

/// Slots: the normal law is one of several alternatives (exactly one per kernel).
enum class PartSlot { normal, additive };

/// One field of per-contact history.
struct HistoryField {
  const char* name;   ///< dataset name in checkpoints (/ssdem_state/history/<name>)
  const char* unit;   ///< SI unit
  int width;          ///< 3 (vector, stored as Vec3) or 1 (scalar)
  bool transported;   ///< rotated with the contact frame each step (tangent-plane vectors)
  bool flips;         ///< changes sign when the pair's members are swapped
};

/// The frame history every kernel with history keeps: the normal at the previous step.
inline constexpr HistoryField kNormalOldField{"n_old", "1", 3, false, true};

/// Column pointers of a history container (structure of arrays), refreshed when it is resized.
/// Vector column 0 is n_old; the parts' columns follow in table order (table.hpp).
template <std::size_t NV, std::size_t NQ>
struct HistoryCols {
  std::array<Vec3*, NV> v{};
  std::array<double*, NQ> q{};
};

/// One pair's (or one pack's) history, loaded from its container's row(s) by the kernel and
/// stored back after it: vector column 0 is n_old, the parts' columns follow in table order.
template <class R, std::size_t NV, std::size_t NQ>
struct HistLocal {
  std::array<V3<R>, NV> v;
  std::array<R, NQ> q;
};

/// The history as seen by a part whose first vector/scalar column is VB/QB.
template <class L, int VB, int QB>
struct HistView {
  L* h;
  auto& vec(int k) const { return h->v[VB + k]; }
  auto& scal(int k) const { return h->q[QB + k]; }
  auto& n_old() const { return h->v[0]; }
};

/// Per-pair working state of the kernel (R: one pair or a pack, lanes.hpp). Written by the
/// kernel (geometry, kinematics), the normal law (kn, kt), the damping part (cn, ct); read by the
/// others.
template <class R>
struct PairCtx {
  V3<R> n;           ///< unit normal from p to n
  R x;               ///< overlap [m]
  R d, d2;           ///< centre distance and its square
  R lp, ln;          ///< lever arms [m]
  R Rbar;            ///< reduced radius [m]
  R mu;              ///< reduced mass [kg]
  R h;               ///< step [s]
  V3<R> u;           ///< contact-point velocity of n relative to p (predicted)
  V3<R> uh;          ///< the same with half-step velocities (history increments)
  R un_s;            ///< u . n
  const V3<R> *wp, *wn, *wp_half, *wn_half;  ///< spins (wall: zero)
  R kn{};              ///< normal stiffness dF/dx (linear: k_n; Hertz: tangent stiffness) [N/m]
  R kt{};              ///< tangential stiffness [N/m]
  R cn{};              ///< normal dashpot coefficient [kg/s] (damping part; else 0)
  R ct{};              ///< tangential dashpot coefficient [kg/s] (damping + tangential; else 0)
  V3<R> FN;          ///< normal force of the normal phase
  R FNmag{};           ///< |FN|, the reference of the friction limits
  V3<R> F, Tp, Tn;   ///< results: force on p, torques on p and n
  R diss{};            ///< energy dissipated over the step h [J] (contact_law.hpp, "Dissipation")
};

/// Relative spin of n with respect to p, predicted (dw) and half-step (dwh); a wall does not spin.
template <bool WALL, class R>
[[gnu::always_inline]] inline void relative_spins(const PairCtx<R>& k, V3<R>& dw, V3<R>& dwh) {
  if constexpr (WALL) {
    dw = -*k.wp;
    dwh = -*k.wp_half;
  } else {
    dw = *k.wn - *k.wp;
    dwh = *k.wn_half - *k.wp_half;
  }
}

/// What the energy of one contact needs (no velocities).
template <class R>
struct EnergyCtx {
  R x;     ///< overlap [m]
  R Rbar;  ///< reduced radius [m]
  bool wall = false;  ///< a sphere-wall contact
};

/// Defaults for the hooks a part does not need.
struct PartBase {
  static constexpr std::array<HistoryField, 0> history{};
  template <unsigned PARTS, bool WALL, class N, class C, class K, class H>
  static void normal_phase(const C&, K&, const H&) {}
  template <unsigned PARTS, bool WALL, class N, class C, class K, class H>
  static void tangent_phase(const C&, K&, const H&) {}
  template <class N, class C, class R, class H>
  static R energy(const C&, const EnergyCtx<R>&, const H&) { return splat<R>(0.0); }
  struct Params {};
  struct Coeffs {
    template <class P> explicit Coeffs(const P&) {}
  };
};

}  // namespace ssdem
