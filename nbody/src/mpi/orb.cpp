/// @file orb.cpp
/// Orthogonal recursive bisection (orb.hpp).
#include "ssdem/mpi/orb.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace ssdem::mpi {

OrbTree::OrbTree(const std::vector<Vec3>& x, int nranks) {
  std::vector<std::size_t> idx(x.size());
  std::iota(idx.begin(), idx.end(), std::size_t{0});
  nodes_.reserve(2 * static_cast<std::size_t>(nranks));
  build(x, idx, 0, idx.size(), 0, nranks);
}

int OrbTree::build(const std::vector<Vec3>& x, std::vector<std::size_t>& idx, std::size_t b, std::size_t e,
                   int r0, int r1) {
  const int self = static_cast<int>(nodes_.size());
  nodes_.push_back(Node{});
  nodes_[self].rank = r0;
  if (r1 - r0 == 1) return self;
  const int nr = r1 - r0, nl = nr / 2;
  const std::size_t n = e - b;
  int axis = 0;
  double cut = 0.0;
  std::size_t t = b;
  if (n > 0) {
    Vec3 lo = x[idx[b]], hi = x[idx[b]];
    for (std::size_t k = b; k < e; ++k) {
      lo = lo.cwiseMin(x[idx[k]]);
      hi = hi.cwiseMax(x[idx[k]]);
    }
    (hi - lo).maxCoeff(&axis);
    std::sort(idx.begin() + b, idx.begin() + e, [&](std::size_t p, std::size_t q) {
      const double a = x[p][axis], c = x[q][axis];
      return a < c || (a == c && p < q);
    });
    const std::size_t want = static_cast<std::size_t>(
        std::llround(static_cast<double>(n) * nl / static_cast<double>(nr)));
    if (want >= n) {
      cut = std::nextafter(x[idx[e - 1]][axis], INFINITY);
      t = e;
    } else {
      t = b + want;
      const double up = x[idx[t]][axis];
      while (t > b && x[idx[t - 1]][axis] == up) --t;  // ties go to the upper side
      // midway between the two sides: spheres near the cut move the least distance before changing rank
      cut = t > b ? 0.5 * (x[idx[t - 1]][axis] + up) : up;
      if (!(cut > (t > b ? x[idx[t - 1]][axis] : -INFINITY))) cut = up;  // midpoint rounded down onto the lower side
    }
  }
  nodes_[self].axis = axis;
  nodes_[self].cut = cut;
  const int lo_child = build(x, idx, b, t, r0, r0 + nl);
  const int hi_child = build(x, idx, t, e, r0 + nl, r1);
  nodes_[self].lo = lo_child;
  nodes_[self].hi = hi_child;
  return self;
}

int OrbTree::owner(const Vec3& p) const {
  if (nodes_.empty()) return 0;
  int k = 0;
  while (nodes_[k].lo >= 0) k = p[nodes_[k].axis] < nodes_[k].cut ? nodes_[k].lo : nodes_[k].hi;
  return nodes_[k].rank;
}

}  // namespace ssdem::mpi
