/// @file multirate.cpp
/// Multi-rate block time steps (time.multirate = true): the level rule, the equalisation of near
/// pairs and the substep of Simulation; equations, rules and their proofs in multirate.hpp.
#include "ssdem/multirate.hpp"

#include <omp.h>

#include <algorithm>
#include <cstdint>
#include <cmath>
#include <cstring>
#include <sstream>
#include <stdexcept>

#include "byte_flags.hpp"
#include "common/status.hpp"
#include "omp_team.hpp"
#include "ssdem/loop_split.hpp"
#include "ssdem/simulation.hpp"

namespace ssdem {

PairClock::PairClock(const ContactParams& p, double base_dt, double steps_per_contact, int lmax)
    : p_(p), unit_(base_dt * steps_per_contact), lmax_(lmax) {
  if (!(p.parts & kPartHertz)) lin_ = p.contact_time(1.0);  // tau_c = lin_ sqrt(mu)
}

int PairClock::level(double mu, double R) const {
  return level_of_time(lin_ > 0.0 ? lin_ * std::sqrt(mu) : p_.contact_time(mu, R));
}

int PairClock::level_of_time(double tc) const {
  const double r = tc / unit_;
  if (!(r >= 2.0)) return 0;  // also NaN
  if (!(r < 0x1p30)) return std::min(std::ilogb(r), lmax_);
  // ilogb of a normal double in [2, 2^30): its biased exponent field (no libm call: this runs for
  // every near pair at every base step)
  std::uint64_t b;
  std::memcpy(&b, &r, sizeof b);
  return std::min(static_cast<int>((b >> 52) & 0x7ff) - 1023, lmax_);
}

std::string LevelStats::histogram_text() const {
  std::ostringstream os;
  bool first = true;
  for (std::size_t l = 0; l < now.size(); ++l) {
    if (now[l] == 0) continue;
    os << (first ? "" : " ") << "l" << l << ":" << now[l];
    first = false;
  }
  return os.str();
}

void Simulation::setup_multirate(const SimState* st) {
  if (!cfg_.multirate) return;
  if (!(cfg_.pair_steps_per_contact > 0.0))
    throw common::InputError("time.steps_per_contact must be > 0");
  cfg_.gravity_every = floor_pow2(std::max(cfg_.gravity_every, 1));
  cfg_.gravity_max_every = floor_pow2(std::max(cfg_.gravity_max_every, 1));
  const std::size_t n = sp_.size();
  lr_.reset(n, st ? &st->level : nullptr);
  tau_prev_.assign(n, 0.0);
  if (st && st->tau_prev.size() == n) tau_prev_ = st->tau_prev;
  topen_.assign(n, 0);
  hopen_.assign(n, 0.0);
  lstats_.now.assign(kMaxLevel + 1, 0);
  lstats_.sphere_time.assign(kMaxLevel + 1, 0.0);
  for (std::uint8_t l : lr_.level) ++lstats_.now[std::min<int>(l, kMaxLevel)];
  if (contacts_) {
    contacts_->set_reinsert_fraction(0.25);  // every pair with gap < skin/2 is listed
    lr_.configure(PairClock(cfg_.contact, cfg_.dt, cfg_.pair_steps_per_contact, kMaxLevel), 0.5 * contacts_->skin());
    if (bonds_) blevels_ = std::make_unique<BondLevels>(*bonds_, sp_, lr_);  // bonds need contacts
  }
}

void predict_active(const ActiveArrays& s, const std::uint32_t* active, std::size_t na, std::int64_t step,
                    double h, bool extrap, double* tau_out, const Vec3* gheld, double hk) {
  for_blocks(na, Work::items, [&](std::size_t lo, std::size_t hi) {
    for (std::size_t r = lo; r < hi; ++r) {
      const std::uint32_t i = active[r];
      const double tau = static_cast<double>(step - s.topen[i]) * h;
      tau_out[r] = tau;
      const double hc = tau - s.hopen[i];  // v_pred = v_open + tau a_old (KDK: h/2 ahead of v_half)
      // a step that holds the block's field (promoted: it does from now on, see below)
      const bool held = gheld && (s.hopen[i] != hk || s.promoted[i]);
      const Vec3 acc = held ? Vec3(s.a[i] + gheld[i]) : s.a[i];
      s.vpred[i] = s.sp.v[i] + hc * acc;
      s.wpred[i] = s.sp.w[i] + hc * s.alpha[i];
      if (extrap) {
        if (s.tau_prev[i] == tau) {  // a_{n+1} ~ 2 a_n - a_{n-1} over equal steps
          s.vpred[i] += 0.5 * tau * (s.a[i] - s.a_prev[i]);
          s.wpred[i] += 0.5 * tau * (s.alpha[i] - s.alpha_prev[i]);
        }
        s.a_prev[i] = s.a[i];
        s.alpha_prev[i] = s.alpha[i];
      }
      s.tau_prev[i] = tau;
      if (s.promoted[i]) {  // opening kick h_open a_old -> (tau/2) a_old
        const double c = 0.5 * tau - s.hopen[i];
        // held field: a whole-block step's opening impulse h_open g (h_open = hk) or a held step's
        // h_open g becomes (tau/2) g, as if the field had been held since the opening
        s.sp.v[i] += c * acc;
        s.sp.w[i] += c * s.alpha[i];
        s.hopen[i] = 0.5 * tau;  // the opening kick it now had (never hk: tau < the block)
      }
    }
  });
}

Substep::Substep(double h_, int K_, std::int64_t step, std::int64_t block_start)
    : h(h_), hk(0.5 * h_ * K_), K(K_), L(trailing_level(K_)), tz(0), s0(step - block_start), opens(s0 == 0),
      closes(s0 + 1 == K_) {
  tz = std::min(trailing_level(s0 + 1), L);
}

void open_and_drift(const KickArrays& k, const std::uint8_t* mask, std::int64_t step, std::int64_t s0, double h,
                    double hk, bool gravity_kick, bool spin, const Vec3* gheld, std::size_t nopen) {
  // (the arrays' data pointers taken once: the loop then runs as over plain arrays)
  const std::size_t n = k.level.size();
  const std::uint8_t* level = k.level.data();
  Vec3* x = k.sp.x.data();
  Vec3* v = k.sp.v.data();
  Vec3* w = k.sp.w.data();
  const Vec3* a = k.a.data();
  const Vec3* alpha = k.alpha.data();
  const Vec3* ag = k.ag.data();
  std::int64_t* topen = k.topen.data();
  double* hopen = k.hopen.data();
  static_assert(sizeof(Vec3) == 3 * sizeof(double), "Vec3 arrays are read as flat arrays of doubles");
  // opening kick of sphere i (synchronised at s0)
  auto open = [&](std::size_t i) {
    if (mask && !mask[i]) {
      topen[i] = step;  // a ghost: its opening step only (its pairs' steps)
      return;
    }
    const double ho = 0.5 * h * static_cast<double>(std::int64_t{1} << level[i]);
    hopen[i] = ho;
    topen[i] = step;
    if (gheld && ho != hk) {  // a step shorter than the block: the block's field held
      v[i] += ho * Vec3(a[i] + gheld[i]);
    } else {
      if (gravity_kick) v[i] += hk * ag[i];
      v[i] += ho * a[i];
    }
    if (spin) w[i] += ho * alpha[i];
  };
  if (gravity_kick && s0 != 0) throw std::logic_error("open_and_drift: the block's gravity kick only at s0 = 0");
  // (a block's opening kicks every sphere: items; at s0 > 0 the kicks of the opening spheres,
  // items, and a scan and the drift of all, a stream)
  const bool team = s0 == 0 ? use_team(n) : use_team(nopen) || use_team(n, Work::stream);
  // the opening spheres each thread lists from its block (the calling thread's storage, kept),
  // and per coarsest opening level how unevenly the blocks held them at its last step
  thread_local std::vector<std::vector<std::uint32_t>> opening;
  thread_local std::size_t skew[64] = {};
  const auto slots = static_cast<std::size_t>(team ? omp_get_max_threads() : 1);
  if (opening.size() < slots) opening.resize(slots);
  for (auto& l : opening) l.clear();
  std::vector<std::uint32_t>* lists = opening.data();
  const int tzo = s0 == 0 ? 0 : __builtin_ctzll(static_cast<std::uint64_t>(s0));
  // Shared by count only where the blocks were skewed (the 375 m row: ~30 000 opening spheres in
  // one block); where they were even (the 1 km remnant fills both blocks) the two barriers cost
  // more than they save (nbody/README.md: integrate 5.81 -> 6.31 s); threshold in omp_team.hpp.
  // Who kicks a sphere never changes its bits.
  const bool share = skew[tzo] >= team_thresholds().kick_skew;
  // The blocks' cuts follow the threads' measured times (loop_split.hpp), one split for the
  // blocks' openings and one per coarsest opening level (6 and above together: the kicks by
  // block cost differently at each): on the 375 m row the thread whose block holds the pile
  // took ~1.7x as long over the same number of spheres, its x and v last written by the other
  // thread's kicks and sums (perf per thread). Any cut gives the same bits.
  thread_local LoopSplit split[8];
  LoopSplit& cut = split[s0 == 0 ? 0 : 1 + std::min(tzo, 6)];
  cut.begin(n, team ? omp_get_max_threads() : 1);
  in_team(team, [&] {
    // each thread its block of spheres: kicks, then the drift of the same spheres
    const int t = omp_get_thread_num(), T = omp_get_num_threads();
    std::size_t b, e;
    cut.block(n, t, T, b, e);
    double t0 = T > 1 ? omp_get_wtime() : 0.0;
    if (s0 == 0) {  // a block opens: every sphere opens (levels <= L)
      for (std::size_t i = b; i < e; ++i) open(i);
    } else {  // the spheres on levels l with 2^l | s0, listed without a branch per sphere
      // (filled in a local vector, its slot's storage swapped in and out: the slots' headers
      // share a cache line, which two threads' push_backs would pass back and forth)
      std::vector<std::uint32_t> mine;
      mine.swap(lists[t]);
      append_at_most(level, b, e, tzo, mine);
      lists[t].swap(mine);
      if (T > 1 && share) {
        // kicked by count, not by block: the opening spheres of a pile lie together in memory
        // (the cell order), mostly in one block (the 2.42 km 375 m row at t = 2 400 s: one
        // thread's kicks and drift took 2.4x the other's perf samples); a sphere drifts after its
        // kick, so a barrier before the drift
#pragma omp barrier
        for_joined_share(lists, t, T, open);
#pragma omp barrier
        t0 = omp_get_wtime();  // (the blocks' own work: the drift)
      } else {
        for (std::uint32_t i : lists[t]) open(i);
      }
    }
    // every sphere drifts, a ghost too (with its velocity as its owner last sent it): one
    // branch-free loop over the components (vectorised; the same product and sum per component
    // as x[i] += h v[i])
    double* xf = x->data();
    const double* vf = v->data();
    for (std::size_t c = 3 * b; c < 3 * e; ++c) xf[c] += h * vf[c];
    if (T > 1) cut.record(t, omp_get_wtime() - t0);
  });
  cut.end();
  if (s0 != 0 && team) skew[tzo] = list_skew(lists, static_cast<int>(slots));
}

void close_kicks(const KickArrays& k, const std::uint32_t* active, std::size_t na, std::int64_t step, double h,
                 double hk, bool gravity_kick, bool spin, const Vec3* gheld) {
  Vec3* v = k.sp.v.data();
  Vec3* w = k.sp.w.data();
  const Vec3* a = k.a.data();
  const Vec3* alpha = k.alpha.data();
  const Vec3* ag = k.ag.data();
  const std::int64_t* topen = k.topen.data();
  const double* hopen = k.hopen.data();
  for_blocks(na, Work::items, [&](std::size_t lo, std::size_t hi) {
    for (std::size_t r = lo; r < hi; ++r) {
      const std::uint32_t i = active[r];
      const double hc = 0.5 * (static_cast<double>(step - topen[i]) * h);
      if (gheld && hopen[i] != hk) {  // held step: the held field, and at the block's end the
        v[i] += hc * Vec3(a[i] + gheld[i]);  // trapezoid residual hk (g_new - g_held)
        if (gravity_kick) v[i] += hk * Vec3(ag[i] - gheld[i]);
      } else {
        v[i] += hc * a[i];
        if (gravity_kick) v[i] += hk * ag[i];
      }
      if (spin) w[i] += hc * alpha[i];
    }
  });
}

void count_active(LevelStats& ls, const std::uint32_t* active, std::size_t na, std::int64_t step,
                  const std::vector<std::int64_t>& topen, double h) {
  // per level the sum of the integer step counts k (tau = k h): exact in any order, so the sum
  // runs in parallel and the result does not depend on the thread count
  std::int64_t ks[kMaxLevel + 1] = {};
  const std::int64_t* to = topen.data();
  for_blocks(na, Work::items, [&](std::size_t lo, std::size_t hi) {
    std::int64_t part[kMaxLevel + 1] = {};
    for (std::size_t r = lo; r < hi; ++r) {
      // level of the step: floor(log2(k)) (k is a power of two but for a promoted sphere's step)
      const auto k = static_cast<std::uint64_t>(step - to[active[r]]);
      part[std::min(63 - __builtin_clzll(k | 1), kMaxLevel)] += static_cast<std::int64_t>(k);
    }
#pragma omp critical(ssdem_count_active)
    for (int l = 0; l <= kMaxLevel; ++l) ks[l] += part[l];
  });
  for (int l = 0; l <= kMaxLevel; ++l)
    if (ks[l]) ls.sphere_time[static_cast<std::size_t>(l)] += static_cast<double>(ks[l]) * h;
  ls.evaluations += static_cast<std::int64_t>(na);
}

// Contact forces of the active spheres (each with its own step), accelerations, and the
// promoted spheres' kick correction.
void Simulation::multirate_forces(const Substep& ss) {
  const std::size_t n = sp_.size();
  const double h = cfg_.dt;
  const bool extrap = cfg_.extrapolated_predictor;
  const std::size_t na = active_.size();
  vpred_.resize(n);
  wpred_.resize(n);
  if (extrap && a_prev_.size() != n) {
    a_prev_.assign(n, Vec3::Zero());
    alpha_prev_.assign(n, Vec3::Zero());
  }
  subset_.spheres = active_;
  subset_.hsphere.resize(na);
  predict_active(ActiveArrays{sp_, a_, alpha_, vpred_, wpred_, a_prev_, alpha_prev_, topen_, hopen_, tau_prev_, lr_.promoted},
                 active_.data(), na, step_, h, extrap, subset_.hsphere.data(), held_field(cfg_, ag_, sp_.size()),
                 ss.hk);
  count_active(lstats_, active_.data(), na, step_, topen_, h);
  bool uniform = na == n;
  const double tau0 = na > 0 ? subset_.hsphere[0] : 0.0;
  for (std::size_t r = 0; r < na && uniform; ++r) uniform = subset_.hsphere[r] == tau0;
  if (contacts_) {
    if (uniform) {  // everyone active with one step: the single-rate kernel call
      cstats_ = contacts_->compute(sp_, vpred_, wpred_, tau0, F_, T_, sp_.dissipated.data());
    } else {
      take_subset(subsets_, ss.tz, *contacts_, active_, lr_.sync, topen_, step_, h, subset_off_, subset_);
      cstats_ = contacts_->compute(sp_, vpred_, wpred_, subset_, F_, T_, sp_.dissipated.data());
      keep_subset(subsets_, ss.tz, subset_);
    }
    // bonds of synchronised spheres (both ends always together), each with its spheres' step
    if (bonds_) bonds_->compute_synchronised(sp_, lr_.sync, topen_, step_, h, F_, T_);
  }
  accelerations(active_.data(), na);
}

void Simulation::step_multirate() {
  const std::size_t n = sp_.size();
  const bool spin = contacts_ != nullptr;
  const bool sg = cfg_.self_gravity;
  const Substep ss(cfg_.dt, block_, step_, block_start_);
  double t0 = omp_get_wtime(), c0 = cpu_now_();
  if (ss.opens) lr_.cap(ss.L);
  const KickArrays kicks{sp_, a_, alpha_, ag_, lr_.level, topen_, hopen_};
  open_and_drift(kicks, nullptr, step_, ss.s0, ss.h, ss.hk, sg && ss.opens, spin,
                 held_field(cfg_, ag_, sp_.size()), active_.size());
  ++step_;
  time_ = static_cast<double>(step_) * ss.h;
  times_.integrate += omp_get_wtime() - t0;
  times_.cpu_integrate += cpu_now_() - c0;
  if (contacts_) {
    t0 = omp_get_wtime();
    c0 = cpu_now_();
    // Since the previous update the spheres active then were kicked (their closing kicks, the
    // corrections of promoted ones), and the spheres that opened this step, which were active
    // then too unless a block opened (every sphere opens) (multirate.hpp): a sphere that opens at
    // s0 > 0 was synchronised, so active, at the end of the step before.
    ContactSystem::Drift drift;
    drift.h = ss.h;
    drift.kicked = kicks_known_ && !ss.opens ? active_.data() : nullptr;
    drift.nkicked = active_.size();
    drift.level = lr_.level.data();
    if (contacts_->update_neighbors(sp_, drift)) ++times_.neighbour_builds;
    times_.neighbours += omp_get_wtime() - t0;
    times_.cpu_neighbours += cpu_now_() - c0;
  }
  t0 = omp_get_wtime();
  c0 = cpu_now_();
  if (blevels_) blevels_->refresh();  // broken bonds leave the rules
  if (contacts_) lr_.update_pair_levels(sp_, *contacts_);
  lr_.assign(sp_, contacts_.get(), ss.tz, ss.L, blevels_.get());
  if (contacts_) lr_.equalise(sp_, *contacts_, ss.tz, blevels_.get());
  lstats_.promotions = lr_.promotions;
  lr_.active(active_);
  const double tl = omp_get_wtime() - t0;
  times_.levels += tl;
  times_.integrate += tl;
  times_.cpu_integrate += cpu_now_() - c0;
  t0 = omp_get_wtime();
  c0 = cpu_now_();
  multirate_forces(ss);
  times_.contacts += omp_get_wtime() - t0;
  times_.cpu_contacts += cpu_now_() - c0;
  if (sg && ss.closes) {
    check_state();  // every sphere, before the tree sees the positions (see the end of the step)
    if (cfg_.adaptive_gravity || cfg_.gravity_held) ag_old_ = ag_;
    compute_gravity(want_pot_);
  }
  t0 = omp_get_wtime();
  c0 = cpu_now_();
  // the field held through this block: the previous evaluation once the block's end evaluated anew
  close_kicks(kicks, active_.data(), active_.size(), step_, ss.h, ss.hk, sg && ss.closes, spin,
              held_field(cfg_, sg && ss.closes ? ag_old_ : ag_, sp_.size()));
  times_.integrate += omp_get_wtime() - t0;
  times_.cpu_integrate += cpu_now_() - c0;
  if (ss.closes) {
    std::fill(lstats_.now.begin(), lstats_.now.end(), 0);
    for (std::size_t i = 0; i < n; ++i) ++lstats_.now[lr_.level[i]];
    close_gravity_block();
  }
  ++times_.steps;
  kicks_known_ = true;
  // The spheres evaluated now: a non-finite value enters only through a force (a, alpha, checked
  // where evaluated) or the field (evaluated at a block's close, where every sphere is active), and
  // a sphere not evaluated now only drifts with, and is kicked by, values checked before. (A finite
  // state overflowing to infinity in a drift is caught at the sphere's next evaluation, and at the
  // latest before the next field evaluation, above.)
  check_state(&active_);
}

}  // namespace ssdem
