/// @file momentum.hpp
/// Momentum enhancement factor β from momentum bookkeeping.
///
/// Frame: the rest frame of the target *before* the impact. Velocities in the files are taken
/// in the simulation frame and shifted by the target's pre-impact velocity v_t:
///     U = v_imp - v_t (impactor velocity relative to the target),  Û = U/|U|,
///     P_X = Σ_{k∈X} m_k (v_k - v_t)   for a set X of spheres.
/// Definitions (validation-data.md §5.1, ssdem.md §5.2; Holsapple & Housen 2012: "the ratio of
/// the change of momentum of the remaining asteroid to that of the impactor"):
///     β        = P_bound·Û / (m |U|)              bound remnant (LR + bound clumps), the headline
///     β_LR     = P_LR·Û / (m |U|)                 largest FOF clump only
///     β_ejecta = 1 - P_esc·Û / (m |U|)            from the escaping material's momentum
///     β_vector: Cheng et al. 2023 (Nature 616:457) eq. 1, M Δv = m U + m (β-1)(Ê·U) Ê with
///               Ê ∥ D = P_bound - m U, giving β_vector = 1 + |D|^2 / (m D·U)
///     β_total  = P_bound·Û / P_total·Û            the same with the momentum actually present in the
///               snapshot as reference (insensitive to a discretised impactor whose mass or
///               speed differs from the scene's m, U, or to material dropped at hand-off)
/// β and β_ejecta agree when momentum is conserved, m U = P_bound + P_esc; the relative
/// violation |P_total - m U| / (m |U|) is reported. The bound set includes embedded impactor
/// material (validation-data.md §5.1 step 3). β_vector equals β for a head-on impact.
#pragma once
#include <Eigen/Core>
#include <optional>

#include "analysis/bound.hpp"

namespace analysis {

struct ImpactSpec {
  double impactor_mass = 0.0;                                  ///< m [kg]
  Eigen::Vector3d impactor_velocity = Eigen::Vector3d::Zero();  ///< simulation frame [m/s]
  Eigen::Vector3d target_velocity = Eigen::Vector3d::Zero();    ///< pre-impact target velocity [m/s]

  bool valid() const { return impactor_mass > 0.0 && (impactor_velocity - target_velocity).norm() > 0.0; }
  Eigen::Vector3d relative_velocity() const { return impactor_velocity - target_velocity; }
  /// Û (zero vector if the impact is not specified).
  Eigen::Vector3d direction() const;
  double impactor_momentum() const { return impactor_mass * relative_velocity().norm(); }
};

struct BetaResult {
  double beta = 0.0, beta_lr = 0.0, beta_ejecta = 0.0;
  double beta_total = 0.0;                 ///< P_bound·Û / P_total·Û (NaN if P_total·Û = 0)
  std::optional<double> beta_vector;       ///< absent when D·U = 0 (no momentum transferred)
  double escaping_momentum_along = 0.0;    ///< P_esc·Û [kg m/s] (target frame)
  Eigen::Vector3d escaping_momentum = Eigen::Vector3d::Zero();  ///< P_esc (target frame)
  double momentum_error = 0.0;             ///< |P_total - m U| / (m |U|)
};

/// β from a bound-mass result. Requires spec.valid().
BetaResult momentum_enhancement(const BoundResult& b, const ImpactSpec& spec);

}  // namespace analysis
