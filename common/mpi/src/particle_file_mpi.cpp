/// @file particle_file_mpi.cpp
/// Implementation of common/particle_file_mpi.hpp (the header states the contract).
#include "common/particle_file_mpi.hpp"

#include <stdexcept>

#include "common/agreed.hpp"
#include "common/h5_parallel.hpp"
#include "common/status.hpp"

namespace common::mpi {

ParticleSnapshot sorted_block(Comm& comm, const SortedRows& plan, const ParticleSnapshot& local,
                              const std::string& path) {
  std::string fields;  // every rank writes the same datasets: their names and widths agree
  for (const Field& f : local.fields)  // names, widths, units and descriptions: HDF5 metadata, the same everywhere
    fields += f.name + ":" + std::to_string(f.ncomp) + ":" + f.unit + ":" + f.description + ";";
  if (!comm.all(comm.bcast(fields) == fields))
    throw std::logic_error("write_particle_snapshot_mpi: the ranks' field lists differ (" + path + ")");
  ParticleSnapshot block;
  block.time = local.time;
  block.step = local.step;
  block.grid = local.grid;
  block.id = plan.move(local.id, 1);
  block.position = plan.move(local.position, 3);
  block.velocity = plan.move(local.velocity, 3);
  block.mass = plan.move(local.mass, 1);
  block.volume = plan.move(local.volume, 1);
  block.size = plan.move(local.size, 3);
  block.material = plan.move(local.material, 1);
  for (const Field& f : local.fields)
    block.fields.push_back(Field{f.name, f.unit, f.ncomp, plan.move(f.values, f.ncomp), f.description});
  return block;
}

std::uintmax_t particle_file_bytes(const ParticleSnapshot& s, std::size_t total) {
  std::uintmax_t row = 8 + 24 + 24 + 8 + 8 + 24 + 4;
  for (const Field& f : s.fields) row += 8 * f.ncomp;
  return row * total + (std::uintmax_t{1} << 20) + 16384 * (7 + s.fields.size());
}

void write_particle_snapshot_mpi(Comm& comm, const std::string& path, const ParticleSnapshot& local,
                                 const std::vector<RowKey>& keys, const Provenance& prov) {
  if (keys.size() != local.count()) throw std::logic_error("write_particle_snapshot_mpi: one key per particle");
  const SortedRows plan(comm, keys);
  const ParticleSnapshot block = sorted_block(comm, plan, local, path);
  ParallelFile file(comm, path, particle_file_bytes(local, plan.total()));
  const bool ok = write_particle_content(file.id(), block, prov, file.rows(plan.offset(), plan.total()));
  file.commit(ok);
  agreed(comm, [&] {  // the sidecar: a failure there fails every rank alike
    if (comm.rank == 0) write_particle_xdmf(path, block, plan.total());
  });
}

}  // namespace common::mpi
