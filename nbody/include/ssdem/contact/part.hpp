/// @file part.hpp
/// What every contact sub-model (a "part") of the soft-sphere law shares: the per-pair working
/// context the pair kernel fills in (geometry, kinematics, stiffness, normal force, result), the
/// declaration of a history field, and the view of one pair's history row.
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
///   energy<N>(coeffs, ectx, row)  elastic energy it stores in one contact [J]
/// N is the normal law chosen for the kernel (stiffness and dashpot coefficients depend on it).
/// The table (table.hpp) lists the parts; the kernel (contact_law.hpp) calls the phases in table
/// order. Equations and sources are in each part's header.
#pragma once
#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <cstddef>
#include <string>

#include "common/schema.hpp"
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

/// One pair's history row as seen by a part whose first vector/scalar column is VB/QB.
template <class Cols, int VB, int QB>
struct HistView {
  const Cols* c;
  std::size_t row;
  Vec3& vec(int k) const { return c->v[VB + k][row]; }
  double& scal(int k) const { return c->q[QB + k][row]; }
  Vec3& n_old() const { return c->v[0][row]; }
};

/// Per-pair working state of the kernel. Written by the kernel (geometry, kinematics), the
/// normal law (kn, kt), the damping part (cn, ct); read by the others.
struct PairCtx {
  Vec3 n;            ///< unit normal from p to n
  double x;          ///< overlap [m]
  double d, d2;      ///< centre distance and its square
  double lp, ln;     ///< lever arms [m]
  double Rbar;       ///< reduced radius [m]
  double mu;         ///< reduced mass [kg]
  double h;          ///< step [s]
  Vec3 u;            ///< contact-point velocity of n relative to p (predicted)
  Vec3 uh;           ///< the same with half-step velocities (history increments)
  double un_s;       ///< u . n
  const Vec3 *wp, *wn, *wp_half, *wn_half;  ///< spins (wall: zero)
  double kn = 0.0;   ///< normal stiffness dF/dx (linear: k_n; Hertz: tangent stiffness) [N/m]
  double kt = 0.0;   ///< tangential stiffness [N/m]
  double cn = 0.0;   ///< normal dashpot coefficient [kg/s] (damping part)
  double ct = 0.0;   ///< tangential dashpot coefficient [kg/s] (damping + tangential)
  Vec3 FN;           ///< normal force of the normal phase
  double FNmag = 0.0;///< |FN|, the reference of the friction limits
  Vec3 F, Tp, Tn;    ///< results: force on p, torques on p and n
  double diss = 0.0; ///< energy dissipated over the step h [J] (contact_law.hpp, "Dissipation")
};

/// Relative spin of n with respect to p, predicted (dw) and half-step (dwh); a wall does not spin.
template <bool WALL>
inline void relative_spins(const PairCtx& k, Vec3& dw, Vec3& dwh) {
  if constexpr (WALL) {
    dw = -*k.wp;
    dwh = -*k.wp_half;
  } else {
    dw = *k.wn - *k.wp;
    dwh = *k.wn_half - *k.wp_half;
  }
}

/// What the energy of one contact needs (no velocities).
struct EnergyCtx {
  double x;     ///< overlap [m]
  double Rbar;  ///< reduced radius [m]
  bool wall = false;  ///< a sphere-wall contact
};

/// Defaults for the hooks a part does not need.
struct PartBase {
  static constexpr std::array<HistoryField, 0> history{};
  template <unsigned PARTS, bool WALL, class N, class C, class H>
  static void normal_phase(const C&, PairCtx&, const H&) {}
  template <unsigned PARTS, bool WALL, class N, class C, class H>
  static void tangent_phase(const C&, PairCtx&, const H&) {}
  template <class N, class C, class H>
  static double energy(const C&, const EnergyCtx&, const H&) { return 0.0; }
  struct Params {};
  struct Coeffs {
    template <class P> explicit Coeffs(const P&) {}
  };
};

/// Rodrigues rotation of v about unit axis k by angle (cos c, sin s).
inline Vec3 rotate_about(const Vec3& v, const Vec3& k, double c, double s) {
  return v * c + k.cross(v) * s + k * (k.dot(v) * (1.0 - c));
}

/// Transport of tangent-plane history with a contact frame whose normal turned from n_old to n
/// over one step (Schwartz+2012 eqs 17-19; pkdgrav DoDEM): rotate about nbar = (n_old + n)/|.|
/// by (h/2) w_sum.nbar (w_sum: the sum of the two half-step spins; a wall: the sphere's), then by
/// the rotation taking n_old to n (assumes a turn below 90 degrees). Used by the contact kernel
/// and by the bonds.
struct FrameTransport {
  bool spin = false, tilt = false;
  Vec3 nbar, k;
  double ca = 1, sa = 0, cc = 1, sn = 0;
  FrameTransport(const Vec3& no, const Vec3& n, const Vec3& w_sum, double h) {
    Vec3 nb = no + n;
    const double l = nb.norm();
    if (l > 0.0) {
      nb /= l;
      const double ang = 0.5 * h * w_sum.dot(nb);
      if (ang != 0.0) {
        spin = true;
        nbar = nb;
        ca = std::cos(ang);
        sa = std::sin(ang);
      }
    }
    const Vec3 ax = no.cross(n);
    sn = ax.norm();
    if (sn > 1e-300) {
      tilt = true;
      k = ax / sn;
      cc = no.dot(n);
    }
  }
  Vec3 operator()(Vec3 v) const {
    if (spin) v = rotate_about(v, nbar, ca, sa);
    if (tilt) v = rotate_about(v, k, cc, sn);
    return v;
  }
};

}  // namespace ssdem
