/// @file simulation.hpp
/// Time integration of spheres under self-gravity, uniform gravity and soft-sphere contacts.
///
/// Integrator: second-order leapfrog kick-drift-kick for positions, velocities and spins
/// (Schwartz, Richardson & Michel 2012 eq. 1; pkdgrav bKDK = 1):
///   v_{n+1/2} = v_n + (h/2) a_n,  w_{n+1/2} = w_n + (h/2) alpha_n
///   x_{n+1}   = x_n + h v_{n+1/2}
///   a_{n+1} = F_c/m + g_self + g_uniform,  alpha_{n+1} = T_c / I,  I = (2/5) m s^2
///   v_{n+1} = v_{n+1/2} + (h/2) a_{n+1},  w_{n+1} likewise.
/// Contact forces use predicted velocities. pkdgrav (ssdem.md §1.1): v_pred = v_{n+1/2} + (h/2) a_n,
/// whose O(h^2) error in the dashpot force gives e_n errors of 1.4e-3 at 50 steps per contact
/// (e_n = 0.55). Default here ("extrapolated", a deviation from pkdgrav for accuracy):
/// v_pred = v_{n+1/2} + (h/2)(2 a_n - a_{n-1}), i.e. a_{n+1} extrapolated linearly; measured e_n
/// error 1.2e-4 (e_n = 0.55) and 8e-4 (e_n = 0.2) at 50 steps (test_nbody_contact). a_{n-1} is
/// part of the checkpointed state. contact.predictor = "pkdgrav" restores the pkdgrav form.
/// Multiple time-stepping for gravity ("gravity.every = k"): impulse r-RESPA (Tuckerman, Berne &
/// Martyna 1992, J. Chem. Phys. 97:1990): self-gravity is applied as an outer half-kick
/// v += (k h/2) g_self at the start and at the end of each block of k contact steps and is
/// evaluated once per block at the block's end positions; the contact forces and the uniform
/// field are integrated by the inner KDK above. The scheme is symplectic and time-reversible for
/// conservative forces (bounded energy error, no drift); k = 1 is plain KDK. Velocities are the
/// physical ones only at block boundaries (step % k == 0): diagnostics and outputs should be taken
/// there. Its error against k = 1 is measured (tests, pipelines/nbody), not assumed.
/// Error-controlled cadence (adaptive_gravity; the scene default): the block length k is chosen
/// anew at the end of every block from the force change the block just measured. With g_i the
/// new and g_i' the previous evaluation (k_prev steps apart) and g_rms the rms of |g_i|,
///   c   = sqrt(sum_i |g_i - g_i'|^2 / sum_i |g_i|^2)           (rms relative change, the
///         measure of the tree's rms force error)
///   c_1 = max_i |g_i - g_i'| / max(|g_i|, 0.1 g_rms)           (largest change of one sphere)
///   k = floor(k_prev / max(c / eta, c_1 / 0.1)), clamped to [1, min(2 k_prev, k_max)] and to the
///       run's end,
/// i.e. the next block may change the forces by about eta (rms, relative) and no sphere's by more
/// than 10 % if they keep changing at the measured rate (0.1: above the per-sphere jumps of the
/// tree's own error when the tree's cells change, ~1e-2 to 2e-2, which would
/// otherwise pin k to 1). Forces that change fast (a close encounter, a fragment hitting a pile)
/// give k = 1, every step. The first block after a start is one step. The measured
/// c of every block is the reported estimate of the cadence's force error (gravity_cadence_stats);
/// the impulse scheme applies (g' + g)/2 on average over a block, so the force error it makes is
/// at most c/2 and, for a force changing linearly, second order. A block's length is part of the
/// state at its start (SimState::gravity_block; checkpoints store it), so restarts are exact.
/// Deviation from pkdgrav: pkdgrav evaluates gravity every step (iMaxRung = 1); predicted
/// velocities for the dashpots here include the contact/uniform acceleration only (the gravity
/// impulse is nearly uniform over a contact pair). With multi-rate steps, spheres on steps shorter
/// than the block hold the block's field instead of taking its impulses (gravity.inner_steps =
/// "held", multirate.hpp "Self-gravity inside a block"); single-rate stepping uses the impulses.
/// A scene enables only its physics: without self-gravity no tree is built; without contacts
/// no neighbour list exists.
#pragma once
#include <cmath>
#include <memory>
#include <optional>
#include <vector>

#include "ssdem/bonds.hpp"
#include "ssdem/contacts.hpp"
#include "ssdem/diagnostics.hpp"
#include "ssdem/gravity.hpp"
#include "ssdem/level_rules.hpp"
#include "ssdem/multirate.hpp"
#include "ssdem/spheres.hpp"
#include "ssdem/team_tuner.hpp"

namespace ssdem {

struct SimConfig {
  double dt = 0.0;
  bool self_gravity = false;
  bool direct_gravity = false;  ///< O(N^2) instead of the tree
  GravityParams gravity;
  int gravity_every = 1;           ///< fixed cadence: block length (adaptive_gravity = false)
  bool adaptive_gravity = false;   ///< error-controlled cadence (see file comment)
  double gravity_tolerance = 1e-3; ///< eta: relative force change allowed per block
  int gravity_max_every = 64;      ///< k_max of the adaptive cadence
  /// Multi-rate: spheres on steps shorter than the gravity block take the block-start field as a
  /// force held through the block plus a trapezoid residual at its end (true: "held"), or the
  /// block's two impulses (false: "impulse"); multirate.hpp, "Self-gravity inside a block".
  bool gravity_held = true;
  Vec3 uniform_g = Vec3::Zero();
  bool contacts = false;
  ContactParams contact;
  std::vector<Plane> walls;
  double skin = 0.0;             ///< neighbour-list skin [m]; <= 0: 0.25 * max radius
  double max_overlap_frac = 1.0; ///< overlap / smaller radius that stops the run (exit 3)
  double min_steps_per_contact = 10.0;
  bool extrapolated_predictor = true;  ///< false: pkdgrav predictor v_{n+1/2} + (h/2) a_n
  BondSet bonds;  ///< bonds of a fresh start (bonds.hpp; a restart takes SimState::bonds); needs contacts
  bool multirate = false;              ///< block time steps on power-of-two levels (multirate.hpp)
  double pair_steps_per_contact = 30;  ///< N of the per-pair level rule (time.steps_per_contact)
  /// run.teams: the team rule measured while the run goes ("auto", team_tuner.hpp), or one rule
  /// throughout ("size": teams by loop size alone, omp_team.hpp). Same bits either way.
  TeamMode teams = TeamMode::automatic;
};

/// g's data where multi-rate spheres on steps shorter than the gravity block hold the field
/// (multi-rate, self-gravity, gravity.inner_steps = "held"; g holds the n local spheres), else null
/// (the block's impulses only): the gheld argument of the kicks (multirate.hpp).
inline const Vec3* held_field(const SimConfig& c, const std::vector<Vec3>& g, std::size_t n) {
  return c.multirate && c.self_gravity && c.gravity_held && g.size() == n ? g.data() : nullptr;
}

/// The complete dynamic state (what a checkpoint holds): restart from it is bit-identical.
struct SimState {
  Spheres sp;
  std::vector<Vec3> a, alpha, ag;
  std::int64_t step = 0;
  double time = 0.0;
  std::int64_t gravity_step = -1;  ///< step at which ag was computed
  int gravity_block = 0;           ///< length of the gravity block starting at `step` (0: gravity_every)
  std::vector<Vec3> a_prev, alpha_prev;  ///< previous contact accelerations (predictor); may be empty
  std::vector<HistoryRecord> history;
  BondSet bonds;  ///< bonds with their state (empty: none)
  std::vector<std::uint8_t> level;  ///< multi-rate level per sphere (empty: single rate / all 0)
  std::vector<double> tau_prev;     ///< multi-rate: length of each sphere's previous step [s]
  double energy0 = NAN;  ///< the run's Diagnostics::accounted() at its first row [J] (NaN: unknown)
  /// Checkpoints of a sorted run (sphere_order.hpp): the file row of each stored sphere, the
  /// arrays above being in file order (empty: storage order is the file order). Simulation
  /// neither reads nor sets it.
  std::vector<std::uint32_t> sphere_order;
};


/// What the adaptive gravity cadence did: blocks (= evaluations after the first), their lengths
/// and the measured relative force change per block (c in the file comment).
struct CadenceStats {
  std::int64_t blocks = 0, steps = 0, min_block = 0, max_block = 0;
  double max_change = 0, sum_change = 0;  ///< c (rms)
  double max_change_one = 0;               ///< c_1 (one sphere)
  double mean_block() const { return blocks ? static_cast<double>(steps) / static_cast<double>(blocks) : 0.0; }
  double mean_change() const { return blocks ? sum_change / static_cast<double>(blocks) : 0.0; }
};

/// Seconds spent per phase: wall clock, and process CPU time (all threads; "core-seconds").
struct PhaseTimes {
  double gravity = 0, neighbours = 0, contacts = 0, integrate = 0;
  double cpu_gravity = 0, cpu_neighbours = 0, cpu_contacts = 0, cpu_integrate = 0;
  double levels = 0;  ///< multi-rate level rule and equalisation (wall; included in `integrate`)
  std::int64_t steps = 0, gravity_evals = 0;
  std::int64_t neighbour_builds = 0;  ///< pair-list rebuilds (in `neighbours`; not the one at a restart)
};

/// a = g_uniform + F/m and, with contacts, alpha = T/I for the spheres idx[0..count) (0..count if
/// idx is null); the per-sphere step of every integrator (Simulation, mpi::DomainSim).
void accelerations(const Spheres& sp, const std::vector<Vec3>& F, const std::vector<Vec3>& T, const Vec3& g,
                   bool contacts, const std::uint32_t* idx, std::size_t count, std::vector<Vec3>& a,
                   std::vector<Vec3>& alpha);

class Simulation {
 public:
  /// Fresh start: validates dt against the contact time, computes the initial forces.
  Simulation(Spheres sp, SimConfig cfg);
  /// Restart from a saved state (forces and history taken from the state; nothing recomputed).
  Simulation(SimState st, SimConfig cfg);
  Simulation(const Simulation&) = delete;  // members refer to each other (BondLevels)
  Simulation& operator=(const Simulation&) = delete;

  /// Advance one step. Throws common::NumericalError on NaN/Inf or runaway overlap; the state
  /// is then the failing one, and last_good() holds the last verified state.
  void step();
  /// True when the current step ends a gravity block (velocities are the physical ones there).
  bool at_gravity_boundary() const { return step_ == block_start_; }
  /// Let the gravity evaluations of the next steps compute each sphere's potential as well (the
  /// driver's next series row is due: diagnostics() then uses it instead of evaluating gravity
  /// again; the forces are the same bits either way).
  void want_potential(bool on) { want_pot_ = on; }
  /// True if each sphere's potential is that of the current positions (diagnostics() then
  /// evaluates no gravity).
  bool potential_current() const { return pot_step_ == step_; }
  /// Length of the current gravity block (steps).
  int gravity_block() const { return block_; }
  /// Blocks never extend past this step (the run's last step); 0 = no limit.
  void set_end_step(std::int64_t s) { end_step_ = s; }
  const CadenceStats& cadence_stats() const { return cadence_; }
  /// Multi-rate levels (empty arrays in single-rate runs).
  const LevelStats& level_stats() const { return lstats_; }
  const std::vector<std::uint8_t>& levels() const { return lr_.level; }
  /// Multi-rate level l_b of each bond (empty without bonds or in single-rate runs).
  const std::vector<std::uint8_t>& bond_levels() const {
    static const std::vector<std::uint8_t> none;
    return blevels_ ? blevels_->levels() : none;
  }
  void run(std::int64_t nsteps) {
    for (std::int64_t k = 0; k < nsteps; ++k) step();
  }

  /// Process CPU time per phase (PhaseTimes::cpu_*), off by default: each reading is a system
  /// call (clock_gettime of the process CPU clock, which sums every thread's), two per phase per
  /// step, which took ~10 % of the samples of a 2 493-sphere debris run (perf; nbody/README.md).
  /// The benchmarks turn it on; wall times per phase are always kept.
  void set_cpu_timing(bool on) { cpu_timing_ = on; }
  const Spheres& spheres() const { return sp_; }
  /// (the next multi-rate step then treats every sphere as kicked: a velocity may have changed;
  /// call it again before every change, a reference kept across steps bypasses that)
  Spheres& spheres_mut() {
    kicks_known_ = false;
    return sp_;
  }
  std::int64_t step_count() const { return step_; }
  double time() const { return time_; }
  const SimConfig& config() const { return cfg_; }
  const ContactStats& contact_stats() const { return cstats_; }
  const PhaseTimes& times() const { return times_; }
  /// The team rule's choice (run.teams; team_tuner.hpp); tests force a rule through it.
  TeamTuner& team_tuner() { return tuner_; }
  const TeamTuner& team_tuner() const { return tuner_; }
  const std::vector<Vec3>& acceleration() const { return a_; }
  const std::vector<Vec3>& self_gravity_acceleration() const { return ag_; }
  bool has_tree() const { return tree_ != nullptr; }
  bool has_contacts() const { return contacts_ != nullptr; }
  const ContactSystem* contact_system() const { return contacts_.get(); }
  const TreeGravity* tree() const { return tree_.get(); }
  const BondSystem* bond_system() const { return bonds_.get(); }

  /// Energies (potential recomputed at the current positions if stale), momenta, contacts.
  Diagnostics diagnostics();
  /// Full state for checkpoints.
  SimState state() const;
  /// Keep a verified copy of the state every `every` steps (0: off) for exit-3 saves.
  void set_keep_last_good(std::int64_t every) {
    keep_every_ = every;
    if (every > 0 && !last_good_) last_good_ = state();
  }
  const std::optional<SimState>& last_good() const { return last_good_; }
  /// Bytes per sphere of all arrays (spheres, integrator, contacts, tree).
  double bytes_per_sphere() const;
  /// This simulation was started from `before`'s state(), renumbered (sphere_order.hpp): take
  /// over its phase times (plus `extra_neighbours_s` of wall, the renumbering's), cadence, level
  /// and contact counters, end step, CPU timing and last-good cadence, so that the run reports
  /// its totals. The team rule (run.teams = auto) starts measuring again.
  void continue_counters(const Simulation& before, double extra_neighbours_s);

 private:
  void setup();
  void compute_forces(bool initial);
  void compute_gravity(bool with_pot);
  /// Throws NumericalError on a non-finite state or an overlap beyond contact.max_overlap_fraction.
  /// With `only`, the state of those spheres alone (see step_multirate).
  void check_state(const std::vector<std::uint32_t>* only = nullptr);
  void close_gravity_block();
  // multi-rate (multirate.cpp)
  void setup_multirate(const SimState* st);
  void step_multirate();
  void multirate_forces(const Substep& ss);
  std::unique_ptr<BondLevels> blevels_;  ///< bonds in the multi-rate level rule (only with bonds)
  void accelerations(const std::uint32_t* idx, std::size_t count);
  /// Process CPU time [s] when set_cpu_timing(true), else 0 (no system call).
  double cpu_now_() const;
  bool cpu_timing_ = false;
  LevelRules lr_;  ///< levels, synchronisation and the level rules (level_rules.hpp)
  std::vector<std::int64_t> topen_;
  std::vector<double> hopen_, tau_prev_;
  std::vector<std::uint32_t> active_;
  /// active_ names every sphere kicked since the last neighbour update but for a block's opening
  /// kicks (false before the first multi-rate step and after spheres_mut(): then all may be)
  bool kicks_known_ = false;
  std::vector<std::size_t> subset_off_;  ///< multirate_forces: per active sphere, its first pair slot
  ContactSystem::Subset subset_;
  SubsetCache subsets_;  ///< subset_'s pairs kept per synchronisation level (take_subset)
  LevelStats lstats_;

  SimConfig cfg_;
  Spheres sp_;
  std::vector<Vec3> a_, alpha_, ag_, vpred_, wpred_, F_, T_, a_prev_, alpha_prev_;
  std::vector<double> pot_;
  std::int64_t pot_step_ = -1, grav_step_ = -1;
  bool want_pot_ = false;  ///< want_potential()
  std::int64_t step_ = 0;
  double time_ = 0.0;
  std::int64_t block_start_ = 0, end_step_ = 0;
  int block_ = 1;
  std::vector<Vec3> ag_old_;
  CadenceStats cadence_;
  std::unique_ptr<ContactSystem> contacts_;
  std::unique_ptr<TreeGravity> tree_;
  std::unique_ptr<BondSystem> bonds_;  ///< only when the scene has bonds
  void setup_bonds(BondSet b);
  ContactStats cstats_;
  PhaseTimes times_;
  TeamTuner tuner_{cfg_.teams};
  std::int64_t keep_every_ = 0;
  std::optional<SimState> last_good_;
};

}  // namespace ssdem
