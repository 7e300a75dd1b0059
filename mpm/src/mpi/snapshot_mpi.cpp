/// @file snapshot_mpi.cpp
/// Implementation of mpm/mpi/snapshot_mpi.hpp (the header states the contract).
#include "mpm/mpi/snapshot_mpi.hpp"

#include <bit>

#include "common/agreed.hpp"
#include "common/finite.hpp"
#include "common/particle_file_mpi.hpp"
#include "mpm/output.hpp"

namespace mpmfrag::mpi {

void write_snapshot_mpi(Comm& comm, const ParticleSet& ps, const std::vector<MaterialSlot>& mats,
                        const common::GridInfo& grid, double time, std::int64_t step, const std::string& path,
                        const common::Provenance& prov) {
  const common::ParticleSnapshot local = make_snapshot(ps, mats, grid, time, step);
  // never Inf/NaN in an output (exit 3 on every rank, nothing written)
  common::mpi::agreed(comm, [&] { common::check_output_particles(local, path); });
  std::vector<common::mpi::RowKey> keys(ps.size());
  for (std::size_t m = 0; m < mats.size(); ++m)
    for (std::size_t p = mats[m].begin; p < mats[m].end; ++p) keys[p] = {m, ps.id[p]};
  common::mpi::write_particle_snapshot_mpi(comm, path, local, keys, prov);
}

std::vector<common::mpi::RowKey> outflow_keys(const OutflowRecord& rec) {
  std::vector<common::mpi::RowKey> keys(rec.time.size());
  for (std::size_t i = 0; i < keys.size(); ++i) keys[i] = {std::bit_cast<std::uint64_t>(rec.time[i] + 0.0), rec.ps.id[i]};
  return keys;
}

void write_outflow_mpi(Comm& comm, const OutflowRecord& local, const common::GridInfo& grid, double time,
                       std::int64_t step, const std::string& path, const common::Provenance& prov) {
  const common::ParticleSnapshot snap = make_outflow_snapshot(local.ps, local.time, local.fields, grid, time, step);
  common::mpi::write_particle_snapshot_mpi(comm, path, snap, outflow_keys(local), prov);
}

}  // namespace mpmfrag::mpi
