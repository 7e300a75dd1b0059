/// @file snapshot_mpi.hpp
/// mpm-frag's particle snapshots on MPI ranks, written collectively with parallel HDF5
/// (common/particle_file_mpi.hpp): every rank passes its own particles, keyed by (material slot,
/// id), so the file lists them as the serial run and the former gather to rank 0 did (materials
/// in slot order, ids ascending within each) and no rank holds the whole set.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "common/grid.hpp"
#include "common/provenance.hpp"
#include "mpm/mpi/domain.hpp"

namespace mpmfrag::mpi {

/// Collective: the snapshot of every rank's particles `ps` (materials `mats`) at `time`, `step`,
/// written to `path` (the current state: DomainSolver::local(); a failure's last good state:
/// DomainSolver::backup()). Throws common::IoError on every rank if it cannot be written (an
/// earlier file is kept), and common::NumericalError on every rank, writing nothing, if any rank
/// holds a value that is not finite (as the serial driver, exit 3).
void write_snapshot_mpi(Comm& comm, const ParticleSet& ps, const std::vector<MaterialSlot>& mats,
                        const common::GridInfo& grid, double time, std::int64_t step, const std::string& path,
                        const common::Provenance& prov);

}  // namespace mpmfrag::mpi
