/// @file fof.hpp
/// Friends-of-friends clumps on sphere *surfaces*.
///
/// Two spheres i, j are friends if the gap between their surfaces is below the linking length:
///     |x_i - x_j| - r_i - r_j < eps                                            (1)
/// and a clump is a connected component of the friend graph (Davis et al. 1985 FOF, applied to
/// surfaces as pkdgrav's `rpa` does; ssdem.md §5.1: rpa links when |x_i - x_j| <= L (r_i + r_j),
/// L = 1.1, i.e. a gap of 0.1 (r_i + r_j) = 0.2 r for equal spheres; our default eps = 0.2 x the
/// median radius reproduces that for a monodisperse set). Touching or overlapping spheres
/// (gap <= 0) are always friends when eps > 0.
///
/// Algorithm: hashed cell list with cell edge h = 2 r_max + eps (so every friend pair lies in the
/// same or a neighbouring cell), cells found by sorting integer cell keys (no bounding-box grid,
/// so escaping ejecta far away cost nothing), then a concurrent union–find over the 13 forward
/// neighbour cells + the own cell (OpenMP). Roots are linked smaller-index-wins, so the root of a
/// component is its smallest sphere index whatever the thread schedule: the result is
/// deterministic and independent of the thread count. O(N log N) for the sort, O(N) otherwise.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

namespace analysis {

/// Clumps of a sphere set, ordered by mass (descending; ties: smallest member index first).
struct FofResult {
  std::vector<std::int64_t> clump_of;     ///< per sphere: clump index (0 = most massive)
  std::vector<double> clump_mass;         ///< per clump [kg]
  std::vector<std::int64_t> clump_count;  ///< per clump: number of spheres
  std::vector<std::int64_t> clump_first;  ///< per clump: smallest member sphere index

  std::size_t count() const { return clump_mass.size(); }
  /// Number of clumps that are single spheres.
  std::size_t singles() const;
};

/// eps = fraction x median radius (the default linking length).
double default_link_length(const double* radius, std::size_t n, double fraction);

/// Friends-of-friends on surfaces, eq. (1). `position` is N*3, `radius` and `mass` N.
/// `eps` may be 0 or negative (then only spheres overlapping by more than |eps| link).
FofResult friends_of_friends(const double* position, const double* radius, const double* mass,
                             std::size_t n, double eps);

}  // namespace analysis
