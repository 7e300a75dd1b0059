/// @file gravity_let.hpp
/// Self-gravity over MPI ranks without replicated positions: the one-rank octree
/// (gravity_tree.hpp) split among the ranks along its own cells, with locally essential trees
/// (Warren & Salmon 1993, "A parallel hashed oct-tree N-body algorithm", SC'93; Salmon 1991),
/// giving every sphere the force of the one-rank tree bit for bit.
///
/// Why it is the same tree. The one-rank tree is a function of the positions only: its root
/// cube (tree_root) from the bounding box of all spheres, a cell split iff it holds more than
/// `bucket` spheres, sink groups the largest subtrees of at most max(group, bucket) spheres, a
/// leaf's spheres in global-index order. All of that is decided here from global counts, never
/// from which rank holds a sphere; so each rank can build whole groups and their subtrees
/// exactly as one rank does, and the group walk (tree::walk) meets the same cells and particles
/// in the same order.
///
/// Per evaluation (DistributedTree::compute):
///  1. One allreduce (max) of the ranks' bounding boxes, largest radius and a non-finite flag:
///     the root cube, as one rank computes it.
///  2. The top tree: the cells above the sink groups, level by level: each rank counts its
///     spheres per octant of every cell being split, one allreduce (sum) per level; a child
///     holding at most max(group, bucket) spheres, or that cannot be split, is a group. Every
///     rank then holds the same top tree, ~N/20 cells (measured: 9 577 for 151 837 spheres at
///     group = 64), ~9 B per sphere of the run (a TopCell and a tree node per cell): the one
///     replicated structure (against ~150 B per sphere of replicated positions and tree before),
///     and its counts, ~1 B per sphere of the run, the one O(N) message.
///  3. Gravity ownership: each group goes to the rank holding most of its spheres (one MAXLOC
///     allreduce over the groups; ties to the lower rank). The contact domains (ORB) are compact
///     boxes balanced by count, so the gravity work is balanced as they are and only the spheres
///     of groups cut by a domain boundary travel to their group's owner (Comm::sparse, 52 B, and
///     the acceleration back, 24 B, 32 B with the potential): measured 1-2 % of a rank's spheres.
///     At the owner a group's spheres are in global-index order (a counting sort by group).
///  4. Each rank builds its groups' subtrees (tree::build_subtree, the one-rank code) and the
///     moments of the top cells it alone owns; the top cells it owns whose parent is shared
///     ("maximal" cells) are allgathered with their moments and boxes, and every rank completes
///     the shared cells' moments from them (tree::moments, children in octant order).
///  5. Locally essential trees: every group of another rank r lies in one of r's maximal cells,
///     whose boxes and largest radii every rank now knows. Each rank walks its maximal cells and
///     opens a cell unless the walk's own opening rule (tree_accepts) accepts it for every
///     maximal cell of r (for r's whole box first): an accepted cell is not sent (r has its
///     moments, or they are in its parent's record); an opened one is sent with its children
///     (moments, and the box and particles of a leaf). Because the rule is monotone (a cell
///     accepted for a box is accepted for every box inside it with smaller radii), every cell a
///     group of r opens was opened here, so r's walk never lacks data (a cell it lacks holds NaN
///     and a leaf it lacks a NaN particle: a fault would surface as a non-finite acceleration,
///     exit 3, never as a wrong force). One sparse exchange (Comm::sparse: messages to the ranks
///     that need cells only, no all-to-all of counts).
///  6. Each rank walks its own groups (tree::walk) and returns the accelerations to the spheres'
///     contact owners.
/// Cost per rank per evaluation: the LET import, O((N/P)^(2/3)) particles and cells near the
/// rank's boundaries (measured: 7 000 particles and 12 700 cells, 1.6 MB, for 76 000 own spheres
/// behind one cut), the boundary groups' spheres moved, the maximal cells allgathered (O(P)
/// records), the level counts (~1 B per sphere of the run) and log(N/group) small allreduces;
/// memory O(N/P + N/group).
#pragma once
#include <cstdint>
#include <vector>

#include "ssdem/gravity_tree.hpp"
#include "ssdem/mpi/comm.hpp"

namespace ssdem::mpi {

/// What one evaluation did on this rank (sums over evaluations).
struct LetStats {
  double evaluations = 0;
  double bytes_owners = 0;  ///< spheres to their gravity owners and accelerations back [B]
  double bytes_top = 0;     ///< level counts and maximal cells [B]
  double bytes_let = 0;     ///< locally essential tree export [B]
  double top_cells = 0, maximal_cells = 0;        ///< last evaluation
  double gravity_spheres = 0, moved_spheres = 0;  ///< own groups' spheres, those from other ranks
  double imported_nodes = 0, imported_particles = 0;
  /// seconds: root box and top tree, spheres to their owners and back, the own groups' subtrees
  /// and the maximal cells, the locally essential trees, the walk
  double t_top = 0, t_owners = 0, t_build = 0, t_let = 0, t_walk = 0;
};

class DistributedTree {
 public:
  DistributedTree(Comm& comm, GravityParams p) : comm_(comm), p_(p) {}
  /// Accelerations (and potentials, if pot) of the spheres own[k] of sp (global indices gidx),
  /// written to acc[own[k]] (pot[own[k]]); acc and pot must have sp.size() entries. Collective.
  void compute(const Spheres& sp, const std::vector<std::uint32_t>& own, std::vector<Vec3>& acc,
               std::vector<double>* pot, const std::vector<std::uint64_t>& gidx);
  const LetStats& stats() const { return st_; }
  const TreeStats& tree_stats() const { return d_.stats; }
  /// Bytes held between evaluations (capacities of the tree and its buffers; an evaluation's
  /// message buffers, ~300 B per sphere it moves, come and go within it).
  double bytes() const;
  /// Replace the counters (a caller that must not count an evaluation restores them).
  void set_stats(const LetStats& s) { st_ = s; }

 private:
  struct TopCell {
    Vec3 c;
    double half = 0;
    int depth = 0;
    std::uint64_t count = 0;
    std::int32_t child = -1;  ///< first child (top index), -1 for a group
    std::uint8_t nchild = 0;
    std::int32_t owner = -1;  ///< the one rank owning every group below, -1 if shared
    bool group = false;
  };
  struct GravityParticle {
    std::uint64_t g;
    double x[3], m, s;
    std::uint32_t group;  ///< top index of its group
  };
  void root_box(const Spheres& sp, const std::vector<std::uint32_t>& own, Vec3& lo, Vec3& hi,
                double& smax, std::uint64_t& n);
  void top_tree(const Spheres& sp, const std::vector<std::uint32_t>& own, const Vec3& lo, const Vec3& hi,
                std::uint64_t n, std::vector<std::uint32_t>& group_of);
  void assign_owners(const std::vector<std::uint32_t>& group_of);
  std::vector<GravityParticle> to_owners(const Spheres& sp, const std::vector<std::uint32_t>& own,
                                         const std::vector<std::uint64_t>& gidx,
                                         const std::vector<std::uint32_t>& group_of,
                                         std::vector<std::vector<std::uint32_t>>& sent);
  void build_local(const std::vector<GravityParticle>& mine);
  void share_maximal();
  void exchange_let();

  Comm& comm_;
  GravityParams p_;
  LetStats st_;
  std::vector<TopCell> top_;
  std::vector<std::uint32_t> dfs_groups_;                ///< group cells in tree order
  std::vector<std::vector<std::uint32_t>> maximal_;      ///< per rank, in tree order
  std::vector<Vec3> box_lo_, box_hi_;                    ///< per rank: box of its gravity spheres
  std::vector<double> box_h_;                            ///< per rank: largest radius
  std::vector<std::uint32_t> back_src_, back_pos_;       ///< per gravity sphere: sender, position
  tree::Data d_;
  std::vector<Vec3> gx_;
  std::vector<double> gm_, gs_;
};

}  // namespace ssdem::mpi
