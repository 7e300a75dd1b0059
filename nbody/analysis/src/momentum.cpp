/// @file momentum.cpp
/// Implementation of analysis/momentum.hpp; the governing equations, sources and deviations are documented there.
#include "analysis/momentum.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

namespace analysis {

Eigen::Vector3d ImpactSpec::direction() const {
  const Eigen::Vector3d u = relative_velocity();
  const double n = u.norm();
  return n > 0.0 ? Eigen::Vector3d(u / n) : Eigen::Vector3d::Zero();
}

BetaResult momentum_enhancement(const BoundResult& b, const ImpactSpec& spec) {
  if (!spec.valid()) throw std::invalid_argument("momentum_enhancement: impactor mass and velocity are required");
  BetaResult r;
  const Eigen::Vector3d U = spec.relative_velocity(), uhat = spec.direction(), vt = spec.target_velocity;
  const double pimp = spec.impactor_momentum();
  const Eigen::Vector3d p_bound = b.bound_momentum - b.bound_mass * vt;
  const Eigen::Vector3d p_lr = b.lr_momentum - b.lr_mass * vt;
  const Eigen::Vector3d p_esc = b.escaping_momentum - b.escaping_mass * vt;
  const Eigen::Vector3d p_tot = b.total_momentum - b.total_mass * vt;
  r.beta = p_bound.dot(uhat) / pimp;
  r.beta_lr = p_lr.dot(uhat) / pimp;
  r.escaping_momentum = p_esc;
  r.escaping_momentum_along = p_esc.dot(uhat);
  r.beta_ejecta = 1.0 - r.escaping_momentum_along / pimp;
  r.momentum_error = (p_tot - spec.impactor_mass * U).norm() / pimp;
  const double ptu = p_tot.dot(uhat);
  r.beta_total = ptu != 0.0 ? p_bound.dot(uhat) / ptu : std::numeric_limits<double>::quiet_NaN();
  const Eigen::Vector3d D = p_bound - spec.impactor_mass * U;
  const double du = D.dot(U);
  if (std::abs(du) > 1e-14 * D.norm() * U.norm() && du != 0.0)
    r.beta_vector = 1.0 + D.squaredNorm() / (spec.impactor_mass * du);
  else if (D.norm() == 0.0)
    r.beta_vector = 1.0;
  return r;
}

}  // namespace analysis
