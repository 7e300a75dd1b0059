/// @file snapshot_mpi.hpp
/// mpm-frag's particle snapshots on MPI ranks, written collectively with parallel HDF5
/// (common/particle_file_mpi.hpp): every rank passes its own particles, keyed by (material slot,
/// id), so the file lists them as the serial run and the former gather to rank 0 did (materials
/// in slot order, ids ascending within each) and no rank holds the whole set; and the outflow
/// file of the particles removed at the grid edge, keyed by (removal time, id).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "common/grid.hpp"
#include "common/provenance.hpp"
#include "common/sorted_rows.hpp"
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

/// The file order of an outflow record's rows: (removal time, id). Removal times are >= 0, so
/// their IEEE-754 bits, read as unsigned integers, order as the times do.
std::vector<common::mpi::RowKey> outflow_keys(const OutflowRecord& rec);

/// Collective: the outflow file of every rank's record (`local`: DomainSolver::local_outflow,
/// the same field list on every rank), positions moved ballistically to `time`, rows sorted by
/// (removal time, id): the file the serial writer makes of the gathered record, written by
/// every rank together. Throws common::IoError on every rank if it cannot be written.
void write_outflow_mpi(Comm& comm, const OutflowRecord& local, const common::GridInfo& grid, double time,
                       std::int64_t step, const std::string& path, const common::Provenance& prov);

}  // namespace mpmfrag::mpi
