/// @file run_mpi.hpp
/// The mpm-frag driver on more than one MPI rank (SUITE_MPI=ON; one rank runs run_mpm): the same
/// scene, over DomainSolver (domain.hpp), with the serial driver's outputs and failure paths.
/// - Files: snapshots and checkpoints written by every rank together with collective parallel
///   HDF5 (the serial layout, particles sorted by id within each material); series.csv rows (with
///   the driven bodies' load columns, the same on every rank) and progress lines from rank 0
///   (global diagnostics); the outflow file written by every rank
///   together from its own record (snapshot_mpi.hpp). Checkpoints periodic, at the end and on SIGTERM/SIGINT; --restart from a
///   checkpoint of any rank count (checkpoint_mpi.hpp).
/// - Run directory (run_directory.hpp), held by rank 0: output.directory is locked for the run
///   (a second run into it exits 2), every rank writes into its staging directory, and rank 0
///   publishes it when the run completes; a failed or interrupted run leaves the previous run's
///   files as they were, its own in the staging directory (named in the log).
/// - Failure: a numerical failure stops every rank after the same step (exit 3). The last good
///   state is saved first, by every rank together, as `<prefix>_failed_<step>.h5`: the current
///   state if the failure left it intact, else the ranks' backups of the same earlier step (every
///   run.backup_every steps, DomainSolver::save_backup); then the outflow record and the series
///   up to the failure. A signal stops every rank after the same step (exit 128 + signal).
#pragma once
#include <string>

#include "common/provenance.hpp"
#include "common/schema.hpp"
#include "mpm/run.hpp"

namespace mpmfrag::mpi {

/// Run a scene on MPI_COMM_WORLD (every rank calls it with the same arguments).
RunSummary run_mpm_mpi(const common::Scene& scene, const common::Provenance& prov, const std::string& restart);

}  // namespace mpmfrag::mpi
