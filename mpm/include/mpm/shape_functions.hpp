/// @file shape_functions.hpp
/// Grid interpolation weights for the Material Point Method: uGIMP (default) and classic linear.
///
/// Governing equations (Bardenhagen & Kober 2004, CMES 5(6):477, eqs. for the "GIMP" weight with
/// linear grid basis and a top-hat particle characteristic function; the six-branch form is the
/// Uintah User Guide's `gimp_shape`/`gimpGrad`, folded by symmetry; see
/// shared/reference/mpm.md §1.1). Per axis, with d = x_p - x_i, a = |d|, cell size h and
/// particle half-width l_p (0 < l_p <= h/2):
///
///   S(d) = 1 - (d^2 + l_p^2) / (2 h l_p)          for a < l_p
///        = 1 - a/h                                for l_p <= a <= h - l_p
///        = (h + l_p - a)^2 / (4 h l_p)            for h - l_p < a < h + l_p
///        = 0                                      otherwise
///   dS/dx_p = -d/(h l_p),  -sgn(d)/h,  -sgn(d)(h + l_p - a)/(2 h l_p),  0.
///
/// Classic linear MPM (Sulsky, Chen & Schreyer 1994): N(d) = 1 - a/h for a < h, dN/dx_p = -sgn(d)/h.
///
/// In 3D the weight is the tensor product S_ip = S(dx) S(dy) S(dz) and
/// grad S_ip = (S'(dx) S(dy) S(dz), S(dx) S'(dy) S(dz), S(dx) S(dy) S'(dz)).
/// "uGIMP" means that l_p keeps its initial (undeformed) value (Uintah's `gimp` interpolator).
///
/// Node selection (Uintah GIMPInterpolator): xi = (x - origin)/h, i = floor(xi), f = xi - i;
/// uGIMP uses nodes {i-1, i, i+1} if f <= 0.5 else {i, i+1, i+2} (3 per axis, 27 in 3D; weights
/// that fall outside the support are exactly zero); linear uses {i, i+1} (8 in 3D).
///
/// Usage without a solver (e.g. projecting particle data onto a grid):
/// @code
///   mpmfrag::ParticleStencil st = mpmfrag::compute_stencil(mpmfrag::ShapeKind::ugimp, grid, x, lp);
///   if (!mpmfrag::stencil_inside(grid, st)) { /* particle support leaves the grid */ }
///   mpmfrag::for_each_node(st, [&](int i, int j, int k, double w, const Eigen::Vector3d& g) {
///     node_mass[mpmfrag::node_index(grid, i, j, k)] += w * m_p;   // P2G
///   });
///   // or: for (const mpmfrag::StencilNode& n : mpmfrag::stencil_nodes(...)) ...
/// @endcode
/// Properties (unit-tested in tests/mpm/test_shape_functions.cpp): sum_i S_ip = 1,
/// sum_i S_ip x_i = x_p, sum_i grad S_ip = 0, and grad S equals the derivative of S.
#pragma once
#include <Eigen/Core>
#include <array>
#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

#include "common/branchless.hpp"
#include "common/choice.hpp"
#include "common/grid.hpp"

namespace mpmfrag {

/// Interpolation scheme.
enum class ShapeKind { linear, ugimp };
/// Scene spellings of ShapeKind (mpm-frag solver.shape, mpm2spheres shape).
inline constexpr std::array kShapeKinds{common::Choice{"ugimp", ShapeKind::ugimp},
                                        common::Choice{"linear", ShapeKind::linear}};

/// Parse a name of kShapeKinds (or the legacy "gimp" for ugimp); throws std::invalid_argument
/// otherwise.
ShapeKind parse_shape_kind(const std::string& name);
/// Inverse of parse_shape_kind.
const char* shape_kind_name(ShapeKind k);

/// uGIMP 1D weight for offset d = x_p - x_i, cell size h, half-width lp (lp <= h/2).
inline double ugimp_weight_1d(double d, double h, double lp) {
  const double a = std::fabs(d);
  if (a < lp) return 1.0 - (d * d + lp * lp) / (2.0 * h * lp);
  if (a <= h - lp) return 1.0 - a / h;
  if (a < h + lp) {
    const double t = h + lp - a;
    return t * t / (4.0 * h * lp);
  }
  return 0.0;
}

/// uGIMP 1D gradient dS/dx_p for offset d = x_p - x_i.
inline double ugimp_gradient_1d(double d, double h, double lp) {
  const double a = std::fabs(d);
  const double s = d < 0.0 ? -1.0 : 1.0;
  if (a < lp) return -d / (h * lp);
  if (a <= h - lp) return -s / h;
  if (a < h + lp) return -s * (h + lp - a) / (2.0 * h * lp);
  return 0.0;
}

/// Classic linear (tent) 1D weight for offset d = x_p - x_i.
inline double linear_weight_1d(double d, double h) {
  const double a = std::fabs(d);
  return a < h ? 1.0 - a / h : 0.0;
}

/// Classic linear 1D gradient dN/dx_p (the one-sided value -sgn(d)/h; 0 outside the support).
inline double linear_gradient_1d(double d, double h) {
  const double a = std::fabs(d);
  if (a >= h) return 0.0;
  return d < 0.0 ? 1.0 / h : -1.0 / h;
}

/// Weights of one particle along one axis: nodes first, first+1, ... first+n-1.
struct AxisWeights {
  int first = 0;                  ///< index of the first node of the stencil on this axis
  int n = 0;                      ///< number of nodes (2 linear, 3 uGIMP)
  std::array<double, 3> w{};      ///< weights (unused slots are 0)
  std::array<double, 3> dw{};     ///< d w / d x_p [1/m] (unused slots are 0)
};

/// Per-axis weights for a particle at `x` (m), on an axis with node 0 at `origin` and spacing
/// `h`; `lp` is the particle half-width (ignored for linear). Does not check the grid bounds.
[[gnu::always_inline]] inline AxisWeights axis_weights(ShapeKind kind, double x, double origin, double h, double lp) {
  AxisWeights a;
  const double xi = (x - origin) / h;
  const double fl = std::floor(xi);
  const int i = static_cast<int>(fl);
  if (kind == ShapeKind::linear) {
    a.first = i;
    a.n = 2;
    for (int s = 0; s < 2; ++s) {
      const double d = x - (origin + (i + s) * h);
      a.w[s] = linear_weight_1d(d, h);
      a.dw[s] = linear_gradient_1d(d, h);
    }
    return a;
  }
  const double f = xi - fl;
  a.first = f <= 0.5 ? i - 1 : i;
  a.n = 3;
  for (int s = 0; s < 3; ++s) {
    const double d = x - (origin + (a.first + s) * h);
    a.w[s] = ugimp_weight_1d(d, h, lp);
    a.dw[s] = ugimp_gradient_1d(d, h, lp);
  }
  return a;
}

/// Weights only (no gradients) of one particle along one axis: nodes first .. first+n-1.
struct AxisWeightsOnly {
  int first = 0;
  double w[3] = {0.0, 0.0, 0.0};  ///< unused slots are 0
};

/// The weights of axis_weights() for bulk projections (the hand-off), evaluated without branches
/// on the particle position. The same S(d) as ugimp_weight_1d / linear_weight_1d, written in cell
/// units: with u = (x - x_first)/h in [1/2, 3/2] (uGIMP node choice above) and l = l_p/h <= 1/2,
/// the outer nodes sit at a = u and 2 - u in [1/2, 3/2] (branches "1 - a" or "(1 + l - a)^2/(4l)"
/// or 0), the middle node at a = |u - 1| <= 1/2 (branches "1 - (a^2 + l^2)/(2l)" or "1 - a").
/// The branch is chosen by selects (common/branchless.hpp), so irregular particle positions cost no
/// mispredicted jumps.
/// Equal to axis_weights(...).w to round-off (tests/mpm/test_shape_functions.cpp).
/// `inv_h` = 1/h; `l` = l_p/h in (0, 1/2] (ignored for linear); |x - origin| / h < 2^31.
/// `inv4l` = 1/(4 l), passed in so that callers with many equal-sized particles divide once.
template <ShapeKind K>
[[gnu::always_inline]] inline AxisWeightsOnly axis_weights_only(double x, double origin, double inv_h, double l,
                                                                 double inv4l) {
  AxisWeightsOnly a;
  const double xi = (x - origin) * inv_h;
  const int i = common::floor_to_int(xi);
  const double f = xi - i;
  if constexpr (K == ShapeKind::linear) {
    a.first = i;
    a.w[0] = 1.0 - f;
    a.w[1] = f;
    return a;
  } else {
    const double u = common::select_le(f, 0.5, f + 1.0, f);        // distance to the first node, in cells
    a.first = i - static_cast<int>(u - f + 0.5);          // i - 1 where f <= 1/2 (u - f is 1 or 0)
    auto outer = [&](double d) {  // node at distance d in [1/2, 3/2]
      const double t0 = 1.0 + l - d;
      const double t = common::select_lt(0.0, t0, t0, 0.0);  // max(t0, 0)
      const double q = t * t * inv4l;
      return common::select_le(d, 1.0 - l, 1.0 - d, q);
    };
    const double c = std::fabs(u - 1.0);  // middle node, c <= 1/2
    a.w[0] = outer(u);
    const double mid = 1.0 - c;
    a.w[1] = common::select_lt(c, l, 1.0 - (c * c + l * l) * (2.0 * inv4l), mid);
    a.w[2] = outer(2.0 - u);
    return a;
  }
}

template <ShapeKind K>
[[gnu::always_inline]] inline AxisWeightsOnly axis_weights_only(double x, double origin, double inv_h, double l) {
  return axis_weights_only<K>(x, origin, inv_h, l, K == ShapeKind::linear ? 0.0 : 0.25 / l);
}

/// The full 3D stencil of one particle: per-axis weights; the node set is the tensor product.
struct ParticleStencil {
  std::array<AxisWeights, 3> axis;
  /// Number of stencil nodes (8 or 27), zero weights included.
  int size() const { return axis[0].n * axis[1].n * axis[2].n; }
};

/// Stencil of a particle at `x` (m) with half-widths `lp` (m, per axis) on `grid`.
inline ParticleStencil compute_stencil(ShapeKind kind, const common::GridInfo& grid,
                                       const Eigen::Vector3d& x, const Eigen::Vector3d& lp) {
  ParticleStencil s;
  for (int d = 0; d < 3; ++d)
    s.axis[d] = axis_weights(kind, x[d], grid.origin[d], grid.cell_size[d], lp[d]);
  return s;
}

/// Whether every stencil node (i,j,k) lies inside the grid (0 <= i < shape[0], ...).
inline bool stencil_inside(const common::GridInfo& grid, const ParticleStencil& s) {
  for (int d = 0; d < 3; ++d)
    if (s.axis[d].first < 0 || s.axis[d].first + s.axis[d].n > grid.shape[d]) return false;
  return true;
}

/// Call f(i, j, k, weight, gradient) for every stencil node (zero weights included).
template <class F>
inline void for_each_node(const ParticleStencil& s, F&& f) {
  const AxisWeights &X = s.axis[0], &Y = s.axis[1], &Z = s.axis[2];
  for (int a = 0; a < X.n; ++a)
    for (int b = 0; b < Y.n; ++b)
      for (int c = 0; c < Z.n; ++c) {
        const double w = X.w[a] * Y.w[b] * Z.w[c];
        const Eigen::Vector3d g(X.dw[a] * Y.w[b] * Z.w[c], X.w[a] * Y.dw[b] * Z.w[c],
                                X.w[a] * Y.w[b] * Z.dw[c]);
        f(X.first + a, Y.first + b, Z.first + c, w, g);
      }
}

/// One node of a particle's stencil.
struct StencilNode {
  Eigen::Vector3i ijk;    ///< node index
  double weight;          ///< S_ip [1]
  Eigen::Vector3d grad;   ///< grad S_ip = dS_ip/dx_p [1/m]
};

/// The stencil nodes of one particle as a list, nodes with zero weight *and* zero gradient left out.
std::vector<StencilNode> stencil_nodes(ShapeKind kind, const common::GridInfo& grid,
                                       const Eigen::Vector3d& x, const Eigen::Vector3d& lp);

/// Position (m) of node (i,j,k): origin + (i,j,k) * cell_size.
inline Eigen::Vector3d node_position(const common::GridInfo& grid, int i, int j, int k) {
  return grid.origin + Eigen::Vector3d(i * grid.cell_size[0], j * grid.cell_size[1],
                                       k * grid.cell_size[2]);
}

/// Linear index of node (i,j,k), x fastest: i + shape[0]*(j + shape[1]*k).
inline std::size_t node_index(const common::GridInfo& grid, int i, int j, int k) {
  return static_cast<std::size_t>(i) +
         static_cast<std::size_t>(grid.shape[0]) *
             (static_cast<std::size_t>(j) + static_cast<std::size_t>(grid.shape[1]) * k);
}

/// Total number of nodes of the grid.
inline std::size_t node_count(const common::GridInfo& grid) {
  return static_cast<std::size_t>(grid.shape[0]) * grid.shape[1] * grid.shape[2];
}

/// Default uGIMP half-width for `ppc` particles per cell per axis: h / (2 ppc).
inline Eigen::Vector3d default_half_width(const common::GridInfo& grid, int ppc) {
  return grid.cell_size / (2.0 * ppc);
}

}  // namespace mpmfrag
