/// @file gravity_tree.hpp
/// The octree of TreeGravity as data plus the three operations on it (build a subtree, its
/// multipole moments, the group walk), shared by the serial tree (gravity.hpp) and the MPI ranks'
/// distributed tree (mpi/gravity_let.hpp), so both run literally the same arithmetic. Equations
/// (spline softening, quadrupoles, the b_max opening rule) in gravity.hpp.
///
/// Geometry, bit for bit the same wherever a cell is built: the root is the cube about the
/// particles' bounding box (tree_root); the child in octant o (bit 0: x > c.x, bit 1: y, bit 2: z,
/// tree_octant) has centre tree_child_centre(c, half, o) and half-size half/2. A cell is split
/// iff it holds more than `bucket` particles and lies above `max_depth` (tree_splits); a sink
/// group is the largest subtree with at most max(group, bucket) particles, or a leaf larger than
/// that (tree_is_group). A leaf's particles are in index order (stable partitions), so a leaf's
/// sums do not depend on how its particles got there.
#pragma once
#include <algorithm>
#include <cstdint>
#include <vector>

#include "ssdem/spheres.hpp"

namespace ssdem {

struct GravityParams {
  double G = 6.674e-11;  ///< [m^3 kg^-1 s^-2]
  double theta = 0.25;   ///< opening angle: rms relative force error <= 1e-3 on piles (test_nbody_gravity_tree)
  int bucket = 8;        ///< max particles per leaf
  int group = 256;       ///< max sinks per group sharing one interaction list (>= bucket; nbody/README.md)
  int max_depth = 40;    ///< subdivision cap (coincident points)
};

struct TreeStats {
  std::size_t nodes = 0, leaves = 0, depth = 0;
  double cell_interactions = 0, particle_interactions = 0;  ///< per particle, mean
  /// per particle, mean: the share of particle_interactions evaluated with the spline kernel (the
  /// group's own spheres and those that may overlap one of them)
  double near_interactions = 0;
};

}  // namespace ssdem

namespace ssdem::tree {

struct Node {
  Vec3 com = Vec3::Zero();
  double mass = 0, bmax = 0, hmax = 0;
  double q[6] = {0, 0, 0, 0, 0, 0};  ///< xx, yy, zz, xy, xz, yz
  Vec3 lo = Vec3::Zero(), hi = Vec3::Zero();  ///< bounding box of the particles
  std::uint32_t start = 0, count = 0;         ///< leaf: particles [start, start + count)
  std::int32_t child = -1;                    ///< first child, children contiguous in octant order
  std::uint8_t nchild = 0;
};

/// A tree and its particles in tree order.
struct Data {
  std::vector<Node> nodes;
  std::vector<std::uint32_t> perm;            ///< tree order -> index of the result arrays
  std::vector<double> px, py, pz, pm, ph;     ///< particles in tree order
  std::vector<std::uint32_t> leaves, groups;  ///< node indices
  std::vector<std::uint32_t> scratch;
  double root_half = 1.0;  ///< kernel length unit: max(root half-size, largest radius)
  TreeStats stats;
};

/// Root cube of particles with bounding box [lo, hi].
inline void tree_root(const Vec3& lo, const Vec3& hi, Vec3& c, double& half) {
  c = 0.5 * (lo + hi);
  half = 0.5 * (hi - lo).maxCoeff() * (1.0 + 1e-12) + 1e-300;
}
inline int tree_octant(const Vec3& x, const Vec3& c) {
  return (x.x() > c.x() ? 1 : 0) | (x.y() > c.y() ? 2 : 0) | (x.z() > c.z() ? 4 : 0);
}
inline Vec3 tree_child_centre(const Vec3& c, double half, int o) {
  const double hh = 0.5 * half;
  return Vec3(c.x() + ((o & 1) ? hh : -hh), c.y() + ((o & 2) ? hh : -hh), c.z() + ((o & 4) ? hh : -hh));
}
inline bool tree_splits(const GravityParams& p, std::uint64_t count, int depth) {
  return count > static_cast<std::uint64_t>(p.bucket) && depth < p.max_depth;
}
inline bool tree_is_group(const GravityParams& p, std::uint64_t count, int depth, bool in_group) {
  return !in_group && (count <= static_cast<std::uint64_t>(std::max(p.group, p.bucket)) || !tree_splits(p, count, depth));
}

/// The opening rule (gravity.hpp): cell c is used as a multipole for every sink inside the box
/// [lo, hi] whose radii are at most hmax. Monotone: a cell accepted for a box is accepted for
/// every box inside it with smaller hmax (IEEE rounding is monotone), which the MPI ranks'
/// export relies on.
inline bool tree_accepts(const Node& c, const Vec3& lo, const Vec3& hi, double hmax, double itheta) {
  const Vec3 dd = (lo - c.com).cwiseMax(c.com - hi).cwiseMax(Vec3::Zero());
  const double rmin2 = dd.squaredNorm();
  const double ropen = std::max(c.bmax * itheta, c.bmax + c.hmax + hmax);
  return rmin2 > ropen * ropen;
}

/// Particle source for the builder: positions, masses, radii indexed by perm values.
struct Source {
  const Vec3* x;
  const double* m;
  const double* s;
};

/// Build the subtree of node `self` over d.perm[start, start + count) (cell centre c, half-size
/// half, at `depth`), appending its descendants to d.nodes and their particles to the tree-order
/// arrays, and compute its moments. Returns nothing; d.nodes[self] is complete afterwards.
void build_subtree(Data& d, const GravityParams& p, const Source& src, std::uint32_t self,
                   std::uint32_t start, std::uint32_t count, const Vec3& c, double half, int depth,
                   bool in_group);
/// Moments (mass, centre of mass, quadrupole, b_max, h_max, box) of node `self` from its
/// particles (leaf) or its children (which must be complete).
void moments(Data& d, std::uint32_t self);
/// Interaction counts of one walk, summed over its sinks (TreeStats divides them by the sinks).
struct WalkTally {
  double cells = 0, parts = 0, near = 0;
};
/// Walk the groups `groups` (node indices) of a complete tree: accelerations (and potentials)
/// of their particles, written to acc[d.perm[t]] (pot[d.perm[t]]), in units G = p.G, lengths and
/// masses as given. `M` is the total mass (nodes[0].mass). Interaction counts are added to
/// `tally`.
void walk(const Data& d, const GravityParams& p, const std::vector<std::uint32_t>& groups,
          std::vector<Vec3>& acc, std::vector<double>* pot, WalkTally& tally);

}  // namespace ssdem::tree
