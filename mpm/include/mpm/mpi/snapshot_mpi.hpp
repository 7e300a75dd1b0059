/// @file snapshot_mpi.hpp
/// mpm-frag's particle snapshots on MPI ranks, written collectively with parallel HDF5
/// (common/particle_file_mpi.hpp): every rank passes its own particles, keyed by (material slot,
/// id), so the file lists them as the serial run and the former gather to rank 0 did (materials
/// in slot order, ids ascending within each) and no rank holds the whole set.
#pragma once
#include <string>

#include "common/grid.hpp"
#include "common/provenance.hpp"
#include "mpm/mpi/domain.hpp"

namespace mpmfrag::mpi {

/// Collective: the snapshot of every rank's particles at the current step, written to `path`.
/// Throws common::IoError on every rank if it cannot be written (an earlier file is kept), and
/// common::NumericalError on every rank, writing nothing, if any rank holds a value that is not
/// finite (as the serial driver, exit 3).
void write_snapshot_mpi(DomainSolver& dom, const common::GridInfo& grid, const std::string& path,
                        const common::Provenance& prov);

}  // namespace mpmfrag::mpi
