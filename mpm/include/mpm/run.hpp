/// @file run.hpp
/// The mpm-frag driver: scene -> solver -> time loop with snapshots, time series, progress,
/// last-good-state backups, clean failure (common::NumericalError, exit code 3, state saved),
/// checkpoints and restart.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "common/provenance.hpp"
#include "common/schema.hpp"
#include "mpm/solver.hpp"

namespace mpmfrag {

/// What a completed run reports (also logged).
struct RunSummary {
  std::int64_t steps = 0;
  double time = 0;
  Diagnostics initial, final;
  double wall_s = 0;
  double bytes_per_particle = 0;
  std::size_t particles = 0;
  double first_dt = 0, min_dt = 0, max_dt = 0;
  std::string last_snapshot;
  std::string series_path;
  int signal = 0;  ///< SIGTERM/SIGINT that stopped the run after a checkpoint (exit 128 + signal), or 0
};

/// Scene keys a restart may change (they do not alter the computed states): the run identity
/// recorded in checkpoints leaves them out (also used by the MPI driver, mpi/run_mpi.hpp).
const std::vector<std::string>& restart_free_keys();

/// Run the scene, or continue the checkpoint `restart` (mpm/checkpoint.hpp; InputError if it is
/// another run's). Throws common::InputError (bad scene), common::IoError (outputs) or
/// common::NumericalError (after saving the last good state; `saved_state()` names the file).
/// A SIGTERM/SIGINT ends the run after the current step and a checkpoint (RunSummary::signal).
RunSummary run_mpm(const common::Scene& scene, const common::Provenance& prov, const std::string& restart = {});

}  // namespace mpmfrag
