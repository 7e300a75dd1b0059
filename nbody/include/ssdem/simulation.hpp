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
/// Deviation from pkdgrav: pkdgrav evaluates gravity every step (iMaxRung = 1); predicted
/// velocities for the dashpots here include the contact/uniform acceleration only (the gravity
/// impulse is nearly uniform over a contact pair).
/// A scene enables only its physics: without self-gravity no tree is built; without contacts
/// no neighbour list exists.
#pragma once
#include <memory>
#include <optional>
#include <vector>

#include "ssdem/bonds.hpp"
#include "ssdem/contacts.hpp"
#include "ssdem/gravity.hpp"
#include "ssdem/spheres.hpp"

namespace ssdem {

struct SimConfig {
  double dt = 0.0;
  bool self_gravity = false;
  bool direct_gravity = false;  ///< O(N^2) instead of the tree
  GravityParams gravity;
  int gravity_every = 1;
  Vec3 uniform_g = Vec3::Zero();
  bool contacts = false;
  ContactParams contact;
  std::vector<Plane> walls;
  double skin = 0.0;             ///< neighbour-list skin [m]; <= 0: 0.25 * max radius
  double max_overlap_frac = 1.0; ///< overlap / smaller radius that stops the run (exit 3)
  double min_steps_per_contact = 10.0;
  bool extrapolated_predictor = true;  ///< false: pkdgrav predictor v_{n+1/2} + (h/2) a_n
  BondSet bonds;  ///< bonds of a fresh start (bonds.hpp; a restart takes SimState::bonds); needs contacts
};

/// The complete dynamic state (what a checkpoint holds): restart from it is bit-identical.
struct SimState {
  Spheres sp;
  std::vector<Vec3> a, alpha, ag;
  std::int64_t step = 0;
  double time = 0.0;
  std::int64_t gravity_step = -1;  ///< step at which ag was computed
  std::vector<Vec3> a_prev, alpha_prev;  ///< previous contact accelerations (predictor); may be empty
  std::vector<HistoryRecord> history;
  BondSet bonds;  ///< bonds with their state (empty: none)
};

struct Diagnostics {
  double kinetic = 0, rotational = 0, potential_self = 0, potential_uniform = 0, elastic = 0;
  double total() const { return kinetic + rotational + potential_self + potential_uniform + elastic; }
  double bond_elastic = 0;   ///< part of `elastic` stored in intact bonds [J]
  double bond_released = 0;  ///< stored energy of the bonds broken so far [J] (left the total)
  std::size_t bonds = 0, bonds_broken = 0;
  Vec3 momentum = Vec3::Zero();
  Vec3 angular_momentum = Vec3::Zero();  ///< orbital + spin, about the origin
  std::size_t contacts = 0, wall_contacts = 0;
  double max_overlap_frac = 0;
};

/// Seconds spent per phase: wall clock, and process CPU time (all threads; "core-seconds").
struct PhaseTimes {
  double gravity = 0, neighbours = 0, contacts = 0, integrate = 0;
  double cpu_gravity = 0, cpu_neighbours = 0, cpu_contacts = 0, cpu_integrate = 0;
  std::int64_t steps = 0, gravity_evals = 0;
  std::int64_t neighbour_builds = 0;  ///< pair-list rebuilds (in `neighbours`; not the one at a restart)
};

class Simulation {
 public:
  /// Fresh start: validates dt against the contact time, computes the initial forces.
  Simulation(Spheres sp, SimConfig cfg);
  /// Restart from a saved state (forces and history taken from the state; nothing recomputed).
  Simulation(SimState st, SimConfig cfg);

  /// Advance one step. Throws common::NumericalError on NaN/Inf or runaway overlap; the state
  /// is then the failing one, and last_good() holds the last verified state.
  void step();
  void run(std::int64_t nsteps) {
    for (std::int64_t k = 0; k < nsteps; ++k) step();
  }

  const Spheres& spheres() const { return sp_; }
  Spheres& spheres_mut() { return sp_; }
  std::int64_t step_count() const { return step_; }
  double time() const { return time_; }
  const SimConfig& config() const { return cfg_; }
  const ContactStats& contact_stats() const { return cstats_; }
  const PhaseTimes& times() const { return times_; }
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

 private:
  void setup();
  void compute_forces(bool initial);
  void compute_gravity(bool with_pot);
  void check_state();

  SimConfig cfg_;
  Spheres sp_;
  std::vector<Vec3> a_, alpha_, ag_, vpred_, wpred_, F_, T_, a_prev_, alpha_prev_;
  std::vector<double> pot_;
  std::int64_t pot_step_ = -1, grav_step_ = -1;
  std::int64_t step_ = 0;
  double time_ = 0.0;
  std::unique_ptr<ContactSystem> contacts_;
  std::unique_ptr<TreeGravity> tree_;
  std::unique_ptr<BondSystem> bonds_;  ///< only when the scene has bonds
  void setup_bonds(BondSet b);
  ContactStats cstats_;
  PhaseTimes times_;
  std::int64_t keep_every_ = 0;
  std::optional<SimState> last_good_;
};

}  // namespace ssdem
