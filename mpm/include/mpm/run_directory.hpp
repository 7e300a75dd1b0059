/// @file run_directory.hpp
/// mpm-frag's output directory, shared by the serial driver (run.hpp) and the MPI driver
/// (mpi/run_mpi.hpp, on rank 0; every rank then writes into the staging directory):
/// `output.directory` is locked for the run and every file goes to a staging directory that is
/// published when the run completes (common/run_dir.hpp), so a failed, killed or interrupted run
/// leaves the previous run's files as they were and a second run into the same directory is
/// refused (exit 2). Names: `<prefix>_<step:06>.h5` snapshots (`<prefix>_failed_<step>.h5` the
/// last good state of a failed run), `<prefix>_series.csv`, `<prefix>_checkpoint.h5`,
/// `<prefix>_outflow.h5`, each `.h5` with its `.xmf` sidecar.
#pragma once
#include <cstdint>
#include <memory>
#include <string>

#include "common/run_dir.hpp"
#include "mpm/scene_setup.hpp"

namespace mpmfrag {

/// `<run.out_dir>/<prefix>_<tag><step, 6 digits>.h5`.
std::string snap_name(const RunConfig& run, const std::string& tag, std::int64_t step);

/// The step of a snapshot file name `<prefix>_<digits>.h5` / `.xmf`, or -1 (other files).
std::int64_t snap_step(const std::string& prefix, const std::string& name);

/// Lock `run.out_dir` (created if needed) and make a fresh staging directory, or adopt the
/// staging directory of the interrupted run whose checkpoint `restart` is. Throws
/// common::InputError (locked by another run) or common::IoError, as common::RunDirectory.
std::unique_ptr<common::RunDirectory> open_run_directory(const RunConfig& run, const std::string& restart);

/// A restart from a published run's checkpoint (`restart` not inside a staging directory of
/// `run.out_dir`): that run's snapshots up to `step` are carried into the staging directory, so
/// the continuation publishes them again. Does nothing for a checkpoint in a staging directory
/// (adopted with it). Throws common::IoError.
void carry_snapshots(common::RunDirectory& rd, const RunConfig& run, const std::string& restart, std::int64_t step);

}  // namespace mpmfrag
