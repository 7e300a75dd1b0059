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

/// cos and sin of x: Taylor polynomials (to x^10 and x^9) for |x| < 1/16, where the first omitted
/// term is below 3e-20 of the result (so they agree with libm to rounding); libm beyond. The
/// transport angle of a resolved contact is tiny; this saves a libm call per contact and step.
[[gnu::always_inline]] inline void small_sincos(double x, double& c, double& s) {
  if (std::abs(x) < 0.0625) {
    const double x2 = x * x;  // Horner in x^2 with the Taylor coefficients
    s = x + x * x2 * (-1.0 / 6 + x2 * (1.0 / 120 + x2 * (-1.0 / 5040 + x2 * (1.0 / 362880))));
    c = 1.0 + x2 * (-0.5 + x2 * (1.0 / 24 + x2 * (-1.0 / 720 + x2 * (1.0 / 40320 + x2 * (-1.0 / 3628800)))));
  } else {
    c = std::cos(x);
    s = std::sin(x);
  }
}

/// Transport of tangent-plane history with a contact frame whose normal turned from n_old to n
/// over one step (Schwartz+2012 eqs 17-19; pkdgrav DoDEM): rotate about nbar = (n_old + n)/|.|
/// by (h/2) w_sum.nbar (w_sum: the sum of the two half-step spins; a wall: the sphere's), then by
/// the rotation taking n_old to n. That second rotation, about a = n_old x n (|a| = sin, c =
/// n_old.n = cos), is Rodrigues' formula without normalising the axis:
///   R v = v + a x v + a x (a x v) / (1 + c)        (since (1 - c) / sin^2 = 1 / (1 + c)),
/// used for turns below 90 degrees (every resolved contact); larger turns use the normalised axis.
/// Used by the contact kernel and by the bonds.
struct FrameTransport {
  bool spin = false, tilt = false, wide = false;
  Vec3 nbar, a;
  double ca = 1, sa = 0, ic = 0;  // spin cos/sin; tilt: 1/(1 + c), or c for a wide turn
  [[gnu::always_inline]] FrameTransport(const Vec3& no, const Vec3& n, const Vec3& w_sum, double h) {
    const Vec3 nb = no + n;
    const double l = nb.norm();
    if (l > 0.0) {
      const double ang = 0.5 * h * w_sum.dot(nb) / l;
      if (ang != 0.0) {
        spin = true;
        nbar = nb / l;
        small_sincos(ang, ca, sa);
      }
    }
    a = no.cross(n);
    const double s2 = a.squaredNorm();
    if (s2 > 0.0) {
      tilt = true;
      const double c = no.dot(n);
      if (c > 0.0) {
        ic = 1.0 / (1.0 + c);
      } else {  // a turn of 90 degrees or more: normalised axis, Rodrigues with (c, sin)
        wide = true;
        ic = c;
      }
    }
  }
  [[gnu::always_inline]] Vec3 operator()(Vec3 v) const {
    if (spin) v = rotate_about(v, nbar, ca, sa);
    if (tilt) {
      if (!wide) {
        const Vec3 av = a.cross(v);
        v += av + a.cross(av) * ic;
      } else {
        const double sn = a.norm();
        v = rotate_about(v, a / sn, ic, sn);
      }
    }
    return v;
  }
};

}  // namespace ssdem
