/// @file exact_sum_mpi.cpp
/// Implementation of common/exact_sum_mpi.hpp.
#include "common/exact_sum_mpi.hpp"

#include <algorithm>
#include <cstdint>
#include <vector>

namespace common::mpi {

void allreduce(Comm& comm, ExactSum* const* sums, std::size_t n) {
  constexpr int L = ExactSum::kLimbs;
  std::vector<std::int64_t> limbs(n * L);
  std::vector<double> special(n);
  std::vector<int> flags(n);
  for (std::size_t k = 0; k < n; ++k) {
    const auto l = sums[k]->limbs();
    std::copy(l.begin(), l.end(), limbs.begin() + static_cast<std::ptrdiff_t>(k * L));
    special[k] = sums[k]->special();
    flags[k] = sums[k]->has_special() ? 1 : 0;
  }
  const int nl = static_cast<int>(limbs.size()), ns = static_cast<int>(n);
  MPI_Allreduce(MPI_IN_PLACE, limbs.data(), nl, MPI_INT64_T, MPI_SUM, comm.c);
  MPI_Allreduce(MPI_IN_PLACE, special.data(), ns, MPI_DOUBLE, MPI_SUM, comm.c);  // inf/NaN: any order
  MPI_Allreduce(MPI_IN_PLACE, flags.data(), ns, MPI_INT, MPI_MAX, comm.c);
  comm.bytes_sent += static_cast<double>(limbs.size() * sizeof(std::int64_t) + n * (sizeof(double) + sizeof(int)));
  for (std::size_t k = 0; k < n; ++k)
    *sums[k] = ExactSum::from_limbs(limbs.data() + k * L, special[k], flags[k] != 0);
}

}  // namespace common::mpi
