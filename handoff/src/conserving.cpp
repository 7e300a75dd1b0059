/// @file conserving.cpp
/// Implementation of handoff/conserving.hpp (the header states the contract, and for physics the equations and sources).
#include "handoff/conserving.hpp"

#include <Eigen/Dense>
#include <cmath>

namespace handoff {

ConservingResult apply_conserving(common::SphereSet& s, const Invariants& target) {
  ConservingResult res;
  const std::size_t n = s.count();
  const Invariants cur = compute_invariants(n, s.position.data(), s.velocity.data(), s.mass.data());
  if (n == 0 || !(cur.mass > 0.0)) {
    res.note = "no spheres";
    return res;
  }
  const Eigen::Vector3d X = cur.centre_of_mass;
  const Eigen::Vector3d V = cur.momentum / cur.mass;
  Eigen::Vector3d A = Eigen::Vector3d::Zero();
  Eigen::Matrix3d I = Eigen::Matrix3d::Zero();
  double B = 0.0, J = 0.0;
  for (std::size_t c = 0; c < n; ++c) {
    const Eigen::Vector3d r = Eigen::Vector3d(&s.position[3 * c]) - X;
    const Eigen::Vector3d u = Eigen::Vector3d(&s.velocity[3 * c]) - V;
    const double M = s.mass[c];
    A += M * r.cross(u);
    B += M * u.squaredNorm();
    I += M * (r.squaredNorm() * Eigen::Matrix3d::Identity() - r * r.transpose());
    J += 0.4 * M * s.radius[c] * s.radius[c];
  }
  I += J * Eigen::Matrix3d::Identity();  // positive definite
  const Eigen::LDLT<Eigen::Matrix3d> Ifac(I);
  const Eigen::Vector3d L0 = target.angular_momentum;
  const double K0int = target.kinetic() - 0.5 * target.mass * (target.momentum / target.mass).squaredNorm();
  const Eigen::Vector3d a = Ifac.solve(L0), b = Ifac.solve(A);
  const double num = 2.0 * K0int - L0.dot(a);
  const double den = B - A.dot(b);
  const double scale = std::max(2.0 * std::fabs(K0int), 1e-300);
  if (num < -1e-13 * scale || den <= 1e-13 * scale) {
    res.note = num < 0 ? "target motion is nearly a rigid rotation: the sphere set's inertia cannot carry its "
                         "angular momentum with its kinetic energy; paper spheres kept"
                       : "sphere velocities carry no non-rigid motion to rescale; paper spheres kept";
    return res;
  }
  res.lambda = std::sqrt(std::max(num, 0.0) / den);
  res.omega = Ifac.solve(L0 - res.lambda * A);
  for (std::size_t c = 0; c < n; ++c) {
    const Eigen::Vector3d r = Eigen::Vector3d(&s.position[3 * c]) - X;
    const Eigen::Vector3d u = Eigen::Vector3d(&s.velocity[3 * c]) - V;
    const Eigen::Vector3d v = V + res.lambda * u + res.omega.cross(r);
    for (int d = 0; d < 3; ++d) {
      s.velocity[3 * c + d] = v[d];
      s.spin[3 * c + d] = res.omega[d];
    }
  }
  res.exact = true;
  return res;
}

}  // namespace handoff
