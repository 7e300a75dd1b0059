/// @file run_mpi.hpp
/// The mpm-frag driver on more than one MPI rank (SUITE_MPI=ON; one rank runs run_mpm): the same
/// scene, over DomainSolver (domain.hpp). First step, and says so: snapshots are gathered to rank
/// 0 and written there by the serial writer (one file per snapshot, the serial layout, particles
/// sorted by id within each material), series.csv rows from the global diagnostics, checkpoints
/// (periodic, at the end, on SIGTERM/SIGINT) written the same way and --restart from a checkpoint
/// of any rank count (checkpoint_mpi.hpp), the outflow file (every rank's record gathered); no
/// collective parallel HDF5 yet, no last-good-state
/// file, files written straight into output.directory (no staging directory). A failure stops
/// every rank (exit 3); a signal stops every rank after the same step (exit 128 + signal).
#pragma once
#include <string>

#include "common/provenance.hpp"
#include "common/schema.hpp"
#include "mpm/run.hpp"

namespace mpmfrag::mpi {

/// Run a scene on MPI_COMM_WORLD (every rank calls it with the same arguments).
RunSummary run_mpm_mpi(const common::Scene& scene, const common::Provenance& prov, const std::string& restart);

}  // namespace mpmfrag::mpi
