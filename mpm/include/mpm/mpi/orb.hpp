/// @file orb.hpp
/// Orthogonal recursive bisection (ORB) of mpm-frag's background grid among MPI ranks (issue 19,
/// item 3; MPI build only). Cells and node planes share their indices: cell c along an axis lies
/// between nodes c and c + 1, c = floor((x - o) / h) clamped to [0, S - 1] with S nodes, so a
/// partition of the cells [0, S_x) x [0, S_y) x [0, S_z) is also one of the nodes.
///
/// ## The bisection (orb_cuts)
/// A node of the tree holds a box B of cells and the ranks [r_0, r_0 + n). With n > 1 it is cut
/// along the longest axis a of B (the lowest axis on a tie) into a lower box for n_l = floor(n/2)
/// ranks and an upper box for n - n_l ranks, at the plane P whose cumulative weight
/// S(P) = sum_{lo_a <= c < P} w(c) (w(c): the weight of the cells of B in plane c) is nearest the
/// target W_B n_l / n (the first P* with S(P*) >= target, or P* - 1 when that is nearer), clamped
/// so that each side keeps W n_side planes when B is at least W n planes wide along a (then every
/// later cut is feasible along a alone), else W ceil(n_side / c) planes with c the number of
/// W x W columns the other two axes of B offer (a side of n_side ranks can still be cut into
/// n_side boxes), else W planes (W = min_width). So the tree, and every rank's box, follows from
/// the weights alone: the same on every rank and every run. A box of n > 1 ranks narrower than
/// 2W on every axis cannot be cut: common::InputError (the set-up: too many ranks; a
/// rebalancing keeps its tree instead, DomainSolver::rebalance).
/// One weight histogram per level of the tree: log2(R) collective reductions for R ranks.
/// On two ranks the one cut is the slab cut of the previous decomposition (same rule), so
/// two-rank runs keep their results.
///
/// ## Boxes
/// Rank r OWNS the cells (and nodes) of its leaf box O_r and HOLDS H_r = O_r grown by `halo`
/// nodes on every side, clipped to the grid: a uGIMP particle of cell c touches nodes c - 1 ..
/// c + 2 (linear: c .. c + 1), so H = 2 holds every node its particles touch. The halo swap
/// (halo.cpp) sums each held node's partial values at its owner and sends the sum back.
/// With W = max(2H, 2g + 1 - H) (g: the face conditions' ghost layers) a symmetry layer's mirror
/// source lies in the box that holds the layer, as with slabs.
#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace mpmfrag::mpi {

/// A box of cells (or nodes) [lo, hi) per axis, global indices.
struct Box {
  Eigen::Vector3i lo = Eigen::Vector3i::Zero(), hi = Eigen::Vector3i::Zero();
  bool empty() const { return (hi.array() <= lo.array()).any(); }
  long long size() const;
  bool contains(const Eigen::Vector3i& c) const { return (c.array() >= lo.array()).all() && (c.array() < hi.array()).all(); }
  Box intersect(const Box& o) const { return {lo.cwiseMax(o.lo), hi.cwiseMin(o.hi)}; }
  bool operator==(const Box& o) const { return lo == o.lo && hi == o.hi; }
};

/// The decomposition: a binary tree of cuts over the grid's cells (file comment).
struct Orb {
  /// One internal node of the tree: cut along `axis` at cell plane `cut`, the lower side to its
  /// first `left` ranks. Stored in preorder (a node, its lower subtree, its upper subtree).
  struct Split {
    int axis = 0, cut = 0, left = 1;
    bool operator==(const Split& o) const { return axis == o.axis && cut == o.cut && left == o.left; }
  };
  Eigen::Vector3i shape = Eigen::Vector3i::Zero();  ///< grid nodes per axis
  int halo = 2;                                     ///< H: ghost nodes a side
  int min_width = 4;                                ///< W: fewest planes per side of a cut
  int nranks = 1;
  std::vector<Split> split;                         ///< nranks - 1 splits, preorder

  int ranks() const { return nranks; }
  /// The rank owning cell c (descends the tree: O(log R) for a balanced tree).
  int owner(const Eigen::Vector3i& c) const;
  /// Every rank's own box (computed by set()).
  const std::vector<Box>& own() const { return own_; }
  /// The box rank r holds: its own box grown by `halo` nodes a side, clipped to the grid.
  Box held(int r) const;
  /// Set the tree (R = split.size() + 1) and compute the boxes; false when it is not a valid
  /// partition of the grid (an axis outside 0..2, a cut leaving a side narrower than min_width, a
  /// `left` outside [1, n - 1], splits too few or too many), with the tree left as it was.
  bool set(std::vector<Split> s);
  /// (axis, cut, left) per split: the /mpm_state/mpi "orb" attribute of checkpoints.
  std::vector<std::int64_t> flat() const;
  static std::vector<Split> unflat(const std::vector<std::int64_t>& v);
  /// Slabs along `axis` at cell planes cut[1..R-1] (cut[0] = 0, cut[R] = S_axis) as a tree: the
  /// checkpoints written before the boxes stored slab cuts.
  static std::vector<Split> slabs(int axis, const std::vector<int>& cut);
  /// Largest own box over the mean, in cells (for the log), and a short description.
  std::string describe() const;
  bool operator==(const Orb& o) const { return nranks == o.nranks && split == o.split; }

 private:
  std::vector<Box> own_;
};

/// A weight histogram asked for by orb_cuts: the weights of the cells in `box` per plane along
/// `axis` (box.hi[axis] - box.lo[axis] values). `locate(c)` says which request of the same call
/// cell c belongs to (-1: none), so that a caller walks its particles once per level.
struct OrbRequest {
  Box box;
  int axis = 0;
};
using OrbHistogram = std::function<std::vector<std::vector<long long>>(
    const std::vector<OrbRequest>&, const std::function<int(const Eigen::Vector3i&)>& locate)>;

/// The ORB of a grid of `shape` nodes for `ranks` ranks from the weights `hist` returns (one call
/// per level of the tree). Throws common::InputError when the grid cannot give every rank a box
/// at least `min_width` planes wide along its cuts.
Orb orb_cuts(const Eigen::Vector3i& shape, int ranks, int halo, int min_width, const OrbHistogram& hist);

/// The plane P in [lo, hi] (relative to the histogram's first plane, 0 <= lo <= hi <= size) whose
/// cumulative weight sum_{c < P} w(c) is nearest total * num / den (the first crossing P* or
/// P* - 1 when that is nearer; exact integer arithmetic), clamped to [lo, hi].
int nearest_cut(const std::vector<long long>& w, long long num, long long den, int lo, int hi);

}  // namespace mpmfrag::mpi
