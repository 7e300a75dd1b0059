/// @file domain_multirate.cpp
/// Multi-rate block time steps (time.multirate; scheme, rules and proofs in multirate.hpp) over the
/// domain decomposition of domain_sim.hpp: the base substep of Simulation::step_multirate with
/// the level rules of level_rules.hpp run on the local set (owned + ghosts) and the equalisation
/// completed across ranks by halo rounds (domain_sim.hpp, "Multi-rate steps").
#include <omp.h>

#include <algorithm>

#include "common/status.hpp"
#include "ssdem/mpi/domain_sim.hpp"

namespace ssdem::mpi {
void DomainSim::setup_multirate() {
  if (!cfg_.multirate) return;
  if (!(cfg_.pair_steps_per_contact > 0.0)) throw common::InputError("time.steps_per_contact must be > 0");
  cfg_.gravity_every = floor_pow2(std::max(cfg_.gravity_every, 1));
  cfg_.gravity_max_every = floor_pow2(std::max(cfg_.gravity_max_every, 1));
  lstats_.sphere_time.assign(kMaxLevel + 1, 0.0);
  if (contacts_) {
    contacts_->set_reinsert_fraction(0.25);  // every pair with gap < skin/2 is listed
    lr_.configure(PairClock(cfg_.contact, cfg_.dt, cfg_.pair_steps_per_contact, kMaxLevel), 0.5 * skin_);
  }
}

// Ghost positions after the drift (the level rules and the pair list need them).
// The ghosts that opened a step at base substep s0 (level l with 2^l | s0; both sides decide it
// from the same levels, so no index is sent): x, v, w after the owner's opening kick and drift.
// Every other ghost drifted here with the velocity its owner last sent, which the owner has not
// changed since (a velocity changes only at its sphere's kicks: the close of a step, whose
// sphere opens the next one, a promotion, sent with the force evaluation's halo, and the block's
// gravity kick, at s0 = 0 where every sphere opens), so its position is the owner's bit for bit.
void DomainSim::halo_opened(std::int64_t s0) {
  if (reach_ < 0.0) return;
  const double t0 = omp_get_wtime(), b0 = comm_.bytes_sent;
  auto opened = [&](std::uint32_t i) { return (s0 & ((std::int64_t{1} << lr_.level[i]) - 1)) == 0; };
  std::vector<std::vector<char>> out(comm_.size);
  std::vector<std::size_t> expect(comm_.size, 0);
  for (int r = 0; r < comm_.size; ++r) {
    for (std::uint32_t i : send_[r])
      if (opened(i))
        for (const Vec3* v : {&sp_.x[i], &sp_.v[i], &sp_.w[i]}) put(out[r], *v);
    for (std::uint32_t i : recv_[r]) expect[r] += opened(i) ? 3 * sizeof(Vec3) : 0;
  }
  const std::vector<std::vector<char>> in = comm_.neighbours(out, expect);
  for (int r = 0; r < comm_.size; ++r) {
    std::size_t off = 0;
    for (std::uint32_t i : recv_[r])
      if (opened(i))
        for (Vec3* v : {&sp_.x[i], &sp_.v[i], &sp_.w[i]}) *v = get<Vec3>(in[r], off);
  }
  stats_.bytes_halo += comm_.bytes_sent - b0;
  stats_.wall_comm += omp_get_wtime() - t0;
}

// The synchronised ghosts' v (a promotion's kick correction), w and predicted v, w, before a force
// evaluation; the other ghosts' predicted velocities are those of their last evaluation, as
// their owners hold them. After a rebuild of the local set (its ghosts carry no predicted
// velocities) every ghost's state is sent (halo_update).
void DomainSim::halo_synced() {
  if (reach_ < 0.0) return;
  if (ghosts_fresh_) {
    halo_update();
    ghosts_fresh_ = false;
    return;
  }
  const double t0 = omp_get_wtime(), b0 = comm_.bytes_sent;
  std::vector<std::vector<char>> out(comm_.size);
  std::vector<std::size_t> expect(comm_.size, 0);
  for (int r = 0; r < comm_.size; ++r) {
    for (std::uint32_t i : send_[r])
      if (lr_.sync[i])
        for (const Vec3* v : {&sp_.v[i], &sp_.w[i], &vpred_[i], &wpred_[i]}) put(out[r], *v);
    for (std::uint32_t i : recv_[r]) expect[r] += lr_.sync[i] ? 4 * sizeof(Vec3) : 0;
  }
  const std::vector<std::vector<char>> in = comm_.neighbours(out, expect);
  for (int r = 0; r < comm_.size; ++r) {
    std::size_t off = 0;
    for (std::uint32_t i : recv_[r])
      if (lr_.sync[i])
        for (Vec3* v : {&sp_.v[i], &sp_.w[i], &vpred_[i], &wpred_[i]}) *v = get<Vec3>(in[r], off);
  }
  stats_.bytes_halo += comm_.bytes_sent - b0;
  stats_.wall_comm += omp_get_wtime() - t0;
}

// Owners' levels to their ghosts. assign: the synchronised ghosts take their owners' new levels
// (only a synchronised sphere's level is assigned, and both sides know which are synchronised:
// a base step that synchronises no ghost sends nothing); else every ghost is lowered to its
// owner's level where that is lower (an equalisation round: LevelRules::lower mirrors the owner's
// promotion).
void DomainSim::halo_levels(bool assign, int tz) {
  if (reach_ < 0.0 || comm_.size == 1) return;
  const double t0 = omp_get_wtime(), b0 = comm_.bytes_sent;
  auto sent = [&](std::uint32_t i) { return !assign || lr_.sync[i] != 0; };
  std::vector<std::vector<char>> out(comm_.size);
  std::vector<std::size_t> expect(comm_.size, 0);
  for (int r = 0; r < comm_.size; ++r) {
    for (std::uint32_t i : send_[r])
      if (sent(i)) put(out[r], lr_.level[i]);
    for (std::uint32_t i : recv_[r]) expect[r] += sent(i) ? sizeof(std::uint8_t) : 0;
  }
  const std::vector<std::vector<char>> in = comm_.neighbours(out, expect);
  for (int r = 0; r < comm_.size; ++r) {
    std::size_t off = 0;
    for (std::uint32_t i : recv_[r]) {
      if (!sent(i)) continue;
      const auto l = get<std::uint8_t>(in[r], off);
      if (!assign) {
        lr_.lower(i, l, tz);
      } else if (lr_.level[i] != l) {
        lr_.level[i] = l;
        lr_.lflag[i] = 1;
      }
    }
  }
  stats_.bytes_halo += comm_.bytes_sent - b0;
  stats_.wall_comm += omp_get_wtime() - t0;
}

void DomainSim::multirate_forces(const Substep& ss) {
  const double h = cfg_.dt;
  const std::size_t no = own_active_.size(), na = active_.size();
  tau_own_.resize(no);
  predict_active(ActiveArrays{sp_, a_, alpha_, vpred_, wpred_, a_prev_, alpha_prev_, topen_, hopen_, tau_prev_,
                              lr_.promoted},
                 own_active_.data(), no, step_, h, cfg_.extrapolated_predictor, tau_own_.data(),
                 held_field(cfg_, ag_, sp_.size()), ss.hk);
  count_active(lstats_, own_active_.data(), no, step_, topen_, h);
  if (cfg_.extrapolated_predictor) has_prev_ = true;
  if (contacts_) {
    halo_synced();  // v (after a promotion's kick correction), w and the predicted v, w
    const double t0 = omp_get_wtime();
    subset_.spheres = active_;
    subset_.hsphere.resize(na);
    for (std::size_t r = 0; r < na; ++r) subset_.hsphere[r] = static_cast<double>(step_ - topen_[active_[r]]) * h;
    take_subset(subsets_, ss.tz, *contacts_, active_, lr_.sync, topen_, step_, h, subset_off_, subset_);
    cstats_ = contacts_->compute(sp_, vpred_, wpred_, subset_, F_, T_, sp_.dissipated.data());
    stats_.add(cstats_);
    keep_subset(subsets_, ss.tz, subset_);
    // bonds of synchronised spheres (both ends together: the equalisation), each with its step
    if (bonds_) bonds_->compute_synchronised(sp_, lr_.sync, topen_, step_, h, F_, T_);
    times_.contacts += omp_get_wtime() - t0;
  }
  accelerations(sp_, F_, T_, cfg_.uniform_g, contacts_ != nullptr, own_active_.data(), no, a_, alpha_);
}

void DomainSim::step_multirate() {
  const bool spin = contacts_ != nullptr;
  const bool sg = cfg_.self_gravity;
  const Substep ss(cfg_.dt, block_, step_, block_start_);
  double t0 = omp_get_wtime();
  if (ss.opens) lr_.cap(ss.L);  // (ghosts too: the same rule on the same level)
  const KickArrays kicks{sp_, a_, alpha_, ag_, lr_.level, topen_, hopen_};
  open_and_drift(kicks, mine_.data(), step_, ss.s0, ss.h, ss.hk, sg && ss.opens, spin,
                 held_field(cfg_, ag_, sp_.size()), active_.size());
  ++step_;
  time_ = static_cast<double>(step_) * ss.h;
  times_.integrate += omp_get_wtime() - t0;
  const double c0 = omp_get_wtime();
  const bool ex = contacts_ ? need_exchange() : ss.closes;
  stats_.wall_comm += omp_get_wtime() - c0;
  if (ex)
    exchange();
  else
    halo_opened(ss.s0);
  const int tz = ss.tz;
  if (contacts_) {
    t0 = omp_get_wtime();
    if (contacts_->update_neighbors(sp_)) ++times_.neighbour_builds;
    times_.neighbours += omp_get_wtime() - t0;
  }
  t0 = omp_get_wtime();
  const std::size_t n2 = sp_.size();  // the exchange may have changed the local set
  if (blevels_) blevels_->refresh();  // broken bonds leave the rules (on every rank that holds them alike)
  if (contacts_) lr_.update_pair_levels(sp_, *contacts_);
  lr_.assign(sp_, contacts_.get(), tz, ss.L, blevels_.get(), mine_.data());
  if (contacts_) {
    halo_levels(true, tz);
    // rounds to the fixed point: a local equalisation; if it changed the level of a sphere that
    // is a ghost elsewhere (on any rank), the owners' levels go to their ghosts (min) and another
    // round follows; else every rank holds its ghosts' levels and is at its local fixed point.
    // (After an equalisation lflag marks exactly the spheres it lowered: level_rules.hpp.)
    for (;;) {
      lr_.equalise(sp_, *contacts_, tz, blevels_.get());
      ++stats_.level_rounds;
      bool changed = false;
      for (const auto& sr : send_)
        for (std::uint32_t i : sr) changed = changed || lr_.lflag[i] != 0;
      const double c1 = omp_get_wtime();
      const bool any = comm_.size > 1 && comm_.max(changed ? 1.0 : 0.0) > 0.0;
      stats_.wall_comm += omp_get_wtime() - c1;
      if (!any) break;
      halo_levels(false, tz);
    }
  }
  active_.clear();
  own_active_.clear();
  for (std::size_t i = 0; i < n2; ++i)
    if (lr_.sync[i]) {
      active_.push_back(static_cast<std::uint32_t>(i));
      if (mine_[i]) {
        own_active_.push_back(static_cast<std::uint32_t>(i));
        lstats_.promotions += lr_.promoted[i];
      }
    }
  const double tl = omp_get_wtime() - t0;
  times_.levels += tl;
  times_.integrate += tl;
  multirate_forces(ss);
  if (sg && ss.closes) {
    if (cfg_.adaptive_gravity || cfg_.gravity_held) ag_old_ = ag_;
    compute_gravity();
  }
  t0 = omp_get_wtime();
  close_kicks(kicks, own_active_.data(), own_active_.size(), step_, ss.h, ss.hk, sg && ss.closes, spin,
              held_field(cfg_, sg && ss.closes ? ag_old_ : ag_, sp_.size()));
  times_.integrate += omp_get_wtime() - t0;
  if (ss.closes) close_gravity_block();
  ++times_.steps;
  ++stats_.steps;
  check_state();
}

LevelStats DomainSim::gather_level_stats() const {
  LevelStats out;
  if (!cfg_.multirate) return out;
  // spheres per level now (owned), sphere-time per level, promotions, evaluations (the counts are
  // exact in doubles below 2^53)
  std::vector<double> mine(lstats_.sphere_time.size(), 0.0);
  for (std::uint32_t i : own_) mine[std::min<int>(lr_.level[i], kMaxLevel)] += 1.0;
  mine.insert(mine.end(), lstats_.sphere_time.begin(), lstats_.sphere_time.end());
  mine.push_back(static_cast<double>(lstats_.promotions));
  mine.push_back(static_cast<double>(lstats_.evaluations));
  const std::vector<double> all = comm_.gather(mine, 0);
  if (comm_.rank != 0) return out;
  const std::size_t L = lstats_.sphere_time.size(), m = mine.size();
  out.now.assign(L, 0);
  out.sphere_time.assign(L, 0.0);
  for (std::size_t off = 0; off + m <= all.size(); off += m) {
    for (std::size_t l = 0; l < L; ++l) {
      out.now[l] += static_cast<std::int64_t>(all[off + l]);
      out.sphere_time[l] += all[off + L + l];
    }
    out.promotions += static_cast<std::int64_t>(all[off + 2 * L]);
    out.evaluations += static_cast<std::int64_t>(all[off + 2 * L + 1]);
  }
  return out;
}

}  // namespace ssdem::mpi
