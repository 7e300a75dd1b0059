/// @file domain_sim.cpp
/// The integrator of simulation.hpp over the domain decomposition of domain_sim.hpp: KDK leapfrog
/// with impulse-RESPA gravity blocks (Tuckerman, Berne & Martyna 1992), the error-controlled
/// cadence and the dashpot velocity predictor, step for step as Simulation::step on one rank.
/// Exchanges, ghosts and gathering live in domain_exchange.cpp.
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <sstream>

#include "../omp_team.hpp"
#include "common/exact_sum_mpi.hpp"
#include "common/sorted_rows.hpp"
#include "common/status.hpp"
#include "ssdem/dt_rule.hpp"
#include "ssdem/gravity_cadence.hpp"
#include "ssdem/mpi/domain_sim.hpp"

namespace ssdem::mpi {

void DomainSim::check_config() const {
  if (!(cfg_.dt > 0.0)) throw common::InputError("time.dt must be > 0");
  if (cfg_.gravity_every < 1) throw common::InputError("gravity.every must be >= 1");
  if (cfg_.adaptive_gravity && (!(cfg_.gravity_tolerance > 0.0) || cfg_.gravity_max_every < 1))
    throw common::InputError("gravity.tolerance must be > 0 and gravity.max_every >= 1");
}

void DomainSim::setup_config(const SphereSummary& sum) {
  smax_ = sum.smax;
  if (cfg_.contacts) {
    check_dt(cfg_.contact, sum, !cfg_.walls.empty(), cfg_.dt, cfg_.min_steps_per_contact);
    skin_ = cfg_.skin > 0.0 ? cfg_.skin : 0.25 * smax_;  // as Simulation::setup
    reach_ = 2.0 * smax_ + skin_;
    contacts_ = std::make_unique<ContactSystem>(cfg_.contact, cfg_.walls, skin_);
    contacts_->set_owned(&mine_);  // no ghost-ghost pair is evaluated
    contacts_->set_margins(false);  // the movers' near_point searches the ordinary grid
  } else {
    reach_ = -1.0;  // no ghosts
  }
  if (cfg_.self_gravity && !cfg_.direct_gravity) tree_ = std::make_unique<DistributedTree>(comm_, cfg_.gravity);
  setup_multirate();
}

void DomainSim::setup(const Spheres& all, const BondSet& bonds) {
  check_config();
  if (!all.consistent()) throw common::InputError("spheres: array sizes differ");
  for (std::size_t i = 0; i < all.size(); ++i)
    if (!(all.m[i] > 0.0) || !(all.s[i] > 0.0))
      throw common::InputError("sphere id " + std::to_string(all.id[i]) + ": mass and radius must be > 0");
  setup_config(summarise(all));
  setup_bonds(bonds, all);  // domain_bonds.cpp
  n_global_ = all.size();
  const std::size_t lo = common::mpi::dense_first(all.size(), comm_.size, comm_.rank),
                    hi = common::mpi::dense_first(all.size(), comm_.size, comm_.rank + 1);
  carried_.clear();
  for (const common::Field& f : all.carried)  // this rank's block of each (carried_block)
    carried_.push_back(common::Field{f.name, f.unit, f.ncomp,
                                     std::vector<double>(f.values.begin() + static_cast<std::ptrdiff_t>(lo * f.ncomp),
                                                         f.values.begin() + static_cast<std::ptrdiff_t>(hi * f.ncomp)),
                                     f.description});
}

DomainSim::DomainSim(Comm& comm, const Spheres& all, SimConfig cfg, double imbalance)
    : comm_(comm), cfg_(std::move(cfg)), imbalance_(imbalance) {
  setup(all, cfg_.bonds);
  SimState st;
  st.bonds = std::move(cfg_.bonds);  // the state's from now on (as Simulation)
  cfg_.bonds = BondSet{};
  st.sp = all;
  st.sp.carried.clear();
  const std::size_t n = all.size();
  st.a.assign(n, Vec3::Zero());
  st.alpha.assign(n, Vec3::Zero());
  st.ag.assign(n, Vec3::Zero());
  block_ = cfg_.adaptive_gravity ? 1 : cfg_.gravity_every;
  distribute(st);
  if (contacts_) contacts_->set_edges(false);  // the initial overlaps are not onsets
  compute_forces(true);
  if (contacts_) contacts_->set_edges(true);
  check_state();
}

DomainSim::DomainSim(Comm& comm, const SimState& all, SimConfig cfg, double imbalance)
    : comm_(comm), cfg_(std::move(cfg)), imbalance_(imbalance) {
  setup(all.sp, all.bonds);
  cfg_.bonds = BondSet{};  // the state's (all.bonds), as after a fresh start: no copy kept
  const std::size_t n = all.sp.size();
  if (all.a.size() != n || all.alpha.size() != n || (cfg_.self_gravity && all.ag.size() != n))
    throw common::InputError("restart state: acceleration arrays do not match the sphere count");
  resume_clock(all);
  has_prev_ = cfg_.extrapolated_predictor && all.a_prev.size() == n;
  distribute(all);
}

void DomainSim::resume_clock(const SimState& st) {
  step_ = st.step;
  time_ = st.time;
  grav_step_ = st.gravity_step;
  if (cfg_.adaptive_gravity) {
    block_start_ = step_;
    block_ = st.gravity_block > 0 ? st.gravity_block : 1;
  } else {
    block_ = cfg_.gravity_every;
    block_start_ = step_ / block_ * block_;
  }
}

void DomainSim::compute_gravity() {
  const double t0 = omp_get_wtime();
  const double b0 = comm_.bytes_sent;
  std::vector<double>* pot = want_pot_ ? &pot_ : nullptr;
  if (pot) pot_.resize(sp_.size());
  if (tree_) {
    tree_->compute(sp_, own_, ag_, pot, gidx_);
  } else {
    // direct summation: every sphere's position, mass and radius on every rank
    struct GX {
      std::uint64_t g;
      double x[3], m, s;
    };
    std::vector<GX> mine(own_.size());
    for (std::size_t k = 0; k < own_.size(); ++k) {
      const std::uint32_t i = own_[k];
      mine[k] = GX{gidx_[i], {sp_.x[i].x(), sp_.x[i].y(), sp_.x[i].z()}, sp_.m[i], sp_.s[i]};
    }
    const double c0 = omp_get_wtime();
    const std::vector<GX> all = comm_.gather(mine);
    stats_.wall_comm += omp_get_wtime() - c0;
    Spheres g;
    g.resize(n_global_);
    for (const GX& p : all) {
      g.x[p.g] = Vec3(p.x[0], p.x[1], p.x[2]);
      g.m[p.g] = p.m;
      g.s[p.g] = p.s;
    }
    std::vector<Vec3> acc;
    std::vector<double> gp;
    direct_gravity(g, cfg_.gravity.G, acc, pot ? &gp : nullptr);
    for (std::uint32_t i : own_) {
      ag_[i] = acc[gidx_[i]];
      if (pot) pot_[i] = gp[gidx_[i]];
    }
  }
  stats_.bytes_gravity += comm_.bytes_sent - b0;
  ++stats_.gravity_gathers;
  grav_step_ = step_;
  if (pot) pot_step_ = step_;
  times_.gravity += omp_get_wtime() - t0;
  ++times_.gravity_evals;
}

void DomainSim::compute_forces(bool initial) {
  const double h = cfg_.dt, hh = 0.5 * h;
  const std::size_t no = own_.size();
  if (contacts_) {
    for_blocks(no, Work::items, [&](std::size_t lo, std::size_t hi) {
      for (std::size_t k = lo; k < hi; ++k) {
        const std::uint32_t i = own_[k];
        if (initial) {
          vpred_[i] = sp_.v[i];
          wpred_[i] = sp_.w[i];
          continue;
        }
        vpred_[i] = sp_.v[i] + hh * a_[i];
        wpred_[i] = sp_.w[i] + hh * alpha_[i];
        if (has_prev_) {
          vpred_[i] += hh * (a_[i] - a_prev_[i]);
          wpred_[i] += hh * (alpha_[i] - alpha_prev_[i]);
        }
      }
    });
    if (!initial && cfg_.extrapolated_predictor) {
      for (std::uint32_t i : own_) {
        a_prev_[i] = a_[i];
        alpha_prev_[i] = alpha_[i];
      }
      has_prev_ = true;
    }
    halo_update();
    const double t0 = omp_get_wtime();
    if (contacts_->update_neighbors(sp_)) ++times_.neighbour_builds;
    const double t1 = omp_get_wtime();
    cstats_ = contacts_->compute(sp_, vpred_, wpred_, h, F_, T_, initial ? nullptr : sp_.dissipated.data());
    stats_.add(cstats_);
    // bonds: in bond order after the contacts, with the half-step velocities (as Simulation)
    if (bonds_) bonds_->compute(sp_, initial ? 0.0 : h, F_, T_);
    times_.neighbours += t1 - t0;
    times_.contacts += omp_get_wtime() - t1;
  }
  if (cfg_.self_gravity && initial) compute_gravity();
  accelerations(sp_, F_, T_, cfg_.uniform_g, contacts_ != nullptr, own_.data(), no, a_, alpha_);
}

void DomainSim::step() {
  if (cfg_.multirate) {
    step_multirate();
    return;
  }
  const double h = cfg_.dt, hh = 0.5 * h;
  const bool spin = contacts_ != nullptr;
  const bool sg = cfg_.self_gravity;
  const int k = block_;
  const double hk = 0.5 * h * k;
  const bool open_kick = sg && step_ == block_start_;
  double t0 = omp_get_wtime();
  const std::size_t no = own_.size();
  for_blocks(no, Work::items, [&](std::size_t lo, std::size_t hi) {
    for (std::size_t q = lo; q < hi; ++q) {
      const std::uint32_t i = own_[q];
      if (open_kick) sp_.v[i] += hk * ag_[i];
      sp_.v[i] += hh * a_[i];
      if (spin) sp_.w[i] += hh * alpha_[i];
      sp_.x[i] += h * sp_.v[i];
    }
  });
  ++step_;
  time_ = static_cast<double>(step_) * h;
  times_.integrate += omp_get_wtime() - t0;
  const bool close_kick = step_ == block_start_ + k;
  // exchange: with contacts when a sphere moved more than skin/2 (domain_sim.hpp); without, at
  // gravity evaluations (ownership then only balances the work)
  const double c0 = omp_get_wtime();
  const bool ex = contacts_ ? need_exchange() : close_kick;
  stats_.wall_comm += omp_get_wtime() - c0;
  if (ex) exchange();
  compute_forces(false);
  if (sg && close_kick) {
    if (cfg_.adaptive_gravity) ag_old_ = ag_;
    compute_gravity();
  }
  t0 = omp_get_wtime();
  const std::size_t no2 = own_.size();  // the exchange may have changed the own set
  for_blocks(no2, Work::items, [&](std::size_t lo, std::size_t hi) {
    for (std::size_t q = lo; q < hi; ++q) {
      const std::uint32_t i = own_[q];
      sp_.v[i] += hh * a_[i];
      if (spin) sp_.w[i] += hh * alpha_[i];
      if (sg && close_kick) sp_.v[i] += hk * ag_[i];
    }
  });
  times_.integrate += omp_get_wtime() - t0;
  if (close_kick) close_gravity_block();
  ++times_.steps;
  ++stats_.steps;
  check_state();
}

void DomainSim::close_gravity_block() {
  const int k = block_;
  block_start_ = step_;
  int next = cfg_.gravity_every;
  if (cfg_.adaptive_gravity) {
    next = 1;
    if (cfg_.self_gravity) {
      const std::size_t n = n_global_;
      // global sums, exact over the ranks: the bits of one rank's (gravity_cadence.hpp)
      common::ExactSum g2s = cadence_g2(ag_, &own_);
      common::mpi::allreduce(comm_, g2s);
      const double g2 = g2s.value();
      const double floor = 0.1 * std::sqrt(g2 / static_cast<double>(std::max<std::size_t>(n, 1)));
      common::ExactSum d2s;
      double cmax = 0;
      cadence_change(ag_, ag_old_, floor, &own_, d2s, cmax);
      common::mpi::allreduce(comm_, d2s);
      cmax = comm_.max(cmax);
      next = next_gravity_block(k, g2, d2s.value(), cmax, cfg_, cadence_);
    }
  }
  if (end_step_ > step_) next = static_cast<int>(std::min<std::int64_t>(next, end_step_ - step_));
  block_ = std::max(next, 1);
  if (cfg_.multirate) block_ = floor_pow2(block_);  // levels need power-of-two blocks
}

void DomainSim::check_state() {
  pending_ = Pending{};
  pending_.step = step_;
  for (std::uint32_t i : own_)  // own_ in index order: the first is the rank's smallest index
    if (!sp_.x[i].allFinite() || !sp_.v[i].allFinite() || !a_[i].allFinite() || !sp_.w[i].allFinite() ||
        !ag_[i].allFinite()) {
      pending_.bad_g = gidx_[i];
      pending_.bad_id = sp_.id[i];
      break;
    }
  if (contacts_ && cstats_.max_overlap_frac > 0.0) {
    pending_.overlap = cstats_.max_overlap_frac;
    pending_.id_a = sp_.id[cstats_.worst_a];
    pending_.id_b = sp_.id[cstats_.worst_b];
  }
  // Inside a gravity block (no output, no kept state) the verdict rides on the next base step's
  // movers allgather (need_exchange, before anything is computed from this state): one
  // collective per base step fewer. At block boundaries, where the driver writes, now.
  if (contacts_ && comm_.size > 1 && !at_gravity_boundary()) return;
  verdict(comm_.gather(parts_to_send()));
  // a verified state (the same steps on every rank: the decision is collective above)
  if (keep_every_ > 0 && at_gravity_boundary() && (!last_good_ || step_ >= last_good_->step + keep_every_))
    last_good_ = pack_local();
}

std::vector<DomainSim::Pending> DomainSim::parts_to_send() {
  const bool fails = pending_.bad_g != ~std::uint64_t{0} || (contacts_ && pending_.overlap > cfg_.max_overlap_frac);
  if (!fails) return {};
  ++stats_.check_parts;
  return {pending_};
}

void DomainSim::verdict(const std::vector<Pending>& all) {
  const std::int64_t step = pending_.step;
  pending_ = Pending{};
  const Pending* first = nullptr;  // the first non-finite sphere, as one rank finds it
  const Pending* worst = nullptr;  // the largest overlap
  for (const Pending& p : all) {
    if (p.bad_g != ~std::uint64_t{0} && (!first || p.bad_g < first->bad_g)) first = &p;
    if (!worst || p.overlap > worst->overlap) worst = &p;
  }
  if (first) {  // the one-rank message (simulation.cpp check_state)
    std::ostringstream os;
    os << "non-finite state of sphere id " << first->bad_id << " at step " << step;
    throw common::NumericalError(os.str());
  }
  if (contacts_ && worst && worst->overlap > cfg_.max_overlap_frac) {
    std::ostringstream os;
    os << "overlap of " << worst->overlap << " x the smaller radius (limit contact.max_overlap_fraction = "
       << cfg_.max_overlap_frac << ") between sphere ids " << worst->id_a << " and "
       << (worst->id_a == worst->id_b ? std::string("a wall") : std::to_string(worst->id_b)) << " at step " << step
       << ": k_n too soft or dt too large for this impact speed";
    throw common::NumericalError(os.str());
  }
}

double DomainSim::bytes_per_owned_sphere() const {
  const double nl = static_cast<double>(sp_.size());
  double b = nl * (Spheres::bytes_per_sphere() + 8 + 1 + 12 * 24);  // local set, gidx, flags, state arrays
  if (cfg_.multirate) b += nl * (4 + 8 + 3 * 8 + 4);  // levels/flags, opening step, h_open, tau_prev, tau, active
  if (bonds_) b += bonds_->bytes_per_sphere(1) + static_cast<double>(bg_.size()) * 9;  // bonds, rows, owner flags
  b += static_cast<double>(retired_.size()) * (161.0 + 24.0);
  if (blevels_) b += blevels_->bytes();
  if (contacts_) b += nl * contacts_->bytes_per_sphere(sp_.size());
  b += static_cast<double>(pot_.capacity()) * 8;    // potentials (rows)
  if (tree_) b += tree_->bytes();
  return own_.empty() ? b : b / static_cast<double>(own_.size());
}

}  // namespace ssdem::mpi
