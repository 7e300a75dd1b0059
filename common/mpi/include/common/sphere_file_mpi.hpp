/// @file sphere_file_mpi.hpp
/// A sphere file (common/sphere_file.hpp) written by every rank of a communicator together, MPI
/// build only, as particle_file_mpi.hpp does for particle files. File row g holds the sphere of
/// index g (0..N-1, the one-rank order); the rows move to fixed blocks (rank r: rows
/// [dense_first(N, P, r), dense_first(N, P, r + 1)); sorted_rows.hpp) and every dataset is written
/// with one hyperslab per rank. The file equals the one the serial writer makes of all the spheres
/// in index order. No rank holds more than its block of rows plus one column in flight.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "common/sorted_rows.hpp"
#include "common/sphere_file.hpp"

namespace common::mpi {

/// This rank's spheres moved to its block of the file, collective. `local`: its spheres (core
/// arrays and fields, the same field list on every rank), `row[i]` the file row of local sphere i;
/// `block_fields`: fields whose values this rank holds already for exactly its block (in row
/// order), placed before local's fields in the file (ssdem-grav's carried fields).
/// std::logic_error on every rank if the ranks' field lists differ (`path` names the file).
struct SphereBlock {
  SortedRows plan;  ///< the move (its offset() and total() are the block's)
  SphereSet set;    ///< the block's rows
  SphereBlock(Comm& comm, const SphereSet& local, const std::vector<std::uint64_t>& row,
              const std::vector<Field>& block_fields, const std::string& path);

 private:
  struct Checked;  ///< the rows' keys and the blocks' splitters, after every rank's input was checked
  static Checked check(Comm& comm, const SphereSet& local, const std::vector<std::uint64_t>& row,
                       const std::vector<Field>& block_fields, const std::string& path);
  SphereBlock(Comm& comm, const Checked& c, const SphereSet& local, const std::vector<Field>& block_fields);
};

/// Bytes to reserve for a sphere file of `total` rows with the fields of `s` (data plus an
/// allowance for HDF5's metadata).
std::uintmax_t sphere_file_bytes(const SphereSet& s, std::size_t total);

/// A rank's part of a sphere file's bonds (/bonds, common/bond_file.hpp): each bond on exactly one
/// rank, with its file row and the rows of its two spheres.
struct BondRows {
  BondTable table;                   ///< the rank's bonds, with their broken column
  std::vector<std::uint64_t> row;    ///< file row of each (0..B-1 over all the ranks)
  std::vector<std::uint64_t> index;  ///< 2 per bond: the file rows of its spheres id_a, id_b
};

/// This rank's bonds moved to its block of /bonds (collective; dense blocks of the B rows).
struct BondBlock {
  std::size_t offset = 0, total = 0;
  BondTable table;
  std::vector<std::uint64_t> index;
  BondBlock(Comm& comm, const BondRows& local);
};

/// Collective: write the sphere file `path` (see SphereBlock for the arguments) with the bonds
/// `bonds` if given (on every rank alike). IoError on every rank if it cannot be written (an
/// earlier file is left as it was); the ranks' sphere sets must hold no bonds themselves
/// (std::logic_error). Rank 0 writes the XDMF sidecar.
void write_sphere_set_mpi(Comm& comm, const std::string& path, const SphereSet& local,
                          const std::vector<std::uint64_t>& row, const std::vector<Field>& block_fields,
                          const Provenance& prov, const BondRows* bonds = nullptr);

}  // namespace common::mpi
