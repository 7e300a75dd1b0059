/// @file sphere_summary_mpi.hpp
/// The SphereSummary (sphere_summary.hpp) of the spheres that the ranks hold in blocks, collective
/// (MPI build): every rank gets the record summarise() gives for all the spheres in one set, the
/// same bits whatever the number of ranks and the split. Extremes by max/min reductions, the two
/// smallest masses from every rank's two (allgather, 2 values per rank), the mass and centre of
/// mass by exact sums (common/mpi/exact_sum_mpi.hpp), the upper median mass by collective
/// selection: bisection on the masses' ordered bit patterns, one allreduce of a count per halving
/// (at most 64), O(n_rank) work each; no rank holds more than its block.
#pragma once
#include "ssdem/mpi/comm.hpp"
#include "ssdem/sphere_summary.hpp"

namespace ssdem::mpi {

SphereSummary summarise(Comm& comm, const Spheres& block);

/// Collective: the k-th smallest (0-based) of the values that the ranks hold together (k below
/// their total count; none NaN). Exact: one of the values, bit for bit.
double kth_smallest(Comm& comm, const std::vector<double>& mine, std::uint64_t k);

}  // namespace ssdem::mpi
