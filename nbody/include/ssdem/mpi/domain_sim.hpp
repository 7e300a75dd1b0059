/// @file domain_sim.hpp
/// ssdem-grav on MPI: the integrator of simulation.hpp (KDK leapfrog, impulse-RESPA gravity
/// blocks with the error-controlled cadence, predicted dashpot velocities) over a domain
/// decomposition. Equations: simulation.hpp; this file adds only where each quantity lives.
///
/// Ownership. Each sphere is owned by one rank, chosen by orthogonal recursive bisection by count
/// (orb.hpp), rebuilt at an exchange when max_r n_r > (1 + imbalance) * mean and max_r n_r >= mean + 1.
/// Owned spheres are
/// integrated by their rank; they carry their global index g (input order), which fixes every
/// summation order, so results do not depend on where a sphere lives.
/// Ghosts and exchanges (LAMMPS-style halo with a skin). At an exchange each rank takes the spheres
/// of the other ranks within R = 2 s_max + k of the bounding box of its own spheres as ghosts
/// (k = the contact skin; with bonds R is at least the longest intact bond, see "Bonds": the
/// movers' coverage test below, made with 2 s_max + k, is then conservative). Spheres that moved less than t = k/2 (k/4 with multi-rate steps) since
/// the exchange cannot form a contact (a near pair) with a sphere that is not a ghost; the few
/// that moved farther ("movers": fast fragments) are sent to every rank each step and checked
/// against its own spheres, and an exchange is done only when a near pair with a mover is not
/// covered by the ghosts, or when movers are many (domain_movers.cpp, with the argument). Between
/// exchanges the ghosts' x, v, w and predicted v, w are sent every step (15 doubles per ghost) in
/// point-to-point messages to the ranks that share ghosts (Comm::neighbours). At an exchange
/// spheres migrate to the rank owning their position (any rank: debris crossing several domains in
/// one step), then ghosts are rebuilt.
/// Numerical failure. Every rank keeps a packed copy of its own spheres and history at the
/// verified block boundaries of set_keep_last_good; after a failure they are gathered into the
/// one-rank state of that step (the serial driver's failed_state.h5). The end-of-step check
/// (non-finite state, runaway overlap) is decided together: at block boundaries at once, inside a
/// block with the next base step's movers allgather (check_state, need_exchange).
/// Contacts. The local set L = owned + ghosts, in global-index order, runs the serial contact
/// system (contacts.hpp). Its per-sphere sums run over partners in ascending local index, which is
/// ascending global index, so an owned sphere's force equals the one-rank force bit for bit.
/// A pair across two ranks is evaluated on both (from identical inputs, so identically); only the
/// owned member's force is used. The pair's contact history belongs to the rank that owns the
/// member with the lower global index (the deterministic owner rule): at every exchange that
/// rank's record is sent to the new owners of both members and imported there, so the history
/// moves with its owner and the copies never diverge. Ghost-ghost pairs (both forces are other
/// ranks') are not evaluated (ContactSystem::set_owned; since 2026-12-05, before they were
/// evaluated and their forces dropped): their records, if any, go stale and are replaced from the
/// owners' records at the next exchange; the ghosts' contact F and T are zero.
/// Gravity. The tree (gravity.tree): the one-rank octree distributed over the ranks along its
/// own cells, with locally essential trees (gravity_let.hpp): forces equal the one-rank forces bit
/// for bit, with O(N/P + N/group) memory and O(N/P) traffic per rank per evaluation. Direct
/// summation (gravity.direct, small N): the positions, masses and radii of all spheres are
/// allgathered at each evaluation and every rank sums for its own spheres.
/// Cadence. The block length uses global sums of |g|^2 and |g - g'|^2: per-rank partial sums are
/// allgathered and added in rank order (deterministic for a given rank count; against one rank
/// they differ by round-off, which can change the integer block length only when it is within
/// ~1e-15 of an integer).
/// Multi-rate steps (time.multirate, multirate.hpp). Levels, opening steps, h_open and the previous
/// step length move with their sphere; a ghost carries its owner's level and opening step, so
/// synchronisation (level <= tz) and each pair's step are known on every rank that holds the pair.
/// Per base step: drift of the owned spheres and of the ghosts (with the velocity last sent), the
/// state of the ghosts that opened a step now (halo_opened; or an exchange; movers at k/4, so
/// that a near pair, gap < k/2, is covered), the new levels of the owned synchronised spheres,
/// their halo (ghost := owner's level), then the equalisation to the fixed point in rounds: a
/// local equalisation; if it changed a sphere that is a ghost elsewhere (on any rank: one
/// allreduce), a halo in which a ghost takes min(local, owner's) level (LevelRules::lower: a
/// promotion is mirrored exactly) and another round. The rule is monotone and order
/// free (level_rules.hpp), so this is the fixed point of one rank; levels, hence forces and
/// trajectories, equal the one-rank run bit for bit. The owned active spheres predict and are
/// sent (v, w, predicted v, w: halo_synced; every ghost's state after a rebuild of the local set)
/// before the contacts of all locally active spheres are computed.
/// Bonds (bonds.hpp; domain_bonds.cpp). A rank holds every intact bond with an own end, in bond
/// order (the one-rank order restricted), and evaluates it from the same inputs as the rank that
/// holds its other end, so that a bond across two ranks is evaluated on both, identically (its
/// shear force, moments and breakage too), and each own sphere receives the one-rank force, sums
/// in the one-rank order. A bond belongs to the rank owning its sphere id_a (the diagnostics,
/// files and routing count it there); at an exchange the owner sends it to the new owners of both
/// ends (a broken bond to that of id_a only, which keeps it for the files). The ghosts reach at
/// least the longest intact bond (allreduced at each exchange), so both ends of every bond a rank
/// holds are in its local set until the next exchange (bonds are never created during a run).
/// Multi-rate steps: every rank runs the bond terms of the level rules (BondLevels) over the bonds
/// it holds, so the equalisation rounds above reach the one-rank fixed point with bonds too, and
/// both ends of a bond are synchronised together on every rank that holds it.
/// Input in blocks (domain_blocks.cpp; the driver's fresh start from an ssdem.spheres file and its
/// restart, both without bonds). Rank r reads only the rows [dense_first(N, P, r), dense_first(N,
/// P, r + 1)) of the input (common::read_sphere_rows, read_checkpoint_rows) and the dense block
/// of the checkpoint's history rows; the set-up's global quantities come from the summary
/// (sphere_summary_mpi.hpp), the ORB tree from the collective build; the rows move to their owners
/// and the history through a directory of ids, so no rank holds more than O(N / P) rows at any
/// time. The owned state is then the one the full-set constructors build, bit for bit (a ghost-
/// ghost pair's record, whose force no rank uses, is no longer kept). With bonds every rank still
/// reads all the spheres (bond generation and the bond checks need every sphere).
#pragma once
#include <memory>
#include <optional>
#include <unordered_map>

#include "ssdem/mpi/comm.hpp"
#include "ssdem/mpi/gravity_let.hpp"
#include "ssdem/mpi/orb.hpp"
#include "ssdem/simulation.hpp"
#include "ssdem/sphere_summary.hpp"

namespace ssdem::mpi {

/// Distance from p to the box [lo, hi] (0 inside): the ghost criterion of an exchange.
inline double box_distance(const Vec3& p, const Vec3& lo, const Vec3& hi) {
  return (lo - p).cwiseMax(p - hi).cwiseMax(Vec3::Zero()).norm();
}
/// The same for a box stored as 3 + 3 doubles (lo, hi), as the exchanges gather them.
inline double box_distance(const Vec3& p, const double* lohi) {
  return box_distance(p, Vec3(lohi[0], lohi[1], lohi[2]), Vec3(lohi[3], lohi[4], lohi[5]));
}

/// Communication and decomposition counters of this rank.
struct DomainStats {
  std::int64_t exchanges = 0, rebalances = 0, gravity_gathers = 0, steps = 0;
  std::int64_t level_rounds = 0;  ///< multi-rate equalisation rounds (>= 1 per base step)
  std::int64_t mover_checks = 0;  ///< base steps at which spheres past the exchange distance were checked
  std::int64_t mover_reductions = 0;  ///< of those, the steps not ruled out by movers_far_apart (tested and reduced)
  std::int64_t check_parts = 0;   ///< failure-check parts this rank sent (only a failing part travels)
  std::int64_t foreign_pairs = 0;  ///< listed ghost-ghost pairs skipped, summed over the evaluations
  /// pair evaluations by the kernel, and those of a pair with a ghost member (the ghost's owner
  /// evaluates the pair too: a pair across two ranks is computed on both), summed likewise
  std::int64_t kernel_pairs = 0, shared_pairs = 0;
  double bytes_halo = 0, bytes_exchange = 0, bytes_gravity = 0, bytes_other = 0;  ///< sent [B]
  double wall_comm = 0;  ///< seconds in communication calls
  /// Adds one contact evaluation's pair counts.
  void add(const ContactStats& c) {
    foreign_pairs += static_cast<std::int64_t>(c.foreign_pairs);
    kernel_pairs += static_cast<std::int64_t>(c.kernel_pairs);
    shared_pairs += static_cast<std::int64_t>(c.shared_pairs);
  }
};

class DomainSim {
 public:
  /// Tests: at a mover check that movers_far_apart rules out (domain_movers.cpp), run the ranks'
  /// test and its reduction anyway and throw std::logic_error (every rank) if it finds a near pair.
  static inline bool audit_movers = false;
  /// Fresh start: every rank passes the same full set of spheres and configuration.
  DomainSim(Comm& comm, const Spheres& all, SimConfig cfg, double imbalance = 0.1);
  /// Restart: every rank passes the same full state (e.g. read from a checkpoint).
  DomainSim(Comm& comm, const SimState& all, SimConfig cfg, double imbalance = 0.1);
  /// Where a rank's block of the input lies ("Input in blocks" above).
  struct Block {
    std::size_t first = 0;   ///< global index (file row) of the block's first sphere
    SphereSummary summary;   ///< of all the spheres (sphere_summary_mpi.hpp)
    bool restart = false;    ///< a checkpoint's state (step, time, accelerations), else a fresh start
    std::string file;        ///< the input, for the messages
  };
  /// Fresh start or restart from blocks: each rank passes its rows [at.first, at.first + n) of the
  /// input (common::dense_first blocks: the carried fields are its carried_block), without bonds,
  /// with the block's history records (a restart). Equal to the constructors above on the whole set.
  DomainSim(Comm& comm, const SimState& block, const Block& at, SimConfig cfg, double imbalance = 0.1);
  DomainSim(const DomainSim&) = delete;  // members refer to each other (BondLevels)
  DomainSim& operator=(const DomainSim&) = delete;

  void step();
  /// Collective: decide a failure check still pending (a run that ends inside a gravity block:
  /// check_state decides inside blocks at the next base step); throws as the check does.
  void settle() {
    if (pending_.step >= 0) verdict(comm_.gather(parts_to_send()));
  }
  bool at_gravity_boundary() const { return step_ == block_start_; }
  /// As Simulation::want_potential: the next gravity evaluations also give each own sphere's
  /// potential (the same bits as one rank's), for the driver's next series row.
  void want_potential(bool on) { want_pot_ = on; }
  /// Collective: the series row's quantities, on every rank, the same bits as one rank's
  /// Simulation::diagnostics (exact sums over the ranks; domain_diagnostics.cpp). Evaluates the
  /// potential (one gravity evaluation, the held field untouched) unless the block's own
  /// evaluation gave it at this step (want_potential).
  Diagnostics diagnostics();
  int gravity_block() const { return block_; }
  void set_end_step(std::int64_t s) { end_step_ = s; }
  std::int64_t step_count() const { return step_; }
  double time() const { return time_; }
  const SimConfig& config() const { return cfg_; }
  const CadenceStats& cadence_stats() const { return cadence_; }
  const DomainStats& stats() const { return stats_; }
  const PhaseTimes& times() const { return times_; }
  std::size_t owned() const { return own_.size(); }
  std::size_t ghosts() const { return sp_.size() - own_.size(); }
  std::size_t global_count() const { return n_global_; }
  /// The distributed tree (null with direct gravity or without self-gravity).
  const DistributedTree* tree() const { return tree_.get(); }
  /// Collective: contacts between spheres of different ranks (summed over the ranks).
  std::size_t cross_rank_contacts() const;
  /// Collective: the rank owning the sphere with this id (-1 if none).
  int owner_of_id(std::uint64_t id) const;
  /// Collective: the full state on rank 0, equal to Simulation::state() of a one-rank run (carried
  /// fields included; history in the one-rank order); an empty state on the other ranks.
  SimState gather_state() const;
  /// Keep this rank's part of a verified state every `every` steps, at gravity-block boundaries
  /// (0: off), for the save after a numerical failure (as Simulation::set_keep_last_good): a copy
  /// of the rank's packed own spheres and history, no communication.
  void set_keep_last_good(std::int64_t every);
  /// Collective: the last kept state on rank 0, as gather_state() returned it then; nullopt where
  /// none was kept (on every rank alike).
  std::optional<SimState> gather_last_good() const;
  /// This rank's part of the state, as the collective writers take it (io_mpi.hpp): its own
  /// spheres in any order with `row`, their indices (the one-rank file rows), their integrator
  /// arrays, and the contact records it owns; step, time and gravity block as the one-rank state.
  struct Local {
    SimState st;
    std::vector<std::uint64_t> row;
    /// per history record its file order key (history_key), taken when the state was packed
    std::vector<std::pair<std::uint64_t, std::uint64_t>> hkey;
    bool has_prev = false;  ///< the state has a_prev, alpha_prev (every rank alike, even one with no spheres)
    /// the bonds this rank owns (id_a own), their rows in the one-rank bond order (file rows), and
    /// their spheres' rows (2 per bond); st.bonds.released_base is the run's on every rank
    std::vector<std::uint64_t> brow, bsph;
  };
  Local local_state() const;
  /// The part of the last kept state (set_keep_last_good); nullopt where none was kept (on every
  /// rank alike).
  std::optional<Local> last_good_local() const;
  /// The file order key of a history record this rank owns (the one-rank order): pairs by (index
  /// a, index b), then wall contacts by (index, wall id), as (first, second). Both members are in
  /// the local set (the record's contact is); keys are taken when a state is packed, so no rank
  /// needs the ids of all spheres.
  std::pair<std::uint64_t, std::uint64_t> history_key(const HistoryRecord& r) const;
  /// The carried per-sphere fields (e.g. damage from mpm2spheres) of this rank's fixed block of
  /// sphere indices [dense_first(N, P, r), dense_first(N, P, r + 1)) (common/sorted_rows.hpp), in
  /// index order: the rows a collective writer gives this rank. No rank holds all of them.
  const std::vector<common::Field>& carried_block() const { return carried_; }
  /// Collective: the multi-rate level statistics of all ranks (rank 0; sums; empty in single rate).
  LevelStats gather_level_stats() const;
  /// Bytes per sphere held by this rank (local set, contact system, gravity tree), divided by the
  /// spheres it owns.
  double bytes_per_owned_sphere() const;
  /// Bonds of the whole run (intact and broken; the same on every rank).
  std::size_t global_bonds() const { return nb_global_; }
  /// Bonds this rank held at the last exchange: intact then, with an own end (a bond across two
  /// ranks is counted on both; those broken since are no longer evaluated).
  std::size_t local_bonds() const { return bonds_ ? bonds_->bonds().size() : 0; }
  /// Collective: intact bonds whose ends are owned by different ranks (summed over the ranks).
  std::size_t cross_rank_bonds() const;

 private:
  /// Owned spheres with their integrator state, in any order (between migration and rebuild).
  struct Owned {
    std::vector<std::uint64_t> g;
    Spheres sp;
    std::vector<Vec3> a, alpha, ag, a_prev, alpha_prev;
    std::vector<std::uint8_t> level;  // multi-rate (empty in single rate)
    std::vector<std::int64_t> topen;
    std::vector<double> hopen, tau_prev;
  };
  void setup(const Spheres& all, const BondSet& bonds);
  void check_config() const;                       ///< the configuration's own checks (InputError)
  void resume_clock(const SimState& st);            ///< a restart's step, time and gravity block
  void setup_config(const SphereSummary& summary);  ///< the set-up that needs only the summary
  void distribute(const SimState& all);
  void distribute_block(const SimState& block, std::size_t first, const std::string& file);  ///< domain_blocks.cpp
  /// The block's history records on the owners of their members (the id directory; checks ids).
  std::vector<HistoryRecord> route_block_history(const SimState& block, std::size_t first,
                                                 const std::vector<int>& owner, const std::string& file);
  void exchange();
  void rebuild_local(Owned own, const std::vector<HistoryRecord>& recs);
  void halo_update();
  /// Halo messages (owned slots send_[r] -> ghost slots recv_[r]) of `record` bytes per sphere:
  /// point-to-point with the ranks that share ghosts only (Comm::neighbours).
  std::vector<std::vector<char>> halo(const std::vector<std::vector<char>>& out, std::size_t record);
  void compute_forces(bool initial);
  void compute_gravity();
  void close_gravity_block();
  /// The end-of-step failure check: the verdict (an allreduce) at gravity-block boundaries, else
  /// carried by the next base step's movers allgather (need_exchange).
  void check_state();
  /// A rank's part of a failure check: its first non-finite sphere (global index, id; g = -1:
  /// none) and its largest overlap with the pair's ids (id_b = id_a: a wall).
  struct Pending {
    std::uint64_t bad_g = ~std::uint64_t{0}, bad_id = 0;
    double overlap = 0.0;
    std::uint64_t id_a = 0, id_b = 0;
    std::int64_t step = -1;
  };
  /// Decide the check of pending_.step from every rank's part (the same on every rank, in rank
  /// order): throw as the one-rank check does (the same message: the first non-finite sphere in
  /// index order, or the largest overlap, the lowest rank's on a tie); clears pending_.
  void verdict(const std::vector<Pending>& all);
  /// This rank's part if it fails the check (a non-finite sphere, or an overlap beyond the limit),
  /// else nothing: the verdict of the failing parts alone is the verdict of all (the first
  /// non-finite index and the largest overlap are among them, ties in the same rank order), and a
  /// healthy step sends no part (before 2026-12-06 every rank sent its part every base step: 96 B
  /// per rank in the movers' allgather, which every rank receives, O(P) per rank and step).
  std::vector<Pending> parts_to_send();
  Pending pending_;  ///< this rank's part of the last check not yet decided together
  // multi-rate (domain_multirate.cpp)
  void setup_multirate();
  void step_multirate();
  void halo_opened(std::int64_t s0);
  void halo_synced();
  void halo_levels(bool assign, int tz);
  void multirate_forces(const Substep& ss);
  double exchange_distance() const { return (cfg_.multirate ? 0.25 : 0.5) * skin_; }
  bool need_exchange();  ///< collective (domain_movers.cpp)
  std::vector<HistoryRecord> owned_history() const;
  void pack_owned(std::size_t i, std::vector<char>& b) const;
  void unpack_owned(const std::vector<char>& b, std::size_t& off, Owned& own) const;
  /// This rank's part of the state: packed own spheres and owned history, with the scalars.
  struct Packed {
    std::vector<char> spheres, history, bonds;
    std::int64_t step = 0, grav_step = -1;
    double time = 0.0;
    int block = 1;
    bool has_prev = false;
  };
  Packed pack_local() const;
  SimState assemble(const Packed& mine) const;  ///< collective: the full state on rank 0
  /// pack_owned records (of one or more ranks, concatenated) and (key, history record) triples -> arrays in
  /// arrival order, with the scalars of `scalars`.
  Local unpack(const std::vector<char>& spheres, const std::vector<char>& history, const std::vector<char>& bonds,
               const Packed& scalars) const;
  // bonds (domain_bonds.cpp)
  void setup_bonds(const BondSet& all, const Spheres& sp);
  /// The bonds of the full state `all` that this rank holds under the ORB `orb_` (into bonds_in_),
  /// and the longest intact bond (bond_reach_).
  void pick_bonds(const SimState& all);
  /// Collective: the longest intact bond now (bond_reach_), then the bond records this rank owns
  /// routed to the ranks `dest` of their ends (dest: the new owner of each local slot).
  std::vector<std::vector<char>> route_bonds(const std::vector<int>& dest);
  /// After the local set is rebuilt: bonds_ from the records in bonds_in_ (any order; consumed).
  void place_bonds();
  /// The records of the bonds this rank owns (for Packed), and their inverse into `L`.
  void pack_bonds(std::vector<char>& b) const;
  void unpack_bonds(const std::vector<char>& b, Local& L) const;
  /// Collective: the bond terms of a series row (Diagnostics::bond_*) into d and the elastic sum.
  void bond_diagnostics(Diagnostics& d, common::ExactSum& elastic) const;
  std::unique_ptr<BondSystem> bonds_;  ///< intact bonds with an own end at the last exchange
  std::unique_ptr<BondLevels> blevels_;  ///< multi-rate: their terms in the level rules
  std::vector<std::uint64_t> bg_;      ///< bond row (one-rank order) of each bond of bonds_
  std::vector<std::uint8_t> bown_;     ///< 1 where this rank owns bond k of bonds_ (id_a own)
  BondSet retired_;                    ///< broken bonds this rank owns (not evaluated any more)
  std::vector<std::uint64_t> retired_g_, retired_sph_;  ///< their rows; their spheres' rows (2 each)
  std::vector<char> bonds_in_;         ///< bond records waiting for the rebuild of the local set
  std::size_t nb_global_ = 0;
  double bond_base_ = 0.0;   ///< BondSet::released_base of the run's bonds
  double bond_reach_ = 0.0;  ///< longest intact bond at the last exchange [m]
  std::int64_t keep_every_ = 0;
  std::optional<Packed> last_good_;
  void unpack_multirate(const std::vector<char>& b, std::size_t& off, Owned& own) const;

  Comm& comm_;
  SimConfig cfg_;
  double imbalance_;
  double reach_ = 0, skin_ = 0, smax_ = 0;
  std::vector<double> boxes_;  // every rank's own-sphere box at the last exchange: (flag, lo, hi) x ranks
  OrbTree orb_;
  // local set L (owned + ghosts, global-index order)
  Spheres sp_;
  std::vector<std::uint64_t> gidx_;
  std::vector<std::uint8_t> mine_;
  std::vector<std::uint32_t> own_;
  std::vector<Vec3> a_, alpha_, ag_, ag_old_, a_prev_, alpha_prev_, vpred_, wpred_, F_, T_, xex_;
  bool has_prev_ = false;
  bool ghosts_fresh_ = true;  ///< the local set was rebuilt: its ghosts carry no predicted velocities
  std::unordered_map<std::uint64_t, std::uint32_t> slot_of_id_;
  std::vector<std::vector<std::uint32_t>> send_, recv_;  // halo: owned slots sent to / ghost slots from each rank
  std::size_t n_global_ = 0;  ///< spheres of the whole run
  std::vector<double> pot_;  ///< potential of the own spheres (local slots) at pot_step_
  bool want_pot_ = false;
  std::int64_t pot_step_ = -1;
  std::vector<common::Field> carried_;  // carried per-sphere fields of this rank's index block (carried_block)
  std::unique_ptr<ContactSystem> contacts_;
  std::unique_ptr<DistributedTree> tree_;
  ContactStats cstats_;
  LevelRules lr_;  // multi-rate: levels of the local set (owned + ghosts)
  std::vector<std::int64_t> topen_;
  std::vector<double> hopen_, tau_prev_, tau_own_;
  std::vector<std::uint32_t> active_, own_active_;
  std::vector<std::size_t> subset_off_;
  ContactSystem::Subset subset_;
  SubsetCache subsets_;  ///< subset_'s pairs kept per synchronisation level (take_subset)
  LevelStats lstats_;
  std::int64_t step_ = 0, block_start_ = 0, end_step_ = 0, grav_step_ = -1;
  double time_ = 0.0;
  int block_ = 1;
  CadenceStats cadence_;
  mutable DomainStats stats_;  // counters (gather_state is const but communicates)
  PhaseTimes times_;
};

}  // namespace ssdem::mpi
