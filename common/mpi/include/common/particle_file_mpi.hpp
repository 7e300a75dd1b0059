/// @file particle_file_mpi.hpp
/// A particle snapshot (common/particle_file.hpp) written by every rank of a communicator
/// together, MPI build only: each rank passes its own particles; the rows are moved so that each
/// rank holds one block of the file's order (sorted_rows.hpp) and written with collective
/// parallel HDF5 (h5_parallel.hpp). The file equals the one the serial writer makes of all the
/// particles in that order: the same datasets, shapes, dtypes, units and attributes, so the
/// hand-off and h5py read it unchanged. No rank holds more than about 2/P of the particles, plus
/// one column in flight.
#pragma once
#include <string>
#include <vector>

#include "common/particle_file.hpp"
#include "common/sorted_rows.hpp"

namespace common::mpi {

/// Collective. `local`: this rank's particles (time, step and grid equal on every rank, the same
/// fields in the same order); keys[i]: the file order of local row i (rows sorted by key).
/// Throws IoError on every rank if the file cannot be written (an earlier file is left as it
/// was); std::logic_error if the ranks' field lists differ. Rank 0 writes the XDMF sidecar.
void write_particle_snapshot_mpi(Comm& comm, const std::string& path, const ParticleSnapshot& local,
                                 const std::vector<RowKey>& keys, const Provenance& prov);

/// The pieces, for writers that add groups of their own (mpm-frag's checkpoints):
/// collective: `local` moved to this rank's block of the file order (`plan`, made from the keys);
/// std::logic_error on every rank if the ranks' field lists differ (`path` names the file).
ParticleSnapshot sorted_block(Comm& comm, const SortedRows& plan, const ParticleSnapshot& local,
                              const std::string& path);
/// Bytes to reserve for a particle file of `total` rows with the fields of `s` (data plus a
/// generous allowance for HDF5's metadata: object headers, attributes, provenance).
std::uintmax_t particle_file_bytes(const ParticleSnapshot& s, std::size_t total);

}  // namespace common::mpi
