/// @file contacts.hpp
/// Contact detection (cell-list Verlet pair list with a skin, maintained incrementally) and force
/// assembly for the soft-sphere law of contact_law.hpp, with contact history keyed by sphere-id
/// pairs.
///
/// Neighbour search. Each sphere i has a reference position r_i (its position when it was last
/// inserted into the cell grid) and a displacement d_i = |x_i - r_i|. The grid holds the r_i in
/// cubic cells of edge c = 2 s_max + k (k = skin, hashed cell keys: an escaping sphere far away
/// costs nothing). The pair list holds, for i < j,
///   every pair with |r_i - r_j| < s_i + s_j + k                                          (I)
/// (it may hold more). Update rule, before every force evaluation:
///   M = { i : d_i > k/2 }. If M is empty, nothing is done. Otherwise r_i := x_i for i in M, each
///   is moved to its new cell, and its pairs are recomputed from the grid (27 cells around r_i,
///   test (I) against the partners' reference positions r_j, whatever their age). If that pair
///   set holds no pair that is not listed yet (a lone fast fragment, spheres moving apart), the
///   list is left untouched (it may then hold pairs beyond the reach: harmless, see below; they
///   are flagged, and when they are 1/8 of the list grid and list are rebuilt from scratch).
///   New pairs are not merged at once: they wait (W) until one of them is due, i.e. its current
///   gap |x_i - x_j| - s_i - s_j is below g_l = (1 - 2 f) k (0 with the default f = 1/2; k/2 with
///   multi-rate's f = 1/4), checked at every update; then the pairs of M are replaced in the
///   (i, j)-sorted list by a merge that adds the waiting pairs too. (A merge copies every pair's
///   history: on reaccumulating debris new pairs appear every few steps, and merging each at
///   once cost 3x the rest of the list's work; measured in nbody/README.md.) Waiting pairs are
///   merged as well when they are 1/8 of the list; a waiting pair with a member in M is
///   recomputed with it. If |M| > max(n/4, 32), grid and list are rebuilt from scratch (r = x for
///   all, W empty; same result, cheaper per sphere).
///   Cell edge >= the largest reach 2 s_max + k, so every partner of (I) is in the 27 cells.
/// Isolated spheres (a margin per sphere; pair_grid.hpp). A re-inserted sphere that has no
/// partner within the larger reach s_i + s_j + k + M + m_j (M = c, the cell edge) becomes fast:
/// its margin m_i = M, it is kept in a second grid of edge c + 2M, and it is re-inserted only
/// when d_i > f k + m_i. (I) becomes |r_i - r_j| < s_i + s_j + k + m_i + m_j, and the proof below
/// holds as written with f k replaced by f k + m_i for each sphere: an unlisted pair still has a
/// gap of at least g_l. The isolation test searches two rings of the first grid (the reach there
/// is at most 2c) and one of the second; an ordinary sphere's search one ring of each. It runs
/// only for a re-inserted sphere whose own search found no pair (one with a pair within reach is
/// not isolated), so a sphere that takes the margin has no pair within its reach. On a debris cloud a
/// lone fragment then re-inserts once per (f k + c) of travel instead of f k (on equal spheres
/// with k = s/4: 37x fewer at multi-rate's f = 1/4, 19x at f = 1/2); in a pile nothing changes
/// (every sphere has a partner). A full rebuild makes every sphere ordinary again. Which pairs
/// are listed changes, the forces do not (below).
/// No-miss criterion (proof sketch): (I) holds for the listed and waiting pairs together after
/// every update, since pairs with no member in M keep their r and were tested against them, and
/// pairs with a member in M are re-tested with the new r (both members' current r; a pair with
/// both in M is tested once both are moved). A waiting pair is listed before its gap falls below
/// g_l (it is checked at every update), so every pair with a gap below g_l, in contact in
/// particular, is listed.
/// After the update d_i <= f k for all i (f = 1/2 above). For a pair neither listed nor waiting,
/// by (I) and the triangle inequality, |x_i - x_j| >= |r_i - r_j| - d_i - d_j >= s_i + s_j + k -
/// 2 f k, i.e. a gap of at least g_l: no overlap (contact_pair needs |x_i - x_j| < s_i + s_j).
/// So every pair in contact is listed. (A per-pair test d_i + d_j <= k would do too; the per-sphere k/2 makes it O(1) per
/// sphere.) Only the spheres that moved more than k/2 pay: on expanding debris the few fast
/// fragments are re-inserted every step, the slow bulk is not touched.
/// Scheduled tests (multi-rate callers; drift_schedule.hpp). Testing d_i > f k (+ m_i) for every
/// sphere at every base step cost 1/3 of the list's upkeep on disrupted debris, where most spheres
/// take long steps: between two kicks a sphere drifts at one velocity, so the step at which its
/// test can first fire is known in advance. update_neighbors(sp, drift) tests only the spheres
/// kicked since the previous call and those whose test is due, and re-plans each. The moved set M
/// is the same, bit for bit, as the test of every sphere would give.
/// Determinism: the pair list is sorted by (i, j) with i < j; per-pair results are written to
/// one record per pair (PairForces) in parallel and gathered per sphere in ascending partner
/// order, so the summation order (and hence the result, bit for bit) is independent of the thread
/// count and of when and how the list was updated: listed pairs not in contact add nothing or
/// their zero record's +0 (which leaves a sum started at +0 unchanged bit for bit) and reset
/// their history exactly as an unlisted pair has none, so the trajectories are bit-identical to a
/// list rebuilt from scratch every step.
/// History: one ContactHistory (contact/history.hpp, structure of arrays, columns of the enabled
/// parts only) per pair, carried across updates by an (i, j)-key merge (a pair in contact is
/// never dropped, by the criterion above), a second one for the wall contacts, both exported and
/// imported for checkpoints keyed by ids.
#pragma once
#include <cstdint>
#include <vector>

#include "common/exact_sum.hpp"
#include "ssdem/cell_table.hpp"
#include "ssdem/contact_law.hpp"
#include "ssdem/drift_schedule.hpp"
#include "ssdem/loop_split.hpp"
#include "ssdem/spheres.hpp"

namespace ssdem {

/// What one sphere-sphere pair in contact contributes to its two spheres at its last evaluation:
/// the force on i (-F on j) and the torques on i and on j. One record per pair (72 bytes), so a
/// sphere's sum over its pairs reads one or two cache lines per pair in contact instead of three
/// arrays.
struct PairForces {
  Vec3 F, Tp, Tn;
};

/// An infinite plane wall: points p with (p - point).normal >= 0 are inside the domain.
struct Plane {
  Vec3 point = Vec3::Zero();
  Vec3 normal = Vec3::UnitZ();  ///< unit normal pointing into the domain
};

/// Per-step contact statistics.
struct ContactStats {
  std::size_t contacts = 0;       ///< sphere-sphere contacts
  std::size_t wall_contacts = 0;
  double max_overlap_frac = 0.0;  ///< max overlap / smaller radius
  std::size_t worst_a = 0, worst_b = 0;  ///< indices of the worst pair (b = a for a wall)
  /// the pair list was rebuilt from scratch since the previous compute() (local updates are
  /// counted by ContactSystem::local_update_count / reinsert_count)
  bool rebuilt = false;
  std::size_t foreign_pairs = 0;  ///< pairs skipped as both members' forces are another rank's (set_owned)
  std::size_t kernel_pairs = 0;   ///< pairs evaluated by the kernel (overlapping or in contact)
  std::size_t shared_pairs = 0;   ///< of those, pairs with a member not owned here (set_owned): also evaluated by its owner
};

class ContactSystem {
 public:
  ContactSystem(const ContactParams& p, std::vector<Plane> walls, double skin);

  const ContactParams& params() const { return params_; }
  const std::vector<Plane>& walls() const { return walls_; }
  double skin() const { return skin_; }

  /// Bring the pair list up to date (see the file comment): re-insert the spheres that moved
  /// more than skin/2 (plus the margin of an isolated sphere), or rebuild everything if `force`,
  /// on a size change or when more than a quarter (and more than 32) moved. Returns whether it
  /// rebuilt from scratch (a local update returns false; see local_update_count()). Called once
  /// before every compute() (single-rate steps, Simulation::compute_forces; the MPI driver);
  /// multi-rate steps call the form below.
  bool update_neighbors(const Spheres& sp, bool force = false);
  /// What a multi-rate caller knows of the drifts between two calls (see "Scheduled tests").
  struct Drift {
    double h = 0.0;  ///< every call follows one drift x += h v of every sphere
    /// the spheres whose velocity changed since the previous call (null: any may have)
    const std::uint32_t* kicked = nullptr;
    std::size_t nkicked = 0;
    /// per sphere: a kicked sphere keeps its velocity through the next 2^level[i] - 1 calls
    const std::uint8_t* level = nullptr;
  };
  /// update_neighbors(sp) with scheduled tests: the same list, bit for bit. Preconditions: since
  /// the previous call of this form, positions changed only by exactly one drift x += h v (a call
  /// of the other form in between makes the next one test every sphere); `kicked` is ascending
  /// (so each sphere once) and < n, and names every sphere whose v changed; `level` is not null
  /// (asserted in debug builds).
  bool update_neighbors(const Spheres& sp, const Drift& drift);
  /// Contact forces and torques for all spheres (overwrites F and T), using predicted
  /// velocities/spins vpred/wpred and half-step spins for the transport rotation. Uses the pair
  /// list as left by update_neighbors() / import_history() (std::logic_error if there is none for
  /// these spheres); ContactStats::rebuilt says whether it was rebuilt since the last compute().
  /// `diss` (may be null): per-sphere accumulator to which each sphere's share of this step's
  /// dissipated energy is added (half of each sphere-sphere contact's, all of its wall
  /// contacts'), gathered in the same order as the forces (thread-count independent).
  ContactStats compute(const Spheres& sp, const std::vector<Vec3>& vpred,
                       const std::vector<Vec3>& wpred, double h, std::vector<Vec3>& F,
                       std::vector<Vec3>& T, double* diss = nullptr);
  /// The pairs and spheres of one multi-rate substep (multirate.hpp): listed pairs (indices into
  /// the pair list, ascending) evaluated with their own step hpair, and the spheres whose F and T
  /// are gathered (ascending; wall contacts with hsphere). Every pair of a listed sphere that is
  /// in contact must be in `pairs` (the multi-rate level rule guarantees it). `whole` (per listed
  /// pair; empty = all 1): 1 if both members are gathered now; a pair with one member only (a
  /// separating pair whose flag is reset) gets no edge force (contact_law.hpp), which would reach
  /// one member only.
  struct Subset {
    std::vector<std::uint32_t> pairs, spheres;
    std::vector<double> hpair, hsphere;
    std::vector<std::uint8_t> whole;
  };
  /// Edge impulses on or off (contact.resolve_edges; off for the first evaluation of a run, whose
  /// overlaps are not onsets).
  void set_edges(bool on) { coeffs_.edges = on && params_.resolve_edges; }
  /// A domain's local set (mpi/domain_sim.hpp): owned[k] != 0 for the spheres whose forces this
  /// process uses. compute() then skips the pairs of two others (ghost-ghost pairs: their forces
  /// are their owners'; their records go stale here, so a caller of export_history keeps only the
  /// records of owned spheres, as DomainSim::owned_history does) and sets the others' contact F
  /// and T to zero; the owned spheres' sums are unchanged, bit for bit. null: every sphere.
  void set_owned(const std::vector<std::uint8_t>* owned) { owned_ = owned; }
  /// compute() restricted to a Subset: F and T are written for its spheres only.
  ContactStats compute(const Spheres& sp, const std::vector<Vec3>& vpred,
                       const std::vector<Vec3>& wpred, const Subset& sub, std::vector<Vec3>& F,
                       std::vector<Vec3>& T, double* diss = nullptr);
  /// Re-insert a sphere once it moved more than f * skin (plus its margin, if isolated) from its
  /// reference position (default f = 1/2). With f < 1/2 every pair with a gap below
  /// (1 - 2 f) * skin is listed (multi-rate uses f = 1/4: pairs closer than skin/2 are always
  /// listed, whatever the list's history).
  void set_reinsert_fraction(double f) {
    reinsert_frac_ = f;
    sched_.invalidate();  // (the plans assumed the old distance)
  }
  /// Whether re-inserted isolated spheres may take a margin (see the file comment; default on).
  /// Off for a caller of near_point(), which searches the ordinary grid only; set before the first
  /// update_neighbors() (spheres that hold a margin keep it until the next rebuild).
  void set_margins(bool on) { margins_on_ = on; }
  /// Re-insertions that gave a sphere the margin of an isolated one, and spheres holding it now.
  std::size_t margin_count() const { return promotions_; }
  std::size_t fast_spheres() const { return fhead_count_; }
  bool holds_margin(std::size_t i) const { return i < fast_.size() && fast_[i] != 0; }
  double reinsert_fraction() const { return reinsert_frac_; }
  /// CSR of the pair list: pairs p in [row_i()[k], row_i()[k+1]) have k as i member; pairs
  /// jpair()[q], q in [row_j()[k], row_j()[k+1]), have k as j member.
  const std::vector<std::uint32_t>& row_i() const { return irow_; }
  const std::vector<std::uint32_t>& row_j() const { return jrow_; }
  const std::vector<std::uint32_t>& jpair() const { return jpair_; }
  /// Changes whenever the pair list (its pairs or their order) changes: per-pair data cached by a
  /// caller (Simulation's pair levels) are stale when this differs from the value they were made at.
  std::uint64_t list_version() const { return version_; }
  /// Add the elastic energy stored in the current contacts [J] to `e`: every contact's, or with
  /// `owned` only those whose i member (of a pair; the sphere of a wall contact) has owned[i] != 0.
  void add_elastic_energy(const Spheres& sp, common::ExactSum& e, const std::vector<std::uint8_t>* owned = nullptr) const;
  /// Active contacts as records keyed by ids (sorted by pair order).
  std::vector<HistoryRecord> export_history(const Spheres& sp) const;
  /// Load history (e.g. from a checkpoint); rebuilds the pair list immediately.
  void import_history(const Spheres& sp, const std::vector<HistoryRecord>& recs);

  /// Pairs compute() evaluates together (pair_batch.hpp): 4 when built with AVX2, else 2.
  static int lanes();
  std::size_t pair_count() const { return pi_.size(); }
  /// Pair list (i < j, sorted by (i, j)): the i and j members.
  const std::vector<std::uint32_t>& pair_i() const { return pi_; }
  const std::vector<std::uint32_t>& pair_j() const { return pj_; }
  /// Whether (a, b) (either order) is in the pair list.
  bool listed(std::size_t a, std::size_t b) const;
  /// Appends to `out` every sphere whose reference position lies in the 27 grid cells around x
  /// (cell edge 2 s_max + skin): every sphere j with |x_j - x| + |x_j - x_ref,j| <= the cell edge.
  void near_point(const Vec3& x, std::vector<std::uint32_t>& out) const;
  /// Reference positions of the cell grid (where each sphere was last inserted).
  const std::vector<Vec3>& reference_positions() const { return xref_; }
  /// Edge of the grid's cells (2 s_max + skin over the spheres of the last rebuild).
  double cell_edge() const { return cell_; }
  /// Full rebuilds (grid and list from scratch).
  std::size_t rebuild_count() const { return rebuilds_; }
  /// Local updates that changed the pair list (merge), and sphere re-insertions in total.
  std::size_t local_update_count() const { return local_updates_; }
  std::size_t reinsert_count() const { return reinserts_; }
  /// Re-insertion tests made, one per sphere tested per update (n per update without schedule).
  std::size_t test_count() const { return tests_; }
  /// Adds the counters above (and margin_count) of `before`, the contact system this one
  /// replaced (a renumbering of the spheres, sphere_order.hpp), so that a run reports its totals.
  void continue_counters(const ContactSystem& before) {
    rebuilds_ += before.rebuilds_;
    local_updates_ += before.local_updates_;
    reinserts_ += before.reinserts_;
    tests_ += before.tests_;
    promotions_ += before.promotions_;
  }
  /// Bytes held per sphere by the contact system (pair list, history, CSR, cell grids), current
  /// sizes; scratch kept between calls (compute()'s per-thread lists of 4 B per pair, the
  /// searches' candidates) is not counted.
  double bytes_per_sphere(std::size_t n) const;

 private:
  void build_pairs(const Spheres& sp);
  void install_pairs(const Spheres& sp, std::vector<std::uint32_t>& npi,
                     std::vector<std::uint32_t>& npj);
  bool local_update(const Spheres& sp, bool all);
  /// Enters sphere i's next scheduled test (drift_ set).
  void plan(const Spheres& sp, std::uint32_t i);
  std::uint64_t cell_of(const Vec3& x, double edge) const;
  void link(std::uint32_t i);
  void unlink(std::uint32_t i);
  /// f(j) for every j != i with |r_i - r_j| < s_i + s_j + skin + m_i + m_j (reference positions,
  /// margins; m_i = mi here); stops early when f returns true (pair_grid.hpp).
  template <class F>
  void visit_near(const Spheres& sp, std::uint32_t i, double mi, F&& f) const;
  /// f(j) for every j within reach of an ordinary sphere i (no margin: a sphere that takes one
  /// has no pair within reach, so nothing searches around it).
  template <class F>
  void for_each_near(const Spheres& sp, std::uint32_t i, F&& f) const;
  /// Whether i has no partner within reach if it took the margin of an isolated sphere.
  bool isolated(const Spheres& sp, std::uint32_t i) const;
  /// Appends to nk the keys (i << 32 | j, i < j) of the pairs within reach of each sphere of
  /// moved_ (unsorted, repeats possible), and gives the margin to each that has none and no
  /// partner within the larger reach either, in ascending order (pair_grid.cpp).
  void search_moved(const Spheres& sp, std::vector<std::uint64_t>& nk);
  template <unsigned PARTS>
  ContactStats compute_impl(const Spheres& sp, const std::vector<Vec3>& vpred,
                            const std::vector<Vec3>& wpred, double h, std::vector<Vec3>& F,
                            std::vector<Vec3>& T, const Subset* sub, double* diss);

  ContactParams params_;
  ContactCoeffs coeffs_;
  std::vector<Plane> walls_;
  double skin_;
  double reinsert_frac_ = 0.5;
  const std::vector<std::uint8_t>* owned_ = nullptr;  ///< set_owned (null: every sphere is owned)

  // pair list (i < j), sorted
  std::vector<std::uint32_t> pi_, pj_;
  ContactHistory ph_;  // per pair
  // per-pair results (pair_batch.hpp): one record per pair, zero whenever the pair is not in
  // contact, so the per-sphere sums may add every listed pair's record without a test
  std::vector<PairForces> pres_;
  std::vector<double> pD_;  // energy dissipated over the pair's last step
  // per pair: its record holds a released pair's edge force (contact_law.hpp, "Contact edges"),
  // summed like a contact's and zeroed at the pair's next evaluation
  std::vector<std::uint8_t> pedge_;
  // CSR of pairs where the sphere is the j member (ascending i)
  std::vector<std::uint32_t> jrow_, jpair_;
  // CSR of pairs where the sphere is the i member: contiguous range
  std::vector<std::uint32_t> irow_;
  ContactHistory wh_;  // wall contacts, row = sphere * nwalls + wall
  std::vector<Vec3> xref_;  // reference positions r_i
  // cell grid of the reference positions: cell key -> first sphere, doubly linked per cell
  double cell_ = 0.0;
  CellTable head_;
  // the isolated spheres' grid (edge fcell_ = cell_ + 2 margin_), their flags and margin
  CellTable fhead_;
  double fcell_ = 0.0, margin_ = 0.0;
  bool margins_on_ = true;
  std::vector<std::uint8_t> fast_;
  std::size_t promotions_ = 0, fhead_count_ = 0;
  std::vector<std::uint32_t> next_, prev_;
  std::vector<std::uint64_t> ckey_;
  std::vector<std::uint8_t> mark_;   // scratch: 1 for the spheres of marked_, 0 for the others
  std::vector<std::uint32_t> moved_, marked_;
  std::vector<std::uint8_t> iso_;                     // scratch of search_moved: per moved sphere
  struct alignas(64) KeyPart {  // (a cache line each: the threads' push_backs write their headers)
    std::vector<std::uint64_t> keys;
  };
  std::vector<KeyPart> nk_part_;  // scratch of search_moved: per thread
  // scheduled tests: the current call's drift (null outside update_neighbors(sp, drift)), the
  // schedule, and the spheres it names for this call
  const Drift* drift_ = nullptr;
  DriftSchedule sched_;
  LoopSplit pair_split_, sphere_split_;  ///< compute()'s team blocks (speed only, never results)
  struct alignas(64) KeptPart {  // scratch of compute(): per thread, the positions of its pairs to evaluate
    std::vector<std::uint32_t> q;
  };
  std::vector<KeptPart> kept_;
  std::vector<std::uint32_t> cand_;
  std::size_t rebuilds_ = 0, local_updates_ = 0, reinserts_ = 0, tests_ = 0;
  std::vector<std::uint64_t> waiting_;    // new pairs not merged yet (keys i << 32 | j, i < j, sorted)
  std::vector<std::uint8_t> stale_flag_;  // per pair: left listed beyond its reach
  std::size_t stale_ = 0;                 // number of flagged pairs
  bool rebuilt_since_compute_ = false;
  std::uint64_t version_ = 0;  // list_version()
  std::vector<HistoryRecord> pending_;  // imported history waiting for the first build
  bool import_ = false;
};

}  // namespace ssdem
