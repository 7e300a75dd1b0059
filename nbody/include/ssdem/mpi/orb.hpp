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
/// Collective build (OrbTree::collective): the same tree from each rank's own positions, no rank
/// holding all of them (orb_collective.cpp): per level of the tree, one allreduce of every node's
/// bounding box and count; the split value, the want-th smallest coordinate, by bisection on the
/// coordinates' ordered bit patterns (one allreduce of counts per halving, at most 64); then one
/// allreduce of the count below it and the largest coordinate below it, which give the cut exactly
/// as above. O(n_own) work per halving, O(nodes of the level) bytes per allreduce.
#pragma once
#include <utility>
#include <vector>

#include "ssdem/mpi/comm.hpp"
#include "ssdem/spheres.hpp"

namespace ssdem::mpi {

class OrbTree {
 public:
  /// ORB of `x` (all spheres, global order) among `nranks` ranks.
  OrbTree(const std::vector<Vec3>& x, int nranks);
  /// One rank owning all space (before the first decomposition).
  OrbTree() = default;
  /// Collective: the tree OrbTree(x of all ranks' spheres, comm.size) builds, from this rank's
  /// own positions only (file comment).
  static OrbTree collective(Comm& comm, const std::vector<Vec3>& own);
  /// The cuts in depth-first order (lower side first): (axis, cut) of every inner node, to compare
  /// two trees.
  std::vector<std::pair<int, double>> cuts() const;
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
