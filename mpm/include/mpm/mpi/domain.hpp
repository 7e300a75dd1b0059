/// @file domain.hpp
/// mpm-frag on MPI (issue 19, item 3; MPI build only, SUITE_MPI=ON): the background grid split
/// among ranks into boxes (ORB), ghost nodes, particle migration, rebalancing and global reductions.
/// One rank runs one Solver (mpm/solver.hpp) on a box of the global grid (Subdomain); the
/// physics is the serial code's, untouched. With OpenMP threads inside each rank (hybrid).
///
/// ## Decomposition (orb.hpp, orb.cpp)
/// The grid's cells (S_x x S_y x S_z, global indices; cell c along an axis lies between nodes c
/// and c + 1) are split among the R ranks by orthogonal recursive bisection: each node of a binary
/// tree cuts its box along its longest axis where the cumulative weight is nearest the share of
/// its lower ranks (orb.hpp gives the rule). Rank r OWNS its leaf box O_r (cells and nodes) and
/// the particles whose cell c_p = floor((x_p - o) / h) lies in it, and HOLDS O_r grown by H = 2
/// nodes a side, clipped to the grid (a uGIMP particle of cell c touches nodes c-1 .. c+2). The
/// set-up's tree balances the particle count, a rebalancing and a restart on another rank count
/// the work (2. below). Every side of a cut is at least W = max(2H, 2g + 1 - H) planes wide (g =
/// ghost_layers of the face conditions), so the mirror source of every symmetry layer lies inside
/// the box that holds the layer. On two ranks the tree is one cut along the longest axis: the
/// slabs of the previous decomposition, with the same cut.
///
/// ## Step (DomainSolver::step)
///   1. migration (migrate.cpp): every particle whose cell left the owner's box is sent, with ALL
///      its state (every ParticleSet array, ParticleSet::for_each_array, and every state array of
///      its material's style, Tonge–Ramesh included), to the owner of its cell (any rank, one
///      sparse exchange, Comm::sparse: debris crossing several boxes in one step is fine, and a
///      rank exchanges messages only with the ranks it sends to or receives from). Arrivals are appended per
///      material after the kept particles, in (source rank, sender order): material ranges stay
///      contiguous and the order is a function of the state alone (deterministic). A particle
///      whose stencil leaves the global grid stops the run on every rank (SolverFailure, state
///      intact); with outflow removal (grid.outflow = "remove") it goes to the owner of its clamped
///      cell, whose Solver removes it in the step and keeps its record (outflow_mpi.cpp).
///   2. every `rebalance_every` steps (default every step): imbalance I = max_r W_r / mean_r W_r
///      of the ranks' work W_r = sum_p w_p (work_weights: a plain particle 1, a Tonge-Ramesh
///      particle 1 + 0.6 M with M its last update's damage sub-steps, in integer units); if
///      I > threshold the tree is recomputed as above from the global histograms of work (one
///      integer allreduce per level of the tree: exact; the set-up's tree, before any update,
///      counts particles), each rank moves to its new box (Solver::set_subdomain) and the
///      particles migrate (1.); unless a rank's new box and particles would not fit its memory
///      (memory_ratio), or the work leaves a box of several ranks too narrow to cut (orb.hpp):
///      then the tree stays (DomainStats::rebalances_skipped).
///   3. the serial step on the box. After each P2G pass the GridExchange (halo.cpp) completes the
///      held nodes in two rounds: every rank sends its partial sums of the pass's fields (m_i,
///      (m v)_i, f_i; after the MUSL re-projection the momenta) on the nodes it holds but does
///      not own to their owners, the owner forms X_i = X_i^(owner) + X_i^(q_1) + X_i^(q_2) + ...
///      over the other holders in ascending rank order, and sends X_i back to every holder: every
///      holder then has the owner's bits (the "summed to their owner and sent back"). With
///      two holders of a node (every node on two ranks, or slabs) this is the one addition of two
///      terms of the previous one-round swap, the same bits (IEEE addition is commutative). Only
///      the nodes whose pass fields are not all +0 travel (with their ordinal in the shared box);
///      a node not received gets + 0.0, which is the dense sum bit for bit (halo.cpp), so the halo is the
///      nodes with mass. The grid update, the face conditions and G2P then run on owned and ghost
///      nodes alike from identical inputs.
///   4. global reductions (Comm::max, exact): the signal speed max_p (s_p + |v_p|) of dt =
///      C h / max (every rank takes the same dt), the smallest particle mass of m_min, the
///      material extents, and the failure flags (a failure on one rank stops every rank).
///   Diagnostics: each rank's totals (Solver::diagnostics), allgathered and summed in rank order.
///
/// ## Determinism and agreement with one rank
/// Repeated runs with the same rank and thread counts are bit-identical (every sum has a fixed
/// order). Against one rank the nodal sums of shared nodes are added in another order, so fields
/// agree to round-off growth (tests/mpm/mpi states the tolerances), mass to round-off and
/// momentum to round-off of the force sums (the force on a shared node is the same sum).
///
/// ## Not yet
/// (Done: snapshots, the outflow file, checkpoints and the last good state of a failure are
/// written by every rank together with collective parallel HDF5, snapshot_mpi.hpp and
/// checkpoint_mpi.hpp, in the serial layout; a restart on any rank count reads each rank's part
/// of the rows; velocity-driven bodies, drive.cpp; the set-up distributed, distributed_setup:
/// every rank walks the whole lattice once per level of the tree and once more, O(N log R)
/// work, but stores only its box's particles; each rank's box and particles checked against its
/// memory before the grid, check_memory.)
#pragma once
#include <mpi.h>

#include <functional>
#include <memory>
#include <vector>

#include "mpm/mpi/comm.hpp"
#include "mpm/mpi/orb.hpp"
#include "mpm/scene_setup.hpp"
#include "mpm/solver.hpp"

namespace mpmfrag::mpi {

/// Integer units of work per plain particle-step (work_weights).
inline constexpr long long kWorkUnit = 64;

/// Each particle's work weight w_p = kWorkUnit + sum_f round(kWorkUnit work_f min(s_{f,p}, 1e9))
/// over the cost fields f of its material's style (StateField::work > 0, one component; a
/// negative or NaN value counts 0; e.g. Tonge-Ramesh's damage sub-steps, whose shocked particles
/// cost up to 1 + 0.6 x 2 000 plain ones): exact integer sums, a function of the state alone
/// (deterministic cuts). kWorkUnit for every particle of a style without them.
std::vector<long long> work_weights(const ParticleSet& ps, const std::vector<MaterialSlot>& mats);
/// sum_p w_p of work_weights, without the per-particle array (the imbalance check of every step).
long long total_work(const ParticleSet& ps, const std::vector<MaterialSlot>& mats);

/// Options of the decomposition.
struct DomainOptions {
  /// Steps between imbalance checks (0: never rebalance). A check costs one pass over the
  /// particles and two integer reductions; every step, because a shock moves the Tonge-Ramesh
  /// work between boxes within a few steps (mpm/README.md, MPI).
  int rebalance_every = 1;
  double imbalance_threshold = 1.2; ///< rebalance when max W_r / mean W_r exceeds this
  /// The memory a rank and a node offer (bytes; < 0: process_memory_limit(), node_memory()),
  /// checked against each rank's box and particles before its grid is allocated (tests set them).
  double process_memory = -1, node_memory = -1;
};

/// Counters of a rank (communication volume and events).
struct DomainStats {
  long long migrated = 0;     ///< particles this rank sent away
  long long rebalances = 0;   ///< rebalancings (same on every rank)
  long long rebalances_skipped = 0;  ///< rebalancings left out: a rank's new box would not fit its memory, or a box could not be cut
  double imbalance_max = 0;   ///< largest work imbalance max W_r / mean W_r seen at a check (before rebalancing)
  double imbalance_sum = 0;   ///< its sum over the checks
  long long imbalance_checks = 0;  ///< checks (same on every rank)
  double halo_bytes = 0;      ///< bytes sent in halo swaps
  double migrate_bytes = 0;   ///< bytes sent in migration (and gathers)
};

/// Halo swap of the held nodes (halo.cpp): the GridExchange of a rank's Solver.
class HaloExchange : public GridExchange {
 public:
  HaloExchange(Comm& comm, const Orb& orb) : comm_(comm), orb_(orb) {}
  void sum_shared(Solver::Node* nodes, int fields) override;
  void max(double* v, int n) override { comm_.max(v, n); }
  /// Rank order: every rank's values allgathered and added from rank 0 up.
  void sum(double* v, int n) override;
  void min_shared_drive(std::int32_t* node_drive, std::vector<std::size_t>& added) override;
  double bytes_sent = 0;

 private:
  Comm& comm_;
  const Orb& orb_;
  std::vector<std::vector<double>> send_, recv_;
  std::vector<std::vector<std::int32_t>> isend_, irecv_;
  /// The other ranks q (ascending) and the boxes this rank shares with them: `ghost[k]` = H_r
  /// intersected with O_q (nodes this rank holds and q owns), `mine[k]` = O_r intersected with
  /// H_q (nodes it owns and q holds); either may be empty.
  struct Shared {
    std::vector<int> rank;
    std::vector<Box> ghost, mine;
  };
  Shared shared() const;
};

/// The particles of `ps` with keep[p] != 0, materials kept contiguous (state arrays included).
void select_particles(const ParticleSet& ps, const std::vector<MaterialSlot>& mats, const std::vector<char>& keep,
                      ParticleSet& out, std::vector<MaterialSlot>& out_mats);

/// Pack particle p with its material state (one migration record) / unpack records into a set
/// of arrivals: `in` (ParticleSet) and per material the arrivals' indices and state rows.
void pack_particle(const ParticleSet& ps, const std::vector<MaterialSlot>& mats, std::size_t p, std::vector<char>& buf);
struct Arrivals {
  ParticleSet ps;
  std::vector<std::vector<std::size_t>> index;               ///< per material: indices in ps
  std::vector<std::vector<std::vector<double>>> state;       ///< per material, per field: rows
};
void unpack_particles(const std::vector<char>& buf, const std::vector<MaterialSlot>& mats, bool with_q, Arrivals& in);
/// Order each material's arrivals by key[k] (k: row of in.ps; keys unique), state rows alike.
void sort_arrivals(Arrivals& in, const std::vector<std::uint64_t>& key);
/// The kept particles (keep[p]) followed, per material, by the arrivals.
void merge_particles(const ParticleSet& ps, const std::vector<MaterialSlot>& mats, const std::vector<char>& keep,
                     const Arrivals& in, ParticleSet& out, std::vector<MaterialSlot>& out_mats);

/// Where each particle of a gathered set (DomainSolver::gather), or of one rank's part of a
/// checkpoint (checkpoint_mpi.hpp), came from: its rank and its index there, with the tree of cuts. A
/// restart on as many ranks rebuilds every rank's particles in the same order from it (the same
/// sums in the same order: bit-identical continuation).
struct Layout {
  int ranks = 0;                     ///< ranks of the writer (0: a one-rank checkpoint, no layout)
  std::vector<Orb::Split> split;     ///< its tree of cuts (Orb::split)
  int slab_end = -1;                 ///< a file of slab cuts (before the boxes): its last plane, S_a
  std::size_t first = 0;             ///< the file row of this rank's first particle (a part)
  std::vector<std::int32_t> rank;    ///< per particle of the set: its rank
  std::vector<std::uint64_t> index;  ///< per particle: its index on that rank
  std::vector<double> outflow_totals;  ///< per rank: totals of its removed particles (pack_totals)
};

/// An outflow record (outflow_mpi.cpp): removed particles, their removal times and output state
/// fields merged over the ranks by name (`init`: each field's initial value), the totals of the
/// removed particles (rank partials summed in rank order) and each rank's partial (pack_totals,
/// rank-major). DomainSolver::local_outflow: this rank's particles, in its order;
/// gather_outflow: every rank's on one, sorted by (removal time, id).
struct OutflowRecord {
  ParticleSet ps;
  std::vector<double> time;
  std::vector<common::Field> fields;
  std::vector<double> init;
  Diagnostics totals;
  std::vector<double> rank_totals;
};

/// Reports every particle to `add` as add(x, w): its position (3 doubles) and integer weight.
using WeightedParticles = std::function<void(const std::function<void(const double*, long long)>& add)>;
/// The ORB (orb_cuts) of grid `g` for `ranks` ranks, with the halo and narrowest side of `layout`,
/// from the weights of the particles `each` reports in each cell (c = floor((x - o) / h), clamped):
/// with `comm` every rank reports its own particles and each level's histograms are summed (one
/// exact integer allreduce per level), without it the caller reports them all.
Orb orb_of_particles(const Orb& layout, const common::GridInfo& g, int ranks, const WeightedParticles& each,
                     Comm* comm = nullptr);

/// The Subdomain of rank r: the box it holds, the box it owns.
Subdomain subdomain_of(const Orb& orb, int r);

/// Distributed set-up (collective; no rank holds every particle): every rank generates the
/// scene's lattice itself (build_setup with a SetupPart), once per level of the tree to count
/// the particles per plane of each box being cut (the tree DomainSolver(comm,
/// build_setup(scene)) would compute, no reduction: every rank counts the same) and once more to
/// keep the particles of its own box, or none (`particles` false: a restart reads them; no tree
/// then). Returns the set-up and the tree, for DomainSolver(comm, setup, orb): the same particles
/// in the same order on every rank as the full set-up.
std::pair<Setup, Orb> distributed_setup(MPI_Comm comm, const common::Scene& scene, bool particles = true);

/// One rank's part of a distributed mpm-frag run.
class DomainSolver {
 public:
  /// Every rank passes the same full set-up (scene_setup.hpp); each keeps the particles of its
  /// box. Collective. Throws common::InputError (too many ranks).
  DomainSolver(MPI_Comm comm, const Setup& setup, DomainOptions opt = {});
  /// Each rank passes the particles of its box of the given tree (distributed_setup).
  /// Collective.
  DomainSolver(MPI_Comm comm, const Setup& mine, const Orb& orb, DomainOptions opt = {});
  /// Restart (checkpoint_mpi.cpp): each rank's `setup` holds its part of a checkpoint's
  /// particles and materials' state (file rows [layout.first, ...), in file order; any split of
  /// the rows over the ranks, one rank holding all included). When `layout` says the file was
  /// written on as many ranks, every rank gets its particles back in their order and the tree
  /// is the layout's; otherwise the tree balances the work (work_weights) and each rank keeps the
  /// file order (a rank whose box by work would not fit its memory stops the restart with the
  /// set-up's message, check_memory; unlike a rebalancing, no fallback to the count's tree).
  /// Collective. Follow with local().resume(), not initialize().
  DomainSolver(MPI_Comm comm, const Setup& setup, const Layout& layout, DomainOptions opt = {});
  /// Initial stress and wave speeds (collective).
  void initialize() { solver_->initialize(); }
  /// The global stable dt (the same on every rank).
  double stable_dt() const { return solver_->stable_dt(); }
  /// Migrate, rebalance if due, then one step of every rank's Solver (collective).
  void step(double dt);
  /// Global totals, rank partials summed in rank order (collective).
  Diagnostics diagnostics();
  /// All particles on `root` (sorted by id within each material, material ranges contiguous);
  /// other ranks get empty sets (collective). `layout` (root): where each came from.
  void gather(int root, ParticleSet& ps, std::vector<MaterialSlot>& mats, Layout* layout = nullptr);
  /// This rank's outflow record with the field list merged over every rank (the same names,
  /// units and order on every rank; a field this rank's particles lack holds its initial value),
  /// and the totals on every rank (collective): what the collective outflow file and checkpoint
  /// write, the rows sorted by (removal time, id) across the ranks (outflow_key).
  OutflowRecord local_outflow();
  /// Every rank's outflow record on `root` (empty elsewhere; collective).
  OutflowRecord gather_outflow(int root);
  /// Imbalance max_r W_r / mean_r W_r of the ranks' work (work_weights; collective).
  double imbalance();
  /// Recompute the tree from the histograms of work and migrate (collective).
  void rebalance();

  Solver& local() { return *solver_; }
  const Orb& orb() const { return orb_; }
  const DomainStats& stats() const { return stats_; }
  Comm& comm() { return comm_; }
  double time() const { return solver_->time(); }
  std::int64_t step_count() const { return solver_->step_count(); }
  /// Keep a copy of this rank's particles, material state, time and step: the last good state a
  /// failure saves (run_mpi.cpp). No communication: every rank calls it at the same step, so the
  /// copies together hold the global state of that step, whatever migrates later (the Solver's
  /// own backup is dropped by each migration, Solver::replace_particles).
  void save_backup();
  const Backup& backup() const { return backup_; }

 private:
  /// Send every particle to the owner of its cell (collective); returns whether this rank's set changed.
  void migrate();
  /// The tree of this rank count balancing the work of every rank's particles `ps` (collective).
  Orb balanced_orb(const ParticleSet& ps, const std::vector<MaterialSlot>& mats);
  void init_orb(const Setup& setup);
  void build_solver(const Setup& setup, ParticleSet mine, std::vector<MaterialSlot> mats);
  /// Collective, before the grid is allocated: this rank's box and particles against its process
  /// limit, the node's ranks together against the node's memory (work.cpp). InputError (exit 2)
  /// on every rank, naming the largest rank's box, when either is exceeded.
  void check_memory(const std::vector<MaterialSlot>& mats) const;
  /// Collective: the largest ratio over the ranks of need to limit (process: this rank's box of
  /// `nodes` nodes and `bytes` of particles; node: its ranks together), that rank, and this
  /// rank's needs and limits.
  struct MemoryRatio {
    double ratio = 0;
    int rank = 0;
    double need = 0, node_need = 0, process = 0, node = 0;
  };
  MemoryRatio memory_ratio(double nodes, double bytes) const;
  Eigen::Vector3i cell(const double* x) const;  ///< cell of position x, clamped to the grid

  Comm comm_;
  DomainOptions opt_;
  common::GridInfo grid_;
  Orb orb_;
  std::unique_ptr<HaloExchange> halo_;
  std::unique_ptr<Solver> solver_;
  DomainStats stats_;
  Backup backup_;
};

}  // namespace mpmfrag::mpi
