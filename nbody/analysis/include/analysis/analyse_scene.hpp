/// @file analyse_scene.hpp
/// Parameters of ssdem-analyse (one common::Schema) and the resolved configuration.
#pragma once
#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "analysis/momentum.hpp"
#include "common/schema.hpp"

namespace analysis {

struct AnalyseConfig {
  std::vector<std::string> inputs;  ///< ssdem.spheres snapshots (any order; sorted by time)
  ImpactSpec impact;
  double parent_body_mass = 0.0;  ///< M_PB; <= 0: total mass of the earliest snapshot
  double target_radius = 0.0;     ///< recorded for the report (0: unknown)
  double link_fraction = 0.2;     ///< eps = link_fraction x median radius ...
  double link_length = 0.0;       ///< ... unless this is > 0 [m]
  double G = 6.674e-11;
  int max_iterations = 1000;
  std::string damage_field = "damage";
  std::string damage_mpm;  ///< particle snapshot (or sphere file) for the end-of-MPM profile
  int axial_bins = 20, radial_bins = 20;
  double range_lo = 0.0, range_hi = 0.0;  ///< axial range; lo >= hi: automatic (see run_analysis.cpp)
  double cylinder_radius = 0.0;
  std::optional<Eigen::Vector3d> axis, origin;
  /// mpm-frag snapshot at t = 0: impactor/target masses and velocities are taken from its
  /// particles for every impact.* value not given explicitly (see impact_from_mpm()).
  std::string impact_from_mpm;
  bool impactor_mass_given = false, impactor_velocity_given = false, target_velocity_given = false,
       parent_body_mass_given = false;
  std::string prefix = "analysis";  ///< writes <prefix>.json, <prefix>.timeseries.csv, <prefix>.damage.csv
  std::string scene_source;         ///< for messages
};

/// What impact_from_mpm() found in the initial particle snapshot.
struct MpmImpact {
  double impactor_mass = 0.0, target_mass = 0.0;
  Eigen::Vector3d impactor_velocity = Eigen::Vector3d::Zero(), target_velocity = Eigen::Vector3d::Zero();
  std::size_t impactor_particles = 0, target_particles = 0;
};

/// Split the particles of an initial mpm-frag snapshot into target and impactor by velocity:
/// v_ref = mass-weighted median velocity (the target's, which dominates the mass); impactor =
/// particles with |v - v_ref| > 0.5 max_i |v_i - v_ref|. Masses and mass-weighted velocities of
/// both parts, i.e. the impact as the simulation discretised it. Throws common::InputError if the
/// file is not a particle snapshot or no impactor stands out.
MpmImpact impact_from_mpm(const std::string& path);

common::Schema analyse_schema();
/// Resolve and check a scene (throws common::InputError naming the scene and key).
AnalyseConfig analyse_config(const common::Scene& scene);

}  // namespace analysis
