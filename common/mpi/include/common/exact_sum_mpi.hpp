/// @file exact_sum_mpi.hpp
/// Exact sums (common/exact_sum.hpp) added over the ranks of a communicator (MPI build only):
/// one MPI_SUM of the accumulators' normalised limbs, which is exact and associative, so every
/// rank gets the bits a single accumulator of all the ranks' terms would give, whatever the
/// number of ranks and whichever rank held which term.
#pragma once
#include <cstddef>

#include "common/exact_sum.hpp"
#include "common/mpi_comm.hpp"

namespace common::mpi {

/// Collective: replace each of the `n` accumulators by its sum over the ranks (the same `n` and
/// order on every rank). Fewer than 2^31 ranks.
void allreduce(Comm& comm, ExactSum* const* sums, std::size_t n);
/// Collective: one accumulator.
inline void allreduce(Comm& comm, ExactSum& sum) {
  ExactSum* p = &sum;
  allreduce(comm, &p, 1);
}

}  // namespace common::mpi
