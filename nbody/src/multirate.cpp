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

#include "common/status.hpp"
#include "ssdem/simulation.hpp"

namespace ssdem {
namespace {
constexpr std::size_t kOmpMin = 2048;  // below this many spheres a loop runs serially
constexpr int kMaxLevel = 30;          // 2^30 base steps: far beyond any gravity block
}  // namespace

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
  level_.assign(n, 0);
  tau_prev_.assign(n, 0.0);
  if (st && st->level.size() == n) level_ = st->level;
  if (st && st->tau_prev.size() == n) tau_prev_ = st->tau_prev;
  sync_.assign(n, 0);
  promoted_.assign(n, 0);
  lflag_.assign(n, 0);
  unsettled_valid_ = false;
  topen_.assign(n, 0);
  hopen_.assign(n, 0.0);
  lstats_.now.assign(kMaxLevel + 1, 0);
  lstats_.sphere_time.assign(kMaxLevel + 1, 0.0);
  for (std::uint8_t l : level_) ++lstats_.now[std::min<int>(l, kMaxLevel)];
  if (contacts_) {
    contacts_->set_reinsert_fraction(0.25);  // every pair with gap < skin/2 is listed
    near_gap_ = 0.5 * contacts_->skin();
    clock_ = PairClock(cfg_.contact, cfg_.dt, cfg_.pair_steps_per_contact, kMaxLevel);
    if (bonds_) setup_bond_levels();  // bonds need contacts
  }
}

// Contact forces of the active spheres (each with its own step), accelerations, and the
// promoted spheres' kick correction.
void Simulation::multirate_forces() {
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
  bool uniform = na == n;
  double tau0 = 0.0;
#pragma omp parallel for schedule(static) if (na >= kOmpMin)
  for (std::size_t r = 0; r < na; ++r) {
    const std::uint32_t i = active_[r];
    const double tau = static_cast<double>(step_ - topen_[i]) * h;
    subset_.hsphere[r] = tau;
    const double hc = tau - hopen_[i];  // v_pred = v_open + tau a_old (KDK: h/2 ahead of v_half)
    vpred_[i] = sp_.v[i] + hc * a_[i];
    wpred_[i] = sp_.w[i] + hc * alpha_[i];
    if (extrap) {
      if (tau_prev_[i] == tau) {  // a_{n+1} ~ 2 a_n - a_{n-1} over equal steps
        vpred_[i] += 0.5 * tau * (a_[i] - a_prev_[i]);
        wpred_[i] += 0.5 * tau * (alpha_[i] - alpha_prev_[i]);
      }
      a_prev_[i] = a_[i];
      alpha_prev_[i] = alpha_[i];
    }
    tau_prev_[i] = tau;
    if (promoted_[i]) {  // opening kick h_open a_old -> (tau/2) a_old
      const double c = 0.5 * tau - hopen_[i];
      sp_.v[i] += c * a_[i];
      sp_.w[i] += c * alpha_[i];
    }
  }
  for (std::size_t r = 0; r < na; ++r) {
    const double tau = subset_.hsphere[r];
    if (r == 0) tau0 = tau;
    uniform = uniform && tau == tau0;
    // level of the step: floor(log2(tau / h)) of the integer step count (tau = k h exactly for
    // k a power of two, so this is ilogb(tau / h))
    const auto k = static_cast<std::uint64_t>(step_ - topen_[active_[r]]);
    lstats_.sphere_time[std::min(63 - __builtin_clzll(k | 1), kMaxLevel)] += tau;
  }
  lstats_.evaluations += static_cast<std::int64_t>(na);
  if (contacts_) {
    if (uniform) {  // everyone active with one step: the single-rate kernel call
      cstats_ = contacts_->compute(sp_, vpred_, wpred_, tau0, F_, T_, sp_.dissipated.data());
    } else {
      // every listed pair with an active member: pairs in contact have both members active (near
      // pairs share a level); a pair with one active member is evaluated too, so that a contact
      // flag left from its last evaluation is reset, never gathered stale (it is not near: no force)
      const auto& pi = contacts_->pair_i();
      const auto& pj = contacts_->pair_j();
      const auto& ri = contacts_->row_i();
      const auto& rj = contacts_->row_j();
      const auto& jp = contacts_->jpair();
      // (in parallel: per active sphere its count, an exclusive prefix sum, then each sphere
      // fills its own slots, in the order of the serial loop over active spheres)
      auto hpair = [&](std::uint32_t p) {
        const std::uint32_t i = pi[p], j = pj[p];
        const std::int64_t ti = sync_[i] ? step_ - topen_[i] : INT64_MAX;
        const std::int64_t tj = sync_[j] ? step_ - topen_[j] : INT64_MAX;
        return static_cast<double>(std::min(ti, tj)) * h;
      };
      subset_off_.resize(na + 1);
      subset_off_[0] = 0;
#pragma omp parallel for schedule(static) if (na >= kOmpMin)
      for (std::size_t r = 0; r < na; ++r) {
        const std::uint32_t k = active_[r];
        std::size_t c = ri[k + 1] - ri[k];
        for (std::uint32_t q = rj[k]; q < rj[k + 1]; ++q) c += sync_[pi[jp[q]]] ? 0 : 1;
        subset_off_[r + 1] = c;
      }
      for (std::size_t r = 0; r < na; ++r) subset_off_[r + 1] += subset_off_[r];
      subset_.pairs.resize(subset_off_[na]);
      subset_.hpair.resize(subset_off_[na]);
#pragma omp parallel for schedule(static) if (na >= kOmpMin)
      for (std::size_t r = 0; r < na; ++r) {
        const std::uint32_t k = active_[r];
        std::size_t o = subset_off_[r];
        for (std::uint32_t p = ri[k]; p < ri[k + 1]; ++p, ++o) {
          subset_.pairs[o] = p;
          subset_.hpair[o] = hpair(p);
        }
        for (std::uint32_t q = rj[k]; q < rj[k + 1]; ++q)
          if (!sync_[pi[jp[q]]]) {  // else added from its i member
            subset_.pairs[o] = jp[q];
            subset_.hpair[o++] = hpair(jp[q]);
          }
      }
      cstats_ = contacts_->compute(sp_, vpred_, wpred_, subset_, F_, T_, sp_.dissipated.data());
    }
    // bonds of synchronised spheres (both ends always together), each with its spheres' step
    if (bonds_) bonds_->compute_synchronised(sp_, sync_, topen_, step_, h, F_, T_);
  }
  accelerations(active_.data(), na);
}

void Simulation::step_multirate() {
  const std::size_t n = sp_.size();
  const double h = cfg_.dt;
  const bool spin = contacts_ != nullptr;
  const bool sg = cfg_.self_gravity;
  const int K = block_;  // a power of two (close_gravity_block)
  const int L = trailing_level(K);
  const double hk = 0.5 * h * K;
  const std::int64_t s0 = step_ - block_start_;
  const bool open_block = s0 == 0;
  const bool open_kick = sg && open_block;
  double t0 = omp_get_wtime(), c0 = cpu_now_();
  if (open_block)
    for (std::size_t i = 0; i < n; ++i)
      if (level_[i] > L) {
        level_[i] = static_cast<std::uint8_t>(L);
        lflag_[i] = 1;
      }
  const std::int64_t st = step_;
#pragma omp parallel for schedule(static) if (n >= kOmpMin)
  for (std::size_t i = 0; i < n; ++i) {
    if (open_kick) sp_.v[i] += hk * ag_[i];
    const std::int64_t len = std::int64_t{1} << level_[i];
    if ((s0 & (len - 1)) == 0) {  // opening kick of a sphere synchronised now
      const double ho = 0.5 * h * static_cast<double>(len);
      hopen_[i] = ho;
      topen_[i] = st;
      sp_.v[i] += ho * a_[i];
      if (spin) sp_.w[i] += ho * alpha_[i];
    }
    sp_.x[i] += h * sp_.v[i];
  }
  ++step_;
  time_ = static_cast<double>(step_) * h;
  times_.integrate += omp_get_wtime() - t0;
  times_.cpu_integrate += cpu_now_() - c0;
  const std::int64_t s1 = s0 + 1;
  const int tz = std::min(trailing_level(s1), L);
  if (contacts_) {
    t0 = omp_get_wtime();
    c0 = cpu_now_();
    if (contacts_->update_neighbors(sp_)) ++times_.neighbour_builds;
    times_.neighbours += omp_get_wtime() - t0;
    times_.cpu_neighbours += cpu_now_() - c0;
  }
  t0 = omp_get_wtime();
  c0 = cpu_now_();
  for (std::size_t i = 0; i < n; ++i) {
    sync_[i] = level_[i] <= tz ? 1 : 0;
    promoted_[i] = 0;
  }
  if (bonds_ && bonds_->breaks() != bond_breaks_seen_) bond_index();  // broken bonds leave the rules
  update_pair_levels();
  assign_levels(tz, L);
  equalise_levels(tz);
  active_.clear();
  for (std::size_t i = 0; i < n; ++i)
    if (sync_[i]) active_.push_back(static_cast<std::uint32_t>(i));
  const double tl = omp_get_wtime() - t0;
  times_.levels += tl;
  times_.integrate += tl;
  times_.cpu_integrate += cpu_now_() - c0;
  t0 = omp_get_wtime();
  c0 = cpu_now_();
  multirate_forces();
  times_.contacts += omp_get_wtime() - t0;
  times_.cpu_contacts += cpu_now_() - c0;
  const bool close_kick = s1 == K;
  if (sg && close_kick) {
    if (cfg_.adaptive_gravity) ag_old_ = ag_;
    compute_gravity(false);
  }
  t0 = omp_get_wtime();
  c0 = cpu_now_();
  const std::size_t na = active_.size();
#pragma omp parallel for schedule(static) if (na >= kOmpMin)
  for (std::size_t r = 0; r < na; ++r) {
    const std::uint32_t i = active_[r];
    const double hc = 0.5 * (static_cast<double>(step_ - topen_[i]) * h);
    sp_.v[i] += hc * a_[i];
    if (spin) sp_.w[i] += hc * alpha_[i];
    if (sg && close_kick) sp_.v[i] += hk * ag_[i];
  }
  times_.integrate += omp_get_wtime() - t0;
  times_.cpu_integrate += cpu_now_() - c0;
  if (close_kick) {
    std::fill(lstats_.now.begin(), lstats_.now.end(), 0);
    for (std::size_t i = 0; i < n; ++i) ++lstats_.now[level_[i]];
    close_gravity_block();
  }
  ++times_.steps;
  check_state();
}

}  // namespace ssdem
