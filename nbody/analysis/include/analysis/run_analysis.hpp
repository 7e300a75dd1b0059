/// @file run_analysis.hpp
/// The ssdem-analyse driver: per snapshot FOF -> largest remnant -> bound mass -> beta, damage
/// profiles at the end of MPM and of the N-body run, and the three output files.
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "analysis/analyse_scene.hpp"
#include "analysis/bound.hpp"
#include "analysis/damage_profile.hpp"
#include "analysis/fof.hpp"
#include "analysis/momentum.hpp"
#include "common/provenance.hpp"
#include "common/sphere_file.hpp"

namespace analysis {

/// The reaccumulation state of one snapshot.
struct SnapshotResult {
  std::string file;
  double time = 0.0;
  long long step = 0;
  std::size_t n_spheres = 0;
  std::size_t n_clumps = 0, n_singles = 0;
  std::size_t lr_count = 0;  ///< spheres in the largest clump
  BoundResult bound;         ///< per-clump flags dropped after use (bound.bound empty)
  std::optional<BetaResult> beta;
  /// Sphere-by-sphere escape test (escape_speed.hpp) about the bound remnant, radius R_ref.
  double speed_escaping_mass = 0.0;
  double speed_reference_radius = 0.0;
  std::optional<double> beta_escape_speed;  ///< 1 - P_esc,speed·Û / (m |U|)
  Eigen::Vector3d lr_velocity = Eigen::Vector3d::Zero(), bound_velocity = Eigen::Vector3d::Zero();
};

/// FOF + bound mass + beta of one sphere set. `sphere_bound` (optional) receives a per-sphere
/// 0/1 flag of membership in the bound remnant.
/// `parent_body_mass` scales impact.target_radius to the escape-speed reference radius (0: use
/// the bound remnant's rms radius instead).
SnapshotResult analyse_snapshot(const common::SphereSet& s, const AnalyseConfig& cfg, double eps,
                                std::vector<char>* sphere_bound = nullptr, double parent_body_mass = 0.0);

struct ProfileRecord {
  std::string source;  ///< file
  std::string stage;   ///< "mpm_end", "handoff", "nbody_end"
  double time = 0.0;
  std::string set;     ///< "all" or "bound" (bound remnant only)
  std::string kind;    ///< "axial" or "radial"
  Eigen::Vector3d origin = Eigen::Vector3d::Zero(), axis = Eigen::Vector3d::UnitZ();
  std::vector<ProfileBin> bins;
};

struct AnalysisOutcome {
  std::vector<SnapshotResult> rows;  ///< in time order
  std::vector<ProfileRecord> profiles;
  double parent_body_mass = 0.0;
  std::string parent_body_mass_source;
  double link_length = 0.0;
  std::vector<std::string> notes;
  std::optional<AnalyseConfig> cfg;  ///< the configuration actually used (impact values resolved)
  std::string impact_source;      ///< where the impact values came from
  std::optional<MpmImpact> mpm_impact;
};

/// Read the snapshots of `cfg.inputs` (stably sorted by time on the N-body clock: the `time`
/// attribute, except 0 for a file written by mpm2spheres, since ssdem-grav starts its clock at 0
/// from the hand-off state), analyse each, compute
/// the damage profiles. Throws common::InputError (bad file, naming file and key).
AnalysisOutcome run_analysis(const AnalyseConfig& cfg);

std::string timeseries_csv(const AnalysisOutcome& o);
std::string damage_csv(const AnalysisOutcome& o);
std::string summary_json(const AnalysisOutcome& o, const AnalyseConfig& cfg, const common::Provenance& prov);
/// Throws common::NumericalError (exit 3) naming `path`, the snapshot file and the quantity if a
/// result about to be written is NaN or Inf (the CSV would show it as an empty cell).
void check_outcome_finite(const AnalysisOutcome& o, const std::string& path);
/// Check the outcome (check_outcome_finite), then write <prefix>.json, <prefix>.timeseries.csv and
/// <prefix>.damage.csv as a set (common::write_text_set_atomic: all to temporaries, renamed only
/// when all were written, the JSON last so that its presence means the set is complete).
void write_outputs(const AnalysisOutcome& o, const AnalyseConfig& cfg, const common::Provenance& prov);

}  // namespace analysis
