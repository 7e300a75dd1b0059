/// @file gravity.hpp
/// Self-gravity: Barnes-Hut octree with quadrupole moments and a group (bucket) walk, plus
/// direct summation for reference and small N.
///
/// Softening: the cubic-spline kernel of Monaghan & Lattanzio (1985) as used for gravity by
/// Hernquist & Katz (1989, ApJS 70:419) and pkdgrav, with support radius h_ij = s_i + s_j (the
/// sum of the two sphere radii; pkdgrav's convention softening length = radius, ssdem.md §2.1).
/// Hence gravity is *exactly Newtonian for every pair that does not overlap* and is softened
/// only inside contacts. With u = r/h (Springel 2005, GADGET-2 eq. A.1 kernel, written here in
/// closed form):
///   phi(r) = -G m / h * W(u),  a(r) = -G m r_vec / h^3 * K(u)
///   u < 1/2:  W = 2.8 - u^2 (16/3 - u^2 (48/5 - 32/5 u)),  K = 32/3 - u^2 (192/5 - 32 u)
///   u < 1:    W = 3.2 - 1/(15u) - u^2 (32/3 - u (16 - u (48/5 - 32/15 u))),
///             K = 64/3 - 48 u + 192/5 u^2 - 32/3 u^3 - 1/(15 u^3)
///   u >= 1:   W = 1/u, K = 1/u^3 (Newtonian)
/// Multipoles (about each cell's centre of mass, traceless quadrupole Q = sum m (3 d d^T - d^2 I)):
///   phi = -G M / r - G (r^T Q r) / (2 r^5),
///   a = -G M r / r^3 + G (Q r / r^5 - (5/2) (r^T Q r) r / r^7)
/// Opening (per group = tree leaf, Barnes 1990 group walk): a cell is used as a multipole for
/// every particle of the group iff r_min > b_max / theta and r_min > b_max + h_max(cell) +
/// h_max(group), where r_min is the distance from the cell's centre of mass to the group's
/// bounding box and b_max the largest distance of a cell particle from its centre of mass
/// (Salmon & Warren 1994 b_max criterion). The second condition guarantees that no softened
/// pair is ever approximated. Coincident/clustered points: leaves hold up to `bucket`
/// particles, and subdivision stops at `max_depth`, where a leaf may hold more.
/// Determinism: the tree is built serially from positions in index order; each group's sum
/// runs in a fixed order, groups are independent, so forces do not depend on the thread count.
#pragma once
#include <cstdint>
#include <vector>

#include "ssdem/gravity_tree.hpp"
#include "ssdem/spheres.hpp"

namespace ssdem {

/// Spline-softened pair kernel: returns K(u)/h^3 and sets W(u)/h (see file comment).
inline double spline_force_factor(double r, double h, double& pot_factor) {
  if (r >= h) {
    const double ir = 1.0 / r;
    pot_factor = ir;
    return ir * ir * ir;
  }
  const double ih = 1.0 / h, u = r * ih;
  const double u2 = u * u;
  const double ih3 = ih * ih * ih;
  if (u < 0.5) {
    pot_factor = ih * (2.8 - u2 * (16.0 / 3.0 - u2 * (9.6 - 6.4 * u)));
    return ih3 * (32.0 / 3.0 - u2 * (38.4 - 32.0 * u));
  }
  pot_factor = ih * (3.2 - 1.0 / (15.0 * u) - u2 * (32.0 / 3.0 - u * (16.0 - u * (9.6 - 32.0 / 15.0 * u))));
  return ih3 * (64.0 / 3.0 - 48.0 * u + 38.4 * u2 - 32.0 / 3.0 * u2 * u - 1.0 / (15.0 * u2 * u));
}

/// Direct O(N^2) summation with the same kernel (reference). `pot` (optional) gets the
/// potential per unit mass at each sphere [J/kg].
void direct_gravity(const Spheres& sp, double G, std::vector<Vec3>& acc,
                    std::vector<double>* pot = nullptr);

/// Barnes-Hut octree with quadrupoles and group walk.
class TreeGravity {
 public:
  explicit TreeGravity(GravityParams p) : p_(p) {}
  const GravityParams& params() const { return p_; }
  /// Build the tree for the current positions and compute accelerations (and potentials).
  void compute(const Spheres& sp, std::vector<Vec3>& acc, std::vector<double>* pot = nullptr);
  const TreeStats& stats() const { return d_.stats; }
  /// Bytes per sphere held by the tree (nodes + permutation + sorted copies).
  double bytes_per_sphere(std::size_t n) const;

 private:
  void build(const Spheres& sp);
  GravityParams p_;
  tree::Data d_;
};

}  // namespace ssdem
