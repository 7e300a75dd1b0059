/// @file sphere_order.hpp
/// The order of the spheres in memory (`run.sort_every`, the serial driver run.cpp).
///
/// The contact pair loop, the per-sphere sums and the kicks read the arrays of both members of
/// every pair; spheres numbered in the order of the input file (the hand-off's cell order) hold
/// a remnant's touching spheres thousands of rows apart once the debris has reassembled (on the
/// 2.42 km 500 m debris at t = 2 h: median |i - j| = 1 859 over touching pairs). The serial
/// driver therefore renumbers the spheres by the cells of a grid of edge c = 2 s_max over their
/// current positions, in the order z, y, x (x fastest), at the start and at a block boundary
/// every `run.sort_every` base steps, as LAMMPS (atom_modify sort, by bins) does:
///   key(x) = (q_z, q_y, q_x),  q_d = floor((x_d - lo_d) / c)  (at most 2^21 - 1),
/// with lo the corner of the positions' bounding box; equal keys keep their previous order
/// (stable). A sphere's partners then lie in three runs of memory (its own row of cells and
/// the rows in front and behind), which the pair loop walks as sequential streams; measured, this
/// beat a Morton (Z-order) curve by 5-8 % on a reassembled remnant and by 7-16 % on the
/// hand-off's young debris (nbody/README.md, "Sphere order in memory").
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

/// The cell order of the positions (cells of edge `cell`): perm[k] is the index in `x` of the
/// sphere that goes to k. Non-finite coordinates sort as the box corner (the state check
/// reports them); cell <= 0 keeps the order.
std::vector<std::uint32_t> cell_order(const std::vector<Vec3>& x, double cell);
/// cell_order(sp.x, 2 max s).
std::vector<std::uint32_t> cell_order(const Spheres& sp);
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
