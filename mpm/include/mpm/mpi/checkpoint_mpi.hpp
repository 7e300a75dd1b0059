/// @file checkpoint_mpi.hpp
/// mpm-frag checkpoints on MPI ranks (issue 19 item 4; MPI build only): written on N ranks and
/// read on any M ranks, one rank included (the serial driver reads them unchanged).
///
/// Writing (collective, checkpoint_write_mpi.cpp): one file written by every rank together with
/// parallel HDF5 (common/h5_parallel.hpp: a temporary name renamed by rank 0 once every rank
/// succeeded, the space reserved first). A parallel sample sort by (material slot, id)
/// (common/sorted_rows.hpp) gives each rank one block of the file's particle order, and one per
/// material for its state arrays; each rank writes its rows of every dataset (the
/// snapshot part, /mpm_state/particles, materials/<m>, mpi/rank and index) through the serial
/// writer's own code (mpm/checkpoint_rows.hpp), so the file is the one the serial writer makes
/// of all the particles (h5diff-equal, test_mpm_mpi_files.cpp): the serial layout, plus the group
///   /mpm_state/mpi   attrs ranks (N), orb (the tree of cuts, orb.hpp: axis, cell plane and
///                    ranks on the lower side per split, 3 (N - 1) integers in preorder; files
///                    written before 2026-12-07 hold slab cuts instead, attr cuts: the N+1
///                    planes along the grid's longest axis, and still restart);
///                    datasets rank (int32) and index (uint64): per particle of the file, the
///                    rank that held it and its index there; outflow_totals (ranks x 16): each
///                    rank's totals of the particles it removed at the grid edge (pack_totals)
/// which only a restart on N ranks uses. The solver's carried state (SolverResume: time, step,
/// the max signal speed of the next dt, m_min) is the same on every rank (global reductions), as
/// parallel HDF5's attributes require. The outflow records are sorted across the ranks by
/// (removal time, id) too (DomainSolver::local_outflow, outflow_keys: each rank writes its block
/// of /mpm_state/outflow, the field list merged over the ranks); rank 0 writes the series text
/// while the other ranks join with no rows; the drives' loads are the same bits on every rank
/// (their impulses summed in rank order, drive.cpp), attributes as on one rank. A value
/// that is not finite on any rank throws NumericalError on every rank and writes nothing.
///
/// Reading (collective): every rank opens the file and reads its own part of the rows
/// independently (mpm/checkpoint.hpp read_checkpoint_part: rows [n r / M, n (r+1) / M) of the
/// particles, of /mpm_state/mpi and of each material's state among them, the same share of the
/// outflow record's rows; the scalars; rank 0 also the series), so no rank holds every particle
/// or the whole record, and checks the run
/// identity; DomainSolver(comm, setup, layout) then sends each particle to its rank with its order
/// key there (one alltoallv): on N ranks each rank gets back its particles in their order
/// and the tree of cuts (bit-identical continuation); on M != N ranks (or from a serial
/// checkpoint) the tree balances the work and each rank keeps the file order (agreement with the
/// uninterrupted run to round-off: the nodal sums are added in another order).
///
/// Errors while reading (a bad file, another run's checkpoint) are thrown on every rank with the
/// same type and the lowest failing rank's message (exit codes 2 / 4; common/agreed.hpp).
#pragma once
#include <string>

#include "common/provenance.hpp"
#include "common/run_identity.hpp"
#include "mpm/checkpoint.hpp"
#include "mpm/mpi/domain.hpp"

namespace mpmfrag::mpi {

/// Write the checkpoint of `dom`'s state to `path`, every rank its rows (collective;
/// `driver.series`: rank 0's). IoError on every rank if it cannot be written (an earlier file
/// at `path` is kept), NumericalError on every rank for a non-finite value.
void write_checkpoint_mpi(DomainSolver& dom, const std::string& path, const DriverState& driver,
                          const common::Provenance& prov, const std::string& identity);

/// A checkpoint read for a restart on MPI ranks.
struct RestartData {
  Checkpoint ck;  ///< this rank's part, with its part of the outflow record (rank 0 also the series)
  Layout layout;  ///< the ranks that wrote this part's particles (no cuts: a serial checkpoint)
};

/// Every rank reads its part of `path`; InputError on every rank if it is not a checkpoint or
/// another run's (identity `ident`).
RestartData read_checkpoint_mpi(Comm& comm, const std::string& path, const common::RunIdentity& ident);

/// Continue `dom` (built from `rd` by DomainSolver(comm, setup, rd.layout)) with the solver's
/// carried state (collective; instead of initialize()): each rank keeps the part of the outflow
/// record it read (the files sort the record, so any split writes the same files), and the
/// removed particles' totals go to the ranks that held them (as many ranks) or to rank 0.
void resume(DomainSolver& dom, RestartData& rd);

}  // namespace mpmfrag::mpi
