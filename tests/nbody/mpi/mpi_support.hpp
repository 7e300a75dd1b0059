/// @file mpi_support.hpp
/// What the MPI tests of ssdem-grav share: the world communicator, one OpenMP thread (the
/// one-rank references sum in index order; a test that wants more threads asks for them), the
/// G = 1 contact configuration of their piles, and the comparison of a gathered state with one
/// rank's (state_diff; compare: a distributed run beside a one-rank one, bit for bit).
#pragma once
#include <mpi.h>
#include <omp.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>

#include "common/rng.hpp"
#include "ssdem/contact_params.hpp"
#include "ssdem/dt_rule.hpp"
#include "ssdem/generators.hpp"
#include "ssdem/mpi/comm.hpp"
#include "ssdem/mpi/domain_sim.hpp"
#include "ssdem/simulation.hpp"

namespace ssdem_test {
inline ssdem::mpi::Comm& world() {
  static ssdem::mpi::Comm c(MPI_COMM_WORLD);
  return c;
}
[[maybe_unused]] inline const bool kOneThread = [] {
  omp_set_num_threads(1);
  return true;
}();

/// G = 1 pile of radius R of 0.1-radius spheres (lattice_pile, jitter 0.05) with random
/// velocities (0.3 v_esc) and spins drawn from KeyedRng(seed, id).
inline ssdem::Spheres hot_pile(double R, std::uint64_t seed, std::uint64_t first_id = 0) {
  using ssdem::Vec3;
  ssdem::Spheres sp = ssdem::lattice_pile(R, 0.1, 1.0, 0.05, 3, Vec3::Zero(), first_id);
  const double M = ssdem::total_mass(sp), vesc = std::sqrt(2 * M / R);
  for (std::size_t i = 0; i < sp.size(); ++i) {
    common::KeyedRng rng(seed, sp.id[i]);
    sp.v[i] = 0.3 * vesc * Vec3(rng.normal(), rng.normal(), rng.normal()) / std::sqrt(3.0);
    sp.w[i] = Vec3(rng.normal(), rng.normal(), rng.normal());
  }
  return sp;
}

/// Self-gravity (G = 1; the tree or direct, adaptive cadence or every 3 steps) and gravel-like
/// contacts for 0.1-radius spheres of the first sphere's mass, k_n for impacts at vmax; dt not a
/// round number of steps per contact.
inline ssdem::SimConfig pile_config(const ssdem::Spheres& sp, double vmax, bool tree, bool adaptive) {
  const ssdem::DtAdvice adv = ssdem::choose_kn_dt(sp.m[0], 0.1, vmax, 1.0, 0.01, 30);
  ssdem::SimConfig c;
  c.self_gravity = true;
  c.direct_gravity = !tree;
  c.gravity.G = 1.0;
  c.adaptive_gravity = adaptive;
  c.gravity_every = 3;
  c.contacts = true;
  c.contact = ssdem::gravel_preset(adv.kn);
  c.dt = 0.77 * adv.dt;
  return c;
}

/// A slab of 20 x 3 spheres of 1 m radius and 2000 kg/m^3 along x at z = 0, 2 mm apart, at rest
/// (the ORB cuts it across x); ids 100 i + j + 1.
inline ssdem::Spheres slab_of_spheres() {
  using ssdem::Vec3;
  ssdem::Spheres sp;
  const double m = 2000.0 * 4.0 / 3.0 * M_PI;
  for (int i = 0; i < 20; ++i)
    for (int j = -1; j <= 1; ++j)
      sp.push(100 * i + j + 1, Vec3((i - 9.5) * 2.002, j * 2.002, 0.0), Vec3::Zero(), Vec3::Zero(), m, 1.0);
  return sp;
}

/// Largest difference between a gathered and a one-rank state (positions, velocities, spins,
/// accelerations, the contact history); -1 if their layouts differ.
inline double state_diff(const ssdem::SimState& a, const ssdem::SimState& b) {
  if (a.sp.size() != b.sp.size() || a.history.size() != b.history.size() || a.step != b.step) return -1;
  double d = 0;
  for (std::size_t i = 0; i < a.sp.size(); ++i) {
    if (a.sp.id[i] != b.sp.id[i]) return -1;
    d = std::max({d, (a.sp.x[i] - b.sp.x[i]).norm(), (a.sp.v[i] - b.sp.v[i]).norm(), (a.sp.w[i] - b.sp.w[i]).norm(),
                  (a.a[i] - b.a[i]).norm(), (a.alpha[i] - b.alpha[i]).norm()});
  }
  for (std::size_t k = 0; k < a.history.size(); ++k) {
    if (a.history[k].id_a != b.history[k].id_a || a.history[k].id_b != b.history[k].id_b) return -1;
    for (std::size_t q = 0; q < a.history[k].v.size(); ++q)
      d = std::max(d, (a.history[k].v[q] - b.history[k].v[q]).norm());
  }
  return d;
}

struct Totals {
  double m = 0;
  ssdem::Vec3 P = ssdem::Vec3::Zero(), L = ssdem::Vec3::Zero();
};
inline Totals totals(const ssdem::SimState& s) {
  Totals t;
  for (std::size_t i = 0; i < s.sp.size(); ++i) {
    t.m += s.sp.m[i];
    t.P += s.sp.m[i] * s.sp.v[i];
    t.L += s.sp.m[i] * s.sp.x[i].cross(s.sp.v[i]) + 0.4 * s.sp.m[i] * s.sp.s[i] * s.sp.s[i] * s.sp.w[i];
  }
  return t;
}

/// Run `steps` steps distributed and (rank 0) serially; expect bit-identical states and totals.
/// `each` is called at the start and after every distributed step.
template <class F>
ssdem::SimState compare(const ssdem::Spheres& sp, const ssdem::SimConfig& cfg, int steps, const char* what, F&& each) {
  ssdem::mpi::DomainSim dsim(world(), sp, cfg);
  std::unique_ptr<ssdem::Simulation> ref;
  if (world().rank == 0) ref = std::make_unique<ssdem::Simulation>(sp, cfg);
  each(dsim);
  for (int k = 0; k < steps; ++k) {
    dsim.step();
    if (ref) ref->step();
    each(dsim);
  }
  ssdem::SimState got = dsim.gather_state();
  if (ref) {
    const ssdem::SimState want = ref->state();
    const double d = state_diff(got, want);
    const Totals tg = totals(got), tw = totals(want);
    std::printf("%s, %d ranks, %d steps: max |difference| vs one rank %.3g; mass %.17g vs %.17g, |dP| %.3g, "
                "|dL| %.3g; %zu contacts\n",
                what, world().size, steps, d, tg.m, tw.m, (tg.P - tw.P).norm(), (tg.L - tw.L).norm(), got.history.size());
    EXPECT_EQ(d, 0.0) << what;
    EXPECT_EQ(tg.m, tw.m);
    EXPECT_EQ((tg.P - tw.P).norm(), 0.0);
    EXPECT_EQ((tg.L - tw.L).norm(), 0.0);
  }
  return got;
}
}  // namespace ssdem_test
