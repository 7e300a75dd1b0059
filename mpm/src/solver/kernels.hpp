/// @file kernels.hpp
/// Private to the solver (mpm/src/solver/): the constants of the step schedule and the small
/// per-particle kernels that several stages share, written once here as inline functions:
/// the particle stencil (uGIMP/linear weights on the three axes and the first node), the
/// PIC/FLIP velocity blend, the stress power sigma : L, and a particle's conserved totals.
///
///   stencil:      S_ip = S(x_p - x_i) S(y_p - y_i) S(z_p - z_i) (shape_functions.hpp), node
///                 (a,b,c) of the stencil at linear index base + a + sx (b + sy c)
///   FLIP blend:   v_p <- alpha (v_p + sum_i S_ip (v*_i - v_i)) + (1 - alpha) sum_i S_ip v*_i
///                 (alpha = FLIP fraction; mpm.md §1.2, Uintah explicit step)
///   stress power: w = sigma : L = s_xx L_xx + s_yy L_yy + s_zz L_zz + s_yz (L_yz + L_zy)
///                     + s_xz (L_xz + L_zx) + s_xy (L_xy + L_yx)   (sigma symmetric, Voigt)
///   totals:       m, m v, m x × v (about the origin), m |v|^2 / 2, m e
///
/// Every kernel keeps the exact operation order of the code it replaced, so results are
/// bit-identical to the single-file solver.
#pragma once
#include <Eigen/Geometry>

#include <cstddef>

#include "mpm/particles.hpp"
#include "mpm/shape_functions.hpp"
#include "mpm/solver.hpp"

namespace mpmfrag::detail {

inline constexpr int kBlock = 4;                // cells per block edge (>= 2 needed for 3-node stencils)
inline constexpr std::size_t kChunk = 256;      // particles per material batch
inline constexpr std::size_t kReduceChunk = 4096;  // particles per chunk of a deterministic sum

/// What a P2G pass accumulates (template argument MODE of Solver::scatter, OR-ed).
/// The same bits name the fields of GridExchange::sum_shared (solver.hpp).
enum P2G : int { kMass = 1, kMom = 2, kForce = 4 };
/// What a G2P pass updates (template argument flags of Solver::g2p, OR-ed): particle velocity
/// (FLIP blend), position, velocity gradient L (then F, volume and the material update).
enum G2P : int { kVel = 1, kPos = 2, kGrad = 4 };

/// Stencil of one particle: per-axis weights and the linear index of its first node.
struct Stencil {
  AxisWeights X, Y, Z;
  std::size_t base;  ///< node index of stencil node (0,0,0)
  /// Offset of the node row (b, c) (nodes a = 0..NPA-1 follow contiguously).
  std::size_t row(int sx, int sy, int b, int c) const {
    return base + static_cast<std::size_t>(sx) * (b + static_cast<std::size_t>(sy) * c);
  }
};

/// Stencil of the particle at x[0..2] with half-widths lp[0..2] on a grid with origin o, cell
/// size h and sx x sy nodes per z-layer (no bounds check: bin() has checked every particle).
/// A subdomain (Solver::shift_): the box's sx x sy layers, base minus the global linear index of
/// the box's node 0 (modular size_t arithmetic: exact for every node inside the box).
[[gnu::always_inline]] inline Stencil particle_stencil(ShapeKind kind, const double* x, const double* lp,
                                                       const Eigen::Vector3d& o, const Eigen::Vector3d& h,
                                                       int sx, int sy, std::size_t shift = 0) {
  Stencil s;
  s.X = axis_weights(kind, x[0], o[0], h[0], lp[0]);
  s.Y = axis_weights(kind, x[1], o[1], h[1], lp[1]);
  s.Z = axis_weights(kind, x[2], o[2], h[2], lp[2]);
  s.base = static_cast<std::size_t>(s.X.first) +
           static_cast<std::size_t>(sx) * (s.Y.first + static_cast<std::size_t>(sy) * s.Z.first) - shift;
  return s;
}

/// PIC/FLIP blend of the particle velocity vp[0..2]: vs = sum S v* (updated grid velocity at the
/// particle), vo = sum S v (grid velocity before the update), alpha = FLIP fraction.
[[gnu::always_inline]] inline void flip_blend(double* vp, double alpha, double vs0, double vs1, double vs2,
                                              double vo0, double vo1, double vo2) {
  vp[0] = alpha * (vp[0] + vs0 - vo0) + (1.0 - alpha) * vs0;
  vp[1] = alpha * (vp[1] + vs1 - vo1) + (1.0 - alpha) * vs1;
  vp[2] = alpha * (vp[2] + vs2 - vo2) + (1.0 - alpha) * vs2;
}

/// Stress power sigma : L per unit volume [W/m^3] of Voigt stress s (xx,yy,zz,yz,xz,xy) and
/// row-major velocity gradient l.
[[gnu::always_inline]] inline double stress_power(const double* s, const double* l) {
  return s[0] * l[0] + s[1] * l[4] + s[2] * l[8] + s[3] * (l[5] + l[7]) + s[4] * (l[2] + l[6]) + s[5] * (l[1] + l[3]);
}

/// Pointer to state array f of `slot` at global particle index `first` (inside the slot's range).
inline double* state_pointer(const MaterialSlot& slot, std::size_t f, std::size_t first) {
  return const_cast<double*>(slot.state[f].data()) + static_cast<std::size_t>(slot.style->state_fields[f].ncomp) * (first - slot.begin);
}

/// Add particle p's mass, momentum, angular momentum (about the origin), kinetic and internal
/// energy to d (Solver::diagnostics and the outflow record).
inline void add_particle_totals(Diagnostics& d, const ParticleSet& ps, std::size_t p) {
  const double m = ps.mass[p];
  const Eigen::Vector3d x(ps.x[3 * p], ps.x[3 * p + 1], ps.x[3 * p + 2]);
  const Eigen::Vector3d v(ps.v[3 * p], ps.v[3 * p + 1], ps.v[3 * p + 2]);
  d.mass += m;
  d.momentum += m * v;
  d.angular_momentum += m * x.cross(v);
  d.kinetic += 0.5 * m * v.squaredNorm();
  d.internal += m * ps.energy[p];
  d.work_dev += m * ps.work_dev[p];
  d.heat_shock += m * ps.heat_shock[p];
  d.heat_transfer += m * ps.heat_transfer[p];
}

}  // namespace mpmfrag::detail
