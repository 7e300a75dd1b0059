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
  std::string prefix = "analysis";  ///< writes <prefix>.json, <prefix>.timeseries.csv, <prefix>.damage.csv
  std::string scene_source;         ///< for messages
};

common::Schema analyse_schema();
/// Resolve and check a scene (throws common::InputError naming the scene and key).
AnalyseConfig analyse_config(const common::Scene& scene);

}  // namespace analysis
