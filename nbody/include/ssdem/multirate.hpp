/// @file multirate.hpp
/// Multi-rate block time steps for the contact dynamics (`time.multirate = true`).
///
/// Scheme (block time steps on power-of-two levels, as pkdgrav's rungs: Quinn, Katz, Stadel &
/// Lake 1997, astro-ph/9710043 §3; Stadel 2001, PhD thesis §3.3; second-order KDK on every
/// level). The base step h is time.dt (the dt rule: the shortest contact / N). A sphere on level
/// l steps with h_l = 2^l h (level 0 = the base step; pkdgrav's rung r_max - l). Self-gravity
/// keeps its RESPA outer block (simulation.hpp; how the field enters spheres on shorter steps:
/// "Self-gravity inside a block" below) of K = 2^L base steps (block lengths are
/// rounded down to powers of two), levels run 0 .. L inside it, so a sphere with no contact in
/// reach takes one inner step per gravity block ("long steps sized by gravity": the block length
/// is the error-controlled gravity cadence). Within a block, at base substep s (0 <= s < K):
///   open:   every sphere synchronised at s (s mod 2^l = 0) kicks v += (h_l/2) a, w likewise;
///   drift:  EVERY sphere drifts x += h v (positions are synchronised at every base step);
///   levels: spheres synchronised at s+1 take their new level (rule below), then the near pairs
///           are equalised (rule below), which may promote a sphere in the middle of its step;
///   forces: contacts of the synchronised ("active") spheres, each pair with its own step;
///   close:  active spheres kick v += (tau/2 - h_open) a_old + (tau/2) a_new, with tau the time
///           since their opening kick and h_open the half-step of that kick; for a sphere closing
///           on schedule tau/2 = h_open and this is the KDK closing kick (v += (h_l/2) a_new).
/// Contact step per pair. A pair (i, j) with reduced mass mu and reduced radius R has the contact
/// time tau_c(mu, R) of the normal law (contact_params.hpp; Hertz at contact.vmax) and may step
/// with h_l <= tau_c / N, N = time.steps_per_contact: its level is
///   l_c(i, j) = max(0, floor(log2(tau_c(mu, R) / (N h)))),
/// a wall contact of sphere i likewise with mu = m_i, R = s_i. So a light fragment's pair steps
/// finely while pairs of heavier spheres take longer steps.
/// Near pairs. A pair is near when its gap |x_i - x_j| - s_i - s_j < g = k/2 (k = contact.skin);
/// the pair list re-inserts spheres after k/4 (ContactSystem::set_reinsert_fraction), so every
/// near pair is listed whatever the list's history (unlisted: gap >= k - k/4 - k/4). The rules
///   new level at a sync (s+1):  l_i = min(L, tz(s+1), min over near partners j of l_c(i, j),
///                                         l_c(wall) for a wall within g),
///     tz(s+1) = the number of trailing zero bits of s+1 (a level may only become coarser where
///     it is synchronised);
///   equalisation: for every near pair, l_i = l_j = min(l_i, l_j, l_c(i, j)) (walls: l_i <=
///     l_c(wall)), iterated to the fixed point; a sphere whose level drops while it is not
///     synchronised at s+1 is promoted to min(that level, tz(s+1)) and closes now (tau < h_l).
/// Hence every near pair, and so every pair in contact, has both spheres on one level, at most
/// l_c of the pair, and both are evaluated together: contact forces act on synchronised spheres
/// only, pairwise antisymmetric (momentum exact) and each contact is a plain KDK at its level's
/// step.
/// Bonds (bonds.hpp; multirate_bonds.cpp). Every intact bond is a permanent near pair, whatever
/// its gap, with its own level
///   l_b = max(0, floor(log2(tau_b / (N h)))),  tau_b = min(pi sqrt(mu / (k_n A)),
///         pi sqrt(mu / (k_s A)), pi sqrt(I_r / (k_n I)), pi sqrt(I_r / (k_s J)))
/// (mu, I_r: the two spheres' reduced mass and moment of inertia; the shortest mode half-period of
/// the bond dt rule, which sets h with the contacts: h = min(tau_c, tau_b) / N when time.dt = 0,
/// so the stiffest bond is on level 0). It enters both rules like a near pair: the new level of a
/// synchronised sphere is also <= l_b of its intact bonds, and the equalisation sets both ends of
/// every intact bond to min(l_a, l_b-end, l_b). So both ends of a bond are always on one level
/// <= l_b, open and close together (the same opening step), and the bond force and torque act
/// only when both are synchronised, pairwise (momentum and angular momentum as in single rate),
/// each bond a plain KDK at its level's step h_l >= tau_b / (2N): its increments use the half-step
/// velocities and spins over the spheres' own step (BondSystem::compute_synchronised). A bond that
/// breaks does so at one of its level's steps (the first at which its stress exceeds its
/// strength), its stored energy goes to the released account as in single rate, and it stops
/// constraining the levels at the next level decision. l_b depends only on the bond and the two
/// spheres, so it is computed once per Simulation (also after a restart: same values).
/// Cohesion (contact/cohesion.hpp) is a constant force F_c = sigma_c pi (beta Rbar)^2 while the
/// spheres overlap: it has no stiffness of its own and acts only in contact, i.e. inside the
/// contact pair's level; its time scale enters through k_n, which the scene's k_n rule raises to
/// >= F_c / x_max (scene_setup.cpp), hence through tau_c and l_c. Its force jump at touch and
/// separation is first order in the pair's step (cohesion.hpp), resolved like single rate at N
/// steps per contact (test_nbody_multirate: a cohesive pair on level 2 pulls off at the threshold
/// with the exit speed of single rate at its step, 1e-3).
/// Reach rule (no tunnelling). Positions are synchronised at every base step and the near test
/// runs at every base step for all spheres, whatever their level: a sphere's displacement before
/// the next test is at most |v| h, the same as in single-rate stepping at the base step. A pair
/// approaching at relative speed w is equalised before it touches if w h < g = k/2, and in any
/// case at the first base step at which it overlaps, i.e. exactly when single-rate stepping at
/// the base step first sees the contact (a 5 km/s fragment through a pile is caught at the
/// base step; test_nbody_multirate).
/// Errors. A promotion in the middle of a step (a sphere on level l at time tau after its
/// opening) replaces its opening kick (h_l/2) a_old by (tau/2) a_old; its drift so far used
/// v + (h_l/2) a_old instead of v + (tau/2) a_old, a position error of tau (h_l - tau) a_old / 2
/// (first order in h_l, once per promotion). a_old holds only the uniform field (a promoted sphere
/// had no contact) and, with the held field below, g: with gravity.inner_steps = "impulse" and
/// gravity.uniform = 0 a promotion is exact, and a sphere flying alone into a pile follows the
/// single-rate trajectory bit for bit when its pairs are on the base level (test_nbody_multirate).
/// Contacts never do work on spheres that are not synchronised, so no energy is created by the
/// level changes.
/// Self-gravity inside a block (gravity.inner_steps; test_nbody_multirate_gravity). "impulse":
/// every sphere takes the block's RESPA half-kicks hk g at its opening and its end (hk = K h/2,
/// simulation.hpp). A resting pile then carries its weight only at the block's ends: inside the
/// block the contacts push it apart unopposed and the closing kick pulls it back, a breathing of
/// amplitude ~ g (K h)^2 / 8 that dissipates energy and forbids blocks much longer than a contact
/// time. "held" (the default): a sphere whose step is shorter than the block (in or near contact;
/// h_open != hk) takes instead the block-start field g_n as a force at its own kicks,
///   opening (h_l/2)(a + g_n), closing (tau/2)(a + g_n), and at the block's end also
///   v += hk (g_{n+1} - g_n)   (the trapezoid residual),
/// so over the block it receives K h g_n + hk (g_{n+1} - g_n) = hk (g_n + g_{n+1}), the impulse
/// scheme's total: momentum at block ends and the field's second-order accuracy are those of
/// RESPA, and without contact forces the block endpoints are the impulse scheme's in exact
/// arithmetic (KDK under a constant force is exact; asserted to 1e-11 on a close binary). A
/// resting pile feels its weight at every step and does not breathe. Spheres on whole-block steps
/// keep the impulses. A sphere promoted out of a whole-block step converts its opening impulse
/// hk g_n into (tau/2) g_n, as if the field had been held since the block opened (its opening
/// step records h_open = tau/2 afterwards); its drift so far used v + hk g_n instead of
/// v + (tau/2) g_n, a position error tau (K h - tau) g_n / 2 <= (K h)^2 g / 8 (first order, once
/// per promotion, as for a_old above; 0.5 m for a 20 s block at g = 1e-2 m/s^2, 1e-3 of a 1 km
/// hand-off sphere's radius). g_n is the
/// evaluation of the block's start (Simulation keeps it through the new evaluation at the block's
/// end). The predicted velocities of held steps include g_n.
/// The extrapolated dashpot predictor (simulation.hpp) extrapolates over the sphere's previous
/// step; after a level change (previous step length differs) that one step uses the pkdgrav
/// predictor.
/// Limits. All spheres of a cluster of near pairs and bonds share the finest level of its pairs
/// and bonds (a pile steps at the step of its lightest contact, a bonded body at that of its
/// stiffest bond or contact; only separate clusters and lone spheres gain). Without bonds no bond
/// arrays exist and the rules are unchanged.
/// Ownership (for a domain decomposition): a sphere's level, opening time and previous step are
/// per-sphere arrays (SimState::level etc.) exchanged with the sphere; the level rule needs only
/// the sphere's near partners (gap < k/2, inside any halo of width >= the skin), the
/// equalisation is a fixed point over near pairs (converges to the same result in any order, so
/// a halo exchange of levels per iteration reproduces it), and synchronisation times are global
/// (base substep counter), so ranks need to agree only on the block length. This is how the MPI
/// driver runs it (mpi/domain_sim.hpp, "Multi-rate steps"; level_rules.hpp), bit-identical to one
/// rank.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "ssdem/contact_params.hpp"
#include "ssdem/spheres.hpp"

namespace ssdem {

/// Level of a contact pair: l_c = max(0, floor(log2(tau_c / (N h)))), at most lmax.
class PairClock {
 public:
  PairClock() = default;
  PairClock(const ContactParams& p, double base_dt, double steps_per_contact, int lmax);
  /// reduced mass mu [kg], reduced radius R [m]
  int level(double mu, double R) const;
  /// max(0, floor(log2(tc / (N h)))), at most lmax: the level of an oscillation of half-period tc
  int level_of_time(double tc) const;

 private:
  ContactParams p_;
  double unit_ = 1.0;  ///< N h
  double lin_ = 0.0;   ///< linear law: tau_c = lin_ * sqrt(mu)
  int lmax_ = 0;
};

/// Levels in use over a run: sphere-substeps per level and the current histogram.
struct LevelStats {
  std::vector<std::int64_t> now;           ///< spheres per level at the last block boundary
  std::vector<double> sphere_time;         ///< simulated sphere-seconds spent on each level
  std::int64_t promotions = 0;             ///< promotions in the middle of a step
  std::int64_t evaluations = 0;            ///< sphere force evaluations (active spheres summed)
  /// "l0:n0 l1:n1 ..." of `now` (levels with n > 0)
  std::string histogram_text() const;
};

/// Deepest level in use (2^30 base steps: far beyond any gravity block).
constexpr int kMaxLevel = 30;

/// The per-sphere arrays a multi-rate force evaluation reads and writes (Simulation, and the owned
/// spheres of mpi::DomainSim).
struct ActiveArrays {
  Spheres& sp;
  const std::vector<Vec3>& a;
  const std::vector<Vec3>& alpha;
  std::vector<Vec3>& vpred;
  std::vector<Vec3>& wpred;
  std::vector<Vec3>& a_prev;
  std::vector<Vec3>& alpha_prev;
  const std::vector<std::int64_t>& topen;  ///< base step of each sphere's opening kick
  std::vector<double>& hopen;              ///< half-step of that kick [s] (tau/2 after a promotion)
  std::vector<double>& tau_prev;           ///< length of each sphere's previous step [s]
  const std::vector<std::uint8_t>& promoted;
};

/// For the active spheres active[0..na) at base step `step` (base step h): their step
/// tau = (step - topen) h (written to tau[r]), the predicted v, w of the dashpots (KDK: v_open +
/// tau a_old, extrapolated by (tau/2)(a - a_prev) over equal steps when `extrap`), and for a
/// promoted sphere its opening kick h_open a_old replaced by (tau/2) a_old (multirate.hpp).
/// gheld: the gravity block's held field (gravity.inner_steps = "held"; null otherwise), hk the
/// block's half-length: a step that holds it (h_open != hk, or promoted) predicts and corrects
/// with a_old + g.
void predict_active(const ActiveArrays& s, const std::uint32_t* active, std::size_t na, std::int64_t step,
                    double h, bool extrap, double* tau, const Vec3* gheld = nullptr, double hk = 0.0);
/// Adds the active spheres' steps (step - topen) h to the level statistics (sphere-time per level,
/// evaluations).
void count_active(LevelStats& ls, const std::uint32_t* active, std::size_t na, std::int64_t step,
                  const std::vector<std::int64_t>& topen, double h);

/// Where a base substep lies in its gravity block of K = 2^L base steps (K a power of two): s0 =
/// step - block start; the block opens at s0 = 0 and closes after s0 = K - 1; hk = h K / 2 is the
/// block's gravity half-kick; tz = min(trailing level of s0 + 1, L) is the coarsest level
/// synchronised at the end of the substep.
struct Substep {
  Substep(double h_, int K_, std::int64_t step, std::int64_t block_start);
  double h, hk;
  int K, L, tz;
  std::int64_t s0;
  bool opens, closes;
};

/// The arrays the kicks and drifts of a multi-rate base substep update.
struct KickArrays {
  Spheres& sp;
  const std::vector<Vec3>& a;      ///< contact + uniform acceleration
  const std::vector<Vec3>& alpha;  ///< angular acceleration
  const std::vector<Vec3>& ag;     ///< self-gravity (the block's outer kicks)
  const std::vector<std::uint8_t>& level;
  std::vector<std::int64_t>& topen;
  std::vector<double>& hopen;
};
/// Opening half of base substep s0 of a gravity block, at base step `step`: every sphere i with
/// mask null or mask[i] != 0 gets the block's opening gravity kick hk ag (when `gravity_kick`, only
/// at s0 = 0, where every sphere opens; std::logic_error otherwise), its
/// opening kick (h_l/2) a if synchronised at s0 (topen = step, hopen = h_l/2; the spin too when
/// `spin`) and drifts x += h v; a sphere outside the mask (a ghost) records its opening step and
/// drifts with its velocity as it is (its owner kicks it and sends the result: DomainSim).
/// With gheld (the block's held field, "held" mode) a sphere opening a step shorter than the block
/// kicks with (h_l/2)(a + gheld) and takes no gravity impulse. `nopen`: how many spheres are
/// expected to open (those active at the end of the previous step); it decides, with the sphere
/// count, whether the pass runs on a team of threads (omp_team.hpp), never the result.
void open_and_drift(const KickArrays& k, const std::uint8_t* mask, std::int64_t step, std::int64_t s0, double h,
                    double hk, bool gravity_kick, bool spin, const Vec3* gheld = nullptr, std::size_t nopen = 0);
/// Closing kicks of the active spheres: v += (tau/2) a with tau = (step - topen) h (spins likewise),
/// plus the block's closing gravity kick hk ag when `gravity_kick`. With gheld (the field held
/// through this block: the previous evaluation at a block's end) a held step (h_open != hk) closes
/// with (tau/2)(a + gheld) and, at the block's end, the residual hk (ag - gheld).
void close_kicks(const KickArrays& k, const std::uint32_t* active, std::size_t na, std::int64_t step, double h,
                 double hk, bool gravity_kick, bool spin, const Vec3* gheld = nullptr);

/// Number of trailing zero bits of s > 0 (the coarsest level synchronised at substep s).
inline int trailing_level(std::int64_t s) {
  int t = 0;
  while (s > 0 && (s & 1) == 0) {
    s >>= 1;
    ++t;
  }
  return t;
}

/// Largest power of two <= k (k >= 1).
inline int floor_pow2(int k) {
  int p = 1;
  while (2 * p <= k) p *= 2;
  return p;
}

}  // namespace ssdem
