/// @file run_mpi.hpp
/// The ssdem-grav driver on more than one MPI rank (SUITE_MPI=ON; one rank runs run_ssdem):
/// the same scene keys, outputs and exit codes as run.hpp, over DomainSim (domain_sim.hpp).
/// Files are gathered to rank 0 and written there with the serial writers (not collective
/// parallel HDF5 yet), so snapshots, series.csv, checkpoints and failed_state.h5 have the content
/// and layout of a one-rank run and a checkpoint written on N ranks restarts on any M.
/// Series rows are not gathered: each rank sums its own spheres' and contacts' terms exactly and
/// the sums are added over the ranks (DomainSim::diagnostics), which gives series.csv the bits of
/// a one-rank run whatever the rank count; contact counts and the largest overlap are counted
/// from the active contact records each rank owns.
/// Signals (SIGTERM/SIGINT, forwarded by mpirun/srun to every rank) are agreed on at gravity-block
/// boundaries; the checkpoint is then written and every rank exits 128 + signal. Not yet: the
/// last-good state (a numerical failure saves the failing state as failed_state.h5, exit 3).
#pragma once
#include <string>

#include "common/provenance.hpp"
#include "common/schema.hpp"

namespace ssdem::mpi {

/// Run a scene on MPI_COMM_WORLD (every rank calls it with the same arguments).
int run_ssdem_mpi(const common::Scene& scene, const common::Provenance& prov, const std::string& restart);

}  // namespace ssdem::mpi
