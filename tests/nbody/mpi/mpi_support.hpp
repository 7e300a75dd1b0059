/// @file mpi_support.hpp
/// What the MPI tests of ssdem-grav share: the world communicator, one OpenMP thread (the
/// one-rank references sum in index order; a test that wants more threads asks for them), the
/// G = 1 contact configuration of their piles, and the comparison of a gathered state with one
/// rank's.
#pragma once
#include <mpi.h>
#include <omp.h>

#include <algorithm>

#include <cmath>

#include "common/rng.hpp"
#include "ssdem/contact_params.hpp"
#include "ssdem/dt_rule.hpp"
#include "ssdem/generators.hpp"
#include "ssdem/mpi/comm.hpp"
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
}  // namespace ssdem_test
