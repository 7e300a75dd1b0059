/// @file sphere_summary_mpi.cpp
/// SphereSummary over the ranks' blocks (sphere_summary_mpi.hpp).
#include "ssdem/mpi/sphere_summary_mpi.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "common/exact_sum_mpi.hpp"
#include "ordered_bits.hpp"

namespace ssdem::mpi {
double kth_smallest(Comm& comm, const std::vector<double>& mine, std::uint64_t k) {
  std::vector<std::uint64_t> key(mine.size());
  std::uint64_t lo = ~std::uint64_t{0}, hi = 0;
  for (std::size_t i = 0; i < mine.size(); ++i) {
    key[i] = key_of(mine[i]);
    lo = std::min(lo, key[i]);
    hi = std::max(hi, key[i]);
  }
  MPI_Allreduce(MPI_IN_PLACE, &lo, 1, MPI_UINT64_T, MPI_MIN, comm.c);
  MPI_Allreduce(MPI_IN_PLACE, &hi, 1, MPI_UINT64_T, MPI_MAX, comm.c);
  // the smallest K in [lo, hi] with count(key <= K) > k, by bisection
  while (lo < hi) {
    const std::uint64_t mid = lo + (hi - lo) / 2;
    long long c = 0;
    for (std::uint64_t x : key) c += x <= mid;
    comm.sum(&c, 1);
    if (static_cast<std::uint64_t>(c) > k)
      hi = mid;
    else
      lo = mid + 1;
  }
  return value_of(lo);
}

SphereSummary summarise(Comm& comm, const Spheres& b) {
  SphereSummary s;
  common::ExactSum M, mx[3];
  double ext[4] = {0.0, 0.0, 0.0, -INFINITY};  // mmax, smax, vmax, -smin
  double two[2] = {INFINITY, INFINITY};        // this rank's two smallest masses
  for (std::size_t i = 0; i < b.size(); ++i) {
    const double m = b.m[i];
    offer_smallest(m, two[0], two[1]);
    ext[0] = std::max(ext[0], m);
    ext[1] = std::max(ext[1], b.s[i]);
    ext[2] = std::max(ext[2], b.v[i].norm());
    ext[3] = std::max(ext[3], -b.s[i]);
    M += m;
    for (int c = 0; c < 3; ++c) mx[c] += m * b.x[i][c];
  }
  long long n = static_cast<long long>(b.size());
  comm.sum(&n, 1);
  s.n = static_cast<std::size_t>(n);
  comm.max(ext, 4);
  s.mmax = ext[0];
  s.smax = ext[1];
  s.vmax = ext[2];
  s.smin = -ext[3];
  // the two smallest of all: the serial scan's result whatever the order (m2 = m1 when shared)
  for (double m : comm.allgather(two, 2)) offer_smallest(m, s.m1, s.m2);
  common::ExactSum* sums[4] = {&M, &mx[0], &mx[1], &mx[2]};
  common::mpi::allreduce(comm, sums, 4);
  s.M = M.value();
  for (int c = 0; c < 3; ++c) s.com[c] = mx[c].value() / s.M;
  double R = 0.0;
  for (std::size_t i = 0; i < b.size(); ++i) R = std::max(R, (b.x[i] - s.com).norm() + b.s[i]);
  s.R = comm.max(R);
  if (s.n > 0) s.m_median = kth_smallest(comm, b.m, s.n / 2);
  return s;
}

}  // namespace ssdem::mpi
