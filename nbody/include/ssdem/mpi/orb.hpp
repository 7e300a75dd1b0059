/// @file orb.hpp
/// Orthogonal recursive bisection (ORB) of the spheres among the MPI ranks by particle count
/// (Salmon 1991; pkdgrav's domain decomposition, Stadel 2001 §2.3): the rank range [r0, r1) and
/// its spheres are split along the longest axis of their bounding box, midway between the
/// coordinates that put round(n * floor(nr/2) / nr) spheres on the lower side, recursively, until one rank is
/// left. The cuts are kept as a binary tree: a position belongs to the rank of the leaf it
/// descends to (x[axis] < cut: lower side), so ownership between rebalances is a lookup by
/// position and a sphere may move to any rank in one step (no neighbour-only assumption).
/// Ties on a cut go to the upper side (the split count is then off by the tied spheres).
/// Determinism: built from positions in global-index order with ties broken by index, so every
/// rank builds the same tree from the same positions.
#pragma once
#include <vector>

#include "ssdem/spheres.hpp"

namespace ssdem::mpi {

class OrbTree {
 public:
  /// ORB of `x` (all spheres, global order) among `nranks` ranks.
  OrbTree(const std::vector<Vec3>& x, int nranks);
  /// One rank owning all space (before the first decomposition).
  OrbTree() = default;
  /// The rank owning position p.
  int owner(const Vec3& p) const;

 private:
  struct Node {
    int axis = 0;
    double cut = 0;
    int lo = -1, hi = -1;  ///< children; -1: leaf
    int rank = 0;
  };
  int build(const std::vector<Vec3>& x, std::vector<std::size_t>& idx, std::size_t b, std::size_t e, int r0,
            int r1);
  std::vector<Node> nodes_;
};

}  // namespace ssdem::mpi
