/// @file slabs.cpp
/// Slab decomposition of the background grid (mpm/mpi/domain.hpp): cuts balancing the particle
/// count per rank,  P_r = min { P : sum_{c < P} n(c) >= r N / R }  with every slab at least W
/// planes wide, the owner of a cell, and the box (owned planes plus H ghost planes per side,
/// clipped to the grid) a rank holds.
#include <algorithm>
#include <string>

#include "common/status.hpp"
#include "mpm/mpi/domain.hpp"

namespace mpmfrag::mpi {

int Slabs::owner(int c) const {
  // the last r with cut[r] <= c
  const auto it = std::upper_bound(cut.begin() + 1, cut.end() - 1, c);
  return static_cast<int>(it - cut.begin()) - 1;
}

Subdomain Slabs::box(int r, const common::GridInfo& g) const {
  Subdomain s;
  s.shape = g.shape;
  const int lo = std::max(0, cut[r] - halo), hi = std::min(g.shape[axis], cut[r + 1] + halo);
  s.lo[axis] = lo;
  s.shape[axis] = hi - lo;
  s.own_axis = axis;
  s.own_lo = cut[r];
  s.own_hi = cut[r + 1];
  return s;
}

std::vector<int> balanced_cuts(const std::vector<long long>& count, int ranks, int min_width) {
  const int planes = static_cast<int>(count.size());
  if (ranks < 1 || planes < ranks * min_width)
    throw common::InputError("the grid has " + std::to_string(planes) + " node planes along its longest axis: at most " +
                             std::to_string(planes / min_width) + " MPI ranks (" + std::to_string(min_width) +
                             " planes per rank), not " + std::to_string(ranks) + "; use fewer ranks or a finer [grid] cell_size");
  long long total = 0;
  for (long long n : count) total += n;
  std::vector<int> cut(ranks + 1, 0);
  cut[ranks] = planes;
  long long cum = 0;
  int c = 0;
  for (int r = 1; r < ranks; ++r) {
    // smallest P with sum_{c < P} n(c) >= r N / R (integer test: R * cum >= r * N)
    while (c < planes && static_cast<__int128>(cum) * ranks < static_cast<__int128>(total) * r) cum += count[c++];
    cut[r] = std::clamp(c, cut[r - 1] + min_width, planes - (ranks - r) * min_width);
  }
  return cut;
}

}  // namespace mpmfrag::mpi
