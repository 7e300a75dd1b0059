/// @file io_mpi.hpp
/// ssdem-grav's snapshots and checkpoints written by every rank together (MPI build): the files of
/// io.hpp, equal to those of a one-rank run (spheres in index order, history records in the
/// one-rank order, the same datasets, units and attributes), written with collective parallel
/// HDF5 (common/mpi/sphere_file_mpi.hpp): each rank's rows move to its fixed block of the file, so
/// no rank holds more than its block (plus one column in flight), and the carried fields, which
/// each rank keeps for its block (DomainSim::carried_block), do not move at all.
/// Errors, on every rank alike: IoError if the file cannot be written (an earlier file is kept, no
/// temporary is left); NumericalError if any rank's spheres hold a NaN or Inf (nothing written).
#pragma once
#include <string>

#include "common/provenance.hpp"
#include "ssdem/io.hpp"
#include "ssdem/mpi/domain_sim.hpp"

namespace ssdem::mpi {

/// Collective: the snapshot of the part `mine` of every rank (DomainSim::local_state()).
void write_snapshot_mpi(Comm& comm, const std::string& path, const DomainSim& sim, const DomainSim::Local& mine,
                        const common::Provenance& prov);
/// Collective: the checkpoint of the part `mine` of every rank (local_state() or last_good_local());
/// `h` as write_checkpoint records it (the same on every rank), `energy0` the run's E_0.
void write_checkpoint_mpi(Comm& comm, const std::string& path, const DomainSim& sim, const DomainSim::Local& mine,
                          const StateHeader& h, double energy0, const common::Provenance& prov);

}  // namespace ssdem::mpi
