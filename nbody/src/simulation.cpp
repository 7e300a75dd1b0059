/// @file simulation.cpp
/// KDK leapfrog driver; equations in simulation.hpp.
#include "ssdem/simulation.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <ctime>
#include <sstream>

#include "common/status.hpp"
#include "omp_team.hpp"
#include "ssdem/dt_rule.hpp"
#include "ssdem/gravity_cadence.hpp"

namespace ssdem {
namespace {
double cpu_now() {
  timespec t;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}
}  // namespace

double Simulation::cpu_now_() const { return cpu_timing_ ? cpu_now() : 0.0; }

Simulation::Simulation(Spheres sp, SimConfig cfg) : cfg_(std::move(cfg)), sp_(std::move(sp)) {
  setup();
  setup_bonds(std::move(cfg_.bonds));
  cfg_.bonds = BondSet{};
  setup_multirate(nullptr);
  const std::size_t n = sp_.size();
  a_.assign(n, Vec3::Zero());
  alpha_.assign(n, Vec3::Zero());
  ag_.assign(n, Vec3::Zero());
  block_ = cfg_.adaptive_gravity ? 1 : cfg_.gravity_every;
  if (contacts_) contacts_->set_edges(false);  // the initial overlaps are not onsets
  compute_forces(true);
  if (contacts_) contacts_->set_edges(true);
  check_state();
}

Simulation::Simulation(SimState st, SimConfig cfg) : cfg_(std::move(cfg)), sp_(std::move(st.sp)) {
  setup();
  setup_bonds(std::move(st.bonds));
  cfg_.bonds = BondSet{};
  setup_multirate(&st);
  const std::size_t n = sp_.size();
  if (st.a.size() != n || st.alpha.size() != n || (cfg_.self_gravity && st.ag.size() != n))
    throw common::InputError("restart state: acceleration arrays do not match the sphere count");
  a_ = std::move(st.a);
  alpha_ = std::move(st.alpha);
  ag_ = cfg_.self_gravity ? std::move(st.ag) : std::vector<Vec3>(n, Vec3::Zero());
  step_ = st.step;
  time_ = st.time;
  grav_step_ = st.gravity_step;
  if (cfg_.adaptive_gravity) {
    block_start_ = step_;  // adaptive: states are saved at block boundaries
    block_ = st.gravity_block > 0 ? st.gravity_block : 1;
  } else {
    block_ = cfg_.gravity_every;  // fixed: blocks start at multiples of k (a state may be mid-block)
    block_start_ = step_ / block_ * block_;
  }
  if (cfg_.extrapolated_predictor && st.a_prev.size() == n) {
    a_prev_ = std::move(st.a_prev);
    alpha_prev_ = std::move(st.alpha_prev);
  }
  if (contacts_) contacts_->import_history(sp_, st.history);
}

void Simulation::setup() {
  if (!(cfg_.dt > 0.0)) throw common::InputError("time.dt must be > 0");
  if (cfg_.gravity_every < 1) throw common::InputError("gravity.every must be >= 1");
  if (cfg_.adaptive_gravity && (!(cfg_.gravity_tolerance > 0.0) || cfg_.gravity_max_every < 1))
    throw common::InputError("gravity.tolerance must be > 0 and gravity.max_every >= 1");
  const std::size_t n = sp_.size();
  if (!sp_.consistent()) throw common::InputError("spheres: array sizes differ");
  for (std::size_t i = 0; i < n; ++i)
    if (!(sp_.m[i] > 0.0) || !(sp_.s[i] > 0.0))
      throw common::InputError("sphere id " + std::to_string(sp_.id[i]) +
                               ": mass and radius must be > 0");
  if (cfg_.contacts) {
    check_dt(cfg_.contact, sp_, !cfg_.walls.empty(), cfg_.dt, cfg_.min_steps_per_contact);
    double smax = 0;
    for (double s : sp_.s) smax = std::max(smax, s);
    // default skin 0.25 s_max: chosen by the nbody-debris-skin sweep (nbody/README.md)
    const double skin = cfg_.skin > 0.0 ? cfg_.skin : 0.25 * smax;
    contacts_ = std::make_unique<ContactSystem>(cfg_.contact, cfg_.walls, skin);
  }
  if (cfg_.self_gravity && !cfg_.direct_gravity) tree_ = std::make_unique<TreeGravity>(cfg_.gravity);
}

void Simulation::setup_bonds(BondSet b) {
  if (b.empty()) return;  // no bonds: no arrays, no cost
  if (!contacts_)
    throw common::InputError("bonds need the soft-sphere contacts (contact.enabled = true)");
  check_bond_dt(b, sp_, cfg_.dt, cfg_.min_steps_per_contact);
  bonds_ = std::make_unique<BondSystem>(std::move(b), sp_);
}

void Simulation::compute_gravity(bool with_pot) {
  const double t0 = omp_get_wtime(), c0 = cpu_now_();
  std::vector<double>* pp = with_pot ? &pot_ : nullptr;
  if (tree_)
    tree_->compute(sp_, ag_, pp);
  else
    direct_gravity(sp_, cfg_.gravity.G, ag_, pp);
  grav_step_ = step_;
  if (with_pot) pot_step_ = step_;
  times_.gravity += omp_get_wtime() - t0;
  times_.cpu_gravity += cpu_now_() - c0;
  ++times_.gravity_evals;
}

void Simulation::compute_forces(bool initial) {
  const std::size_t n = sp_.size();
  const double h = cfg_.dt;
  if (contacts_) {
    vpred_.resize(n);
    wpred_.resize(n);
    if (initial) {
      vpred_ = sp_.v;
      wpred_ = sp_.w;
    } else {
      for_blocks(n, Work::items, [&](std::size_t lo, std::size_t hi) {
        for (std::size_t i = lo; i < hi; ++i) {
          vpred_[i] = sp_.v[i] + 0.5 * h * a_[i];
          wpred_[i] = sp_.w[i] + 0.5 * h * alpha_[i];
        }
      });
      if (cfg_.extrapolated_predictor && a_prev_.size() == n) {
        // a_{n+1} ~ 2 a_n - a_{n-1}: v_pred = v_{n+1/2} + (h/2)(2 a_n - a_{n-1})
        for_blocks(n, Work::items, [&](std::size_t lo, std::size_t hi) {
          for (std::size_t i = lo; i < hi; ++i) {
            vpred_[i] += 0.5 * h * (a_[i] - a_prev_[i]);
            wpred_[i] += 0.5 * h * (alpha_[i] - alpha_prev_[i]);
          }
        });
      }
      if (cfg_.extrapolated_predictor) {
        a_prev_ = a_;
        alpha_prev_ = alpha_;
      }
    }
    const double t0 = omp_get_wtime(), c0 = cpu_now_();
    if (contacts_->update_neighbors(sp_)) ++times_.neighbour_builds;
    const double t1 = omp_get_wtime(), c1 = cpu_now_();
    // dissipation is counted over steps only (the initial evaluation is no step)
    cstats_ = contacts_->compute(sp_, vpred_, wpred_, h, F_, T_, initial ? nullptr : sp_.dissipated.data());
    // bonds: increments with the half-step velocities (none at the initial evaluation)
    if (bonds_) bonds_->compute(sp_, initial ? 0.0 : h, F_, T_);
    const double t2 = omp_get_wtime(), c2 = cpu_now_();
    times_.neighbours += t1 - t0;
    times_.contacts += t2 - t1;
    times_.cpu_neighbours += c1 - c0;
    times_.cpu_contacts += c2 - c1;
  }
  if (cfg_.self_gravity && initial) compute_gravity(false);
  accelerations(nullptr, n);
}

void accelerations(const Spheres& sp, const std::vector<Vec3>& F, const std::vector<Vec3>& T, const Vec3& g,
                   bool contacts, const std::uint32_t* idx, std::size_t count, std::vector<Vec3>& a,
                   std::vector<Vec3>& alpha) {
  for_blocks(count, Work::items, [&](std::size_t lo, std::size_t hi) {
    for (std::size_t r = lo; r < hi; ++r) {
      const std::size_t i = idx ? idx[r] : r;
      Vec3 ai = g;
      if (contacts) {
        ai += F[i] / sp.m[i];
        alpha[i] = T[i] / sp.inertia(i);
      }
      a[i] = ai;
    }
  });
}

// a = g_uniform + F/m, alpha = T/I for spheres idx[0..count) (all of 0..count if idx is null).
void Simulation::accelerations(const std::uint32_t* idx, std::size_t count) {
  ssdem::accelerations(sp_, F_, T_, cfg_.uniform_g, contacts_ != nullptr, idx, count, a_, alpha_);
}

void Simulation::step() {
  tuner_.tick(times_.gravity);  // gravity's regions are not gated by the team rules
  if (cfg_.multirate) {
    step_multirate();
    return;
  }
  const std::size_t n = sp_.size();
  const double h = cfg_.dt, hh = 0.5 * h;
  const bool spin = contacts_ != nullptr;
  const bool sg = cfg_.self_gravity;
  const int k = block_;
  const double hk = 0.5 * h * k;  // gravity impulse half-interval (RESPA outer half-kick)
  const bool open_kick = sg && step_ == block_start_;
  double t0 = omp_get_wtime(), c0 = cpu_now_();
  for_blocks(n, Work::items, [&](std::size_t lo, std::size_t hi) {
    for (std::size_t i = lo; i < hi; ++i) {
      if (open_kick) sp_.v[i] += hk * ag_[i];
      sp_.v[i] += hh * a_[i];
      if (spin) sp_.w[i] += hh * alpha_[i];
      sp_.x[i] += h * sp_.v[i];
    }
  });
  ++step_;
  time_ = static_cast<double>(step_) * h;  // no accumulated round-off; identical on restart
  times_.integrate += omp_get_wtime() - t0;
  times_.cpu_integrate += cpu_now_() - c0;
  compute_forces(false);
  const bool close_kick = step_ == block_start_ + k;
  if (sg && close_kick) {
    if (cfg_.adaptive_gravity) ag_old_ = ag_;
    compute_gravity(want_pot_);
  }
  t0 = omp_get_wtime();
  c0 = cpu_now_();
  for_blocks(n, Work::items, [&](std::size_t lo, std::size_t hi) {
    for (std::size_t i = lo; i < hi; ++i) {
      sp_.v[i] += hh * a_[i];
      if (spin) sp_.w[i] += hh * alpha_[i];
      if (sg && close_kick) sp_.v[i] += hk * ag_[i];
    }
  });
  times_.integrate += omp_get_wtime() - t0;
  times_.cpu_integrate += cpu_now_() - c0;
  if (close_kick) close_gravity_block();
  ++times_.steps;
  check_state();
}

void Simulation::close_gravity_block() {
  const int k = block_;
  block_start_ = step_;
  int next = cfg_.gravity_every;
  if (cfg_.adaptive_gravity) {
    next = 1;
    if (cfg_.self_gravity) {
      const std::size_t n = sp_.size();
      const double g2 = cadence_g2(ag_, nullptr).value();  // exact: thread-count independent
      const double floor = 0.1 * std::sqrt(g2 / static_cast<double>(std::max<std::size_t>(n, 1)));
      common::ExactSum d2;
      double cmax = 0;
      cadence_change(ag_, ag_old_, floor, nullptr, d2, cmax);
      next = next_gravity_block(k, g2, d2.value(), cmax, cfg_, cadence_);
    }
  }
  if (end_step_ > step_) next = static_cast<int>(std::min<std::int64_t>(next, end_step_ - step_));
  block_ = std::max(next, 1);
  if (cfg_.multirate) block_ = floor_pow2(block_);  // levels need power-of-two blocks
}

void Simulation::check_state(const std::vector<std::uint32_t>* only) {
  const std::size_t n = sp_.size();
  const std::size_t m = only ? only->size() : n;
  const std::uint32_t* idx = only ? only->data() : nullptr;
  // 0 * (sum of the values) is 0 unless one is NaN or infinite (no branch per sphere)
  // (a NaN or infinity in any term makes z so in any order of the sum: a team's order is free)
  double z = 0.0;
  for_blocks(m, Work::items, [&](std::size_t lo, std::size_t hi) {
    double s = 0.0;
    for (std::size_t r = lo; r < hi; ++r) {
      const std::size_t i = idx ? idx[r] : r;
      s += 0.0 * (sp_.x[i] + sp_.v[i] + a_[i] + sp_.w[i] + ag_[i]).sum();
    }
#pragma omp critical(ssdem_check_state)
    z += s;
  });
  if (!(z == 0.0)) {
    // the sphere named: the first with a non-finite position if any (where a non-finite velocity
    // went first, before the field or the contacts spread it), else the first non-finite one
    auto bad = [&](std::size_t i, bool pos_only) {
      return pos_only ? !sp_.x[i].allFinite()
                      : !sp_.v[i].allFinite() || !a_[i].allFinite() || !sp_.w[i].allFinite() || !ag_[i].allFinite();
    };
    for (const bool pos_only : {true, false})
      for (std::size_t i = 0; i < n; ++i)
        if (bad(i, pos_only)) {
          std::ostringstream os;
          os << "non-finite state of sphere id " << sp_.id[i] << " at step " << step_;
          throw common::NumericalError(os.str());
        }
  }
  if (contacts_ && cstats_.max_overlap_frac > cfg_.max_overlap_frac) {
    std::ostringstream os;
    os << "overlap of " << cstats_.max_overlap_frac
       << " x the smaller radius (limit contact.max_overlap_fraction = " << cfg_.max_overlap_frac
       << ") between sphere ids " << sp_.id[cstats_.worst_a] << " and "
       << (cstats_.worst_a == cstats_.worst_b ? std::string("a wall")
                                              : std::to_string(sp_.id[cstats_.worst_b]))
       << " at step " << step_ << ": k_n too soft or dt too large for this impact speed";
    throw common::NumericalError(os.str());
  }
  if (keep_every_ > 0 && at_gravity_boundary() && (!last_good_ || step_ >= last_good_->step + keep_every_))
    last_good_ = state();
}

Diagnostics Simulation::diagnostics() {
  Diagnostics d;
  const std::size_t n = sp_.size();
  if (cfg_.self_gravity && pot_step_ != step_) {
    // potential at the current positions; keep the held acceleration untouched
    std::vector<Vec3> keep = ag_;
    const std::int64_t gs = grav_step_;
    compute_gravity(true);
    ag_.swap(keep);
    grav_step_ = gs;
    --times_.gravity_evals;
  }
  DiagnosticSums sums;  // exact: the same bits as the MPI ranks' (diagnostics.hpp)
  for (std::size_t i = 0; i < n; ++i)
    sums.add_sphere(sp_, i, contacts_ != nullptr, cfg_.self_gravity ? &pot_[i] : nullptr, cfg_.uniform_g);
  if (contacts_) {
    contacts_->add_elastic_energy(sp_, sums.elastic);
    if (bonds_) {
      d.bond_elastic = bonds_->elastic_energy(sp_);
      sums.elastic += d.bond_elastic;
      d.bond_released = bonds_->released_energy();
      d.bonds = bonds_->bonds().size();
      d.bonds_broken = bonds_->broken_count();
    }
    d.contacts = cstats_.contacts;
    d.wall_contacts = cstats_.wall_contacts;
    d.max_overlap_frac = cstats_.max_overlap_frac;
  }
  sums.store(d);
  return d;
}

void Simulation::continue_counters(const Simulation& b, double extra_neighbours_s) {
  times_ = b.times_;
  times_.neighbours += extra_neighbours_s;
  cadence_ = b.cadence_;
  lstats_ = b.lstats_;
  cstats_ = b.cstats_;
  end_step_ = b.end_step_;
  cpu_timing_ = b.cpu_timing_;
  if (contacts_ && b.contacts_) contacts_->continue_counters(*b.contacts_);
  set_keep_last_good(b.keep_every_);
}

SimState Simulation::state() const {
  SimState s;
  s.sp = sp_;
  s.a = a_;
  s.alpha = alpha_;
  if (cfg_.self_gravity) s.ag = ag_;
  s.step = step_;
  s.time = time_;
  s.gravity_step = grav_step_;
  s.gravity_block = block_;
  s.a_prev = a_prev_;
  s.alpha_prev = alpha_prev_;
  if (contacts_) s.history = contacts_->export_history(sp_);
  if (bonds_) s.bonds = bonds_->bonds();
  s.level = lr_.level;
  s.tau_prev = tau_prev_;
  return s;
}

double Simulation::bytes_per_sphere() const {
  const std::size_t n = sp_.size();
  double b = Spheres::bytes_per_sphere() + 2 * 24;  // spheres + a, alpha
  if (cfg_.self_gravity) b += 24;
  if (contacts_) b += 4 * 24 + contacts_->bytes_per_sphere(n);  // vpred, wpred, F, T
  if (contacts_ && cfg_.extrapolated_predictor) b += 2 * 24;     // a_prev, alpha_prev
  if (tree_) b += tree_->bytes_per_sphere(n);
  if (bonds_) b += bonds_->bytes_per_sphere(n);
  if (cfg_.multirate) b += 4 + 8 + 2 * 8 + 4;  // levels/flags, opening step, h_open, tau_prev, active
  if (blevels_ && n > 0) b += blevels_->bytes() / static_cast<double>(n);  // bond levels, sphere -> bond index
  return b;
}

}  // namespace ssdem
