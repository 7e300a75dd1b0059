/// @file sphere_order.hpp
/// The order of the spheres in memory (`run.sort_every`, the serial driver run.cpp).
///
/// The contact pair loop, the per-sphere sums and the kicks read the arrays of both members of
/// every pair; spheres numbered in the order of the input file (the hand-off's cell order) hold
/// a remnant's touching spheres thousands of rows apart once the debris has reassembled (on the
/// 2.42 km 500 m debris at t = 2 h: median |i - j| = 1 859 over touching pairs, 11 along a
/// Morton curve), and each pair costs cache misses. The serial driver therefore renumbers the
/// spheres along a Morton (Z-order) curve of their positions at a block boundary every
/// `run.sort_every` base steps (and at the start), as LAMMPS (atom_modify sort) and PKDGRAV do:
///   key(x) = interleave(q_x, q_y, q_z),  q_d = floor((x_d - lo_d) / L * (2^21 - 1)),
/// with lo the corner and L the longest edge of the positions' bounding box; equal keys keep
/// their previous order (stable), so the order is a function of the state and the previous order
/// (which checkpoints record), never of the thread count.
///
/// A renumbering is a restart from the permuted state (Simulation(SimState)): the physics is
/// unchanged, but the per-sphere sums run over the partners in the new index order, so the
/// run differs from an unsorted one by round-off (chaos amplifies it: the chaos floor, not an
/// error). Repeated runs, restarts and thread counts still give the same bits. Files keep the
/// file order (row g is the input's sphere g): SphereOrder maps storage to file rows for every
/// snapshot and checkpoint, and a checkpoint records the storage order
/// (/ssdem_state/sphere_order) so that a restart continues bit-identically.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "ssdem/simulation.hpp"

namespace ssdem {

/// The Morton order of the positions: perm[k] is the index in `x` of the sphere that goes to k.
/// Non-finite coordinates sort as the box corner (the state check reports them).
std::vector<std::uint32_t> morton_order(const std::vector<Vec3>& x);
/// True if perm holds each of 0 .. n-1 once.
bool is_permutation_of(const std::vector<std::uint32_t>& perm, std::size_t n);
/// Renumbers every per-sphere array (carried fields too): new index k holds old index perm[k].
void permute_spheres(Spheres& sp, const std::vector<std::uint32_t>& perm);
/// The same for a state: the spheres and a, alpha, ag, a_prev, alpha_prev, level, tau_prev and
/// sphere_order where present. History records and bonds are keyed by sphere id: unchanged.
void permute_state(SimState& st, const std::vector<std::uint32_t>& perm);

/// The file row of each stored sphere: row(k) = g when storage index k holds the input's sphere g.
class SphereOrder {
 public:
  explicit SphereOrder(std::size_t n = 0);
  bool identity() const { return identity_; }
  const std::vector<std::uint32_t>& rows() const { return row_; }
  /// After permute_state(st, perm): row'[k] = row[perm[k]].
  void renumber(const std::vector<std::uint32_t>& perm);
  /// Copies in file order (for snapshots).
  Spheres to_file(const Spheres& sp) const;
  /// A state in file order with sphere_order = rows() (for checkpoints; empty if the identity).
  SimState to_file(SimState st) const;
  /// A checkpoint's state (file order, with sphere_order or without): permuted to the recorded
  /// storage order; returns that order. InputError naming `path` if sphere_order is not a
  /// permutation of the sphere rows.
  static SphereOrder from_file(SimState& st, const std::string& path);

 private:
  std::vector<std::uint32_t> row_;
  bool identity_ = true;
};

}  // namespace ssdem
