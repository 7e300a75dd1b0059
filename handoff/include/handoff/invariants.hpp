/// @file invariants.hpp
/// Conserved quantities of a particle set or a sphere set, for the hand-off audit.
///
///   M = sum m,  X = sum m x / M,  P = sum m v,  V = P / M,
///   L = sum m (x - X) x (v - V) + sum I_s omega          (about the set's own centre of mass)
///   K_trans = sum m |v|^2 / 2,  K_rot = sum omega . I_s omega / 2,  I_s = (2/5) m r^2 (solid sphere)
/// One pass over the items (moments about item 0 shifted to the centre of mass) and a second for the
/// scale below; sums plain within blocks of 32 items and compensated (Neumaier) across blocks, so that round-off (~1e-14 relative)
/// does not mask a real conservation error (invariants.cpp).
#pragma once
#include <Eigen/Core>
#include <cstddef>

namespace handoff {

struct Invariants {
  double mass = 0.0;
  Eigen::Vector3d centre_of_mass = Eigen::Vector3d::Zero();
  Eigen::Vector3d momentum = Eigen::Vector3d::Zero();
  Eigen::Vector3d angular_momentum = Eigen::Vector3d::Zero();  ///< about the centre of mass
  double kinetic_translational = 0.0;
  double kinetic_rotational = 0.0;
  /// sum m |x - X| |v - V| (+ sum I_s |omega|): the largest |L| this motion could have; the scale
  /// for relative angular-momentum errors, meaningful also when L itself is near zero (head-on).
  double angular_momentum_scale = 0.0;
  std::size_t count = 0;
  double kinetic() const { return kinetic_translational + kinetic_rotational; }
};

/// Invariants of `n` items with flat arrays x, v (n*3), m (n); `spin` (n*3) and `radius` (n)
/// may be null (point masses, no spin).
Invariants compute_invariants(std::size_t n, const double* x, const double* v, const double* m,
                              const double* spin = nullptr, const double* radius = nullptr);

}  // namespace handoff
