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
/// (k = the contact skin). An exchange is done when some sphere moved more than k/2 since the last
/// one (one allreduce per step): until then every sphere that can touch an owned one in the
/// contact step is a ghost, as |x_i - x_j| < s_i + s_j at a contact implies
/// |x_i(ex) - x_j(ex)| < 2 s_max + k. Between exchanges the ghosts' x, v, w and predicted v, w
/// are sent every step (15 doubles per ghost). At an exchange spheres migrate to the rank owning
/// their position (any rank: debris crossing several domains in one step), then ghosts are rebuilt.
/// Contacts. The local set L = owned + ghosts, in global-index order, runs the serial contact
/// system (contacts.hpp). Its per-sphere sums run over partners in ascending local index, which is
/// ascending global index, so an owned sphere's force equals the one-rank force bit for bit.
/// A pair across two ranks is evaluated on both (from identical inputs, so identically); only the
/// owned member's force is used. The pair's contact history belongs to the rank that owns the
/// member with the lower global index (the deterministic owner rule): at every exchange that
/// rank's record is sent to the new owners of both members and imported there, so the history
/// moves with its owner and the copies never diverge (ghost-ghost pairs, whose forces are unused,
/// are overwritten from the owner's record at the next exchange).
/// Gravity (replicated top: the ecosystem note's v1 design, not locally essential trees). At each
/// gravity evaluation the positions of all spheres are allgathered (32 B per sphere per rank), every
/// rank builds the same tree from them (gravity.hpp, index order) and walks only the sink groups
/// holding its own spheres: forces equal the one-rank forces bit for bit, at O(N) memory and
/// communication per rank per evaluation (fine to ~1e7 spheres; a distributed tree is left).
/// Cadence. The block length uses global sums of |g|^2 and |g - g'|^2: per-rank partial sums are
/// allgathered and added in rank order (deterministic for a given rank count; against one rank
/// they differ by round-off, which can change the integer block length only when it is within
/// ~1e-15 of an integer).
/// Bonds are not distributed yet: a scene with bonds on more than one rank is refused.
#pragma once
#include <memory>
#include <unordered_map>

#include "ssdem/mpi/comm.hpp"
#include "ssdem/mpi/orb.hpp"
#include "ssdem/simulation.hpp"

namespace ssdem::mpi {

/// Communication and decomposition counters of this rank.
struct DomainStats {
  std::int64_t exchanges = 0, rebalances = 0, gravity_gathers = 0, steps = 0;
  double bytes_halo = 0, bytes_exchange = 0, bytes_gravity = 0, bytes_other = 0;  ///< sent [B]
  double wall_comm = 0;  ///< seconds in communication calls
};

class DomainSim {
 public:
  /// Fresh start: every rank passes the same full set of spheres and configuration.
  DomainSim(Comm& comm, const Spheres& all, SimConfig cfg, double imbalance = 0.1);
  /// Restart: every rank passes the same full state (e.g. read from a checkpoint).
  DomainSim(Comm& comm, const SimState& all, SimConfig cfg, double imbalance = 0.1);

  void step();
  bool at_gravity_boundary() const { return step_ == block_start_; }
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
  std::size_t global_count() const { return gsp_.size(); }
  /// Collective: contacts between spheres of different ranks (summed over the ranks).
  std::size_t cross_rank_contacts() const;
  /// Collective: the rank owning the sphere with this id (-1 if none).
  int owner_of_id(std::uint64_t id) const;
  /// Collective: the full state on rank 0, equal to Simulation::state() of a one-rank run (carried
  /// fields included; history in the one-rank order); an empty state on the other ranks.
  SimState gather_state() const;
  /// Bytes per sphere held by this rank (local set, contact system, replicated gravity arrays),
  /// divided by the spheres it owns.
  double bytes_per_owned_sphere() const;

 private:
  /// Owned spheres with their integrator state, in any order (between migration and rebuild).
  struct Owned {
    std::vector<std::uint64_t> g;
    Spheres sp;
    std::vector<Vec3> a, alpha, ag, a_prev, alpha_prev;
  };
  void setup(const Spheres& all);
  void distribute(const SimState& all);
  void exchange();
  void rebuild_local(Owned own, const std::vector<HistoryRecord>& recs);
  void halo_update();
  void compute_forces(bool initial);
  void compute_gravity();
  void close_gravity_block();
  void check_state();
  std::vector<HistoryRecord> owned_history() const;
  void pack_owned(std::size_t i, std::vector<char>& b) const;

  Comm& comm_;
  SimConfig cfg_;
  double imbalance_;
  double reach_ = 0, skin_ = 0;
  OrbTree orb_;
  // local set L (owned + ghosts, global-index order)
  Spheres sp_;
  std::vector<std::uint64_t> gidx_;
  std::vector<std::uint8_t> mine_;
  std::vector<std::uint32_t> own_;
  std::vector<Vec3> a_, alpha_, ag_, ag_old_, a_prev_, alpha_prev_, vpred_, wpred_, F_, T_, xex_;
  bool has_prev_ = false;
  std::unordered_map<std::uint64_t, std::uint32_t> slot_of_id_;
  std::vector<std::vector<std::uint32_t>> send_, recv_;  // halo: owned slots sent to / ghost slots from each rank
  // replicated for gravity: all spheres (id, m, s constant; x gathered), global order
  Spheres gsp_;
  std::vector<std::uint8_t> gmine_;
  std::vector<Vec3> gacc_;
  std::vector<common::Field> carried_;  // rank 0: carried per-sphere fields (global order)
  std::unique_ptr<ContactSystem> contacts_;
  std::unique_ptr<TreeGravity> tree_;
  ContactStats cstats_;
  std::int64_t step_ = 0, block_start_ = 0, end_step_ = 0, grav_step_ = -1;
  double time_ = 0.0;
  int block_ = 1;
  CadenceStats cadence_;
  mutable DomainStats stats_;  // counters (gather_state is const but communicates)
  PhaseTimes times_;
};

}  // namespace ssdem::mpi
