/// @file test_multirate_bonds.cpp
/// Bonds with multi-rate block time steps (multirate.hpp "Bonds", multirate_bonds.cpp): every
/// intact bond keeps its two spheres on one level <= l_b = floor(log2(tau_b / (N h))).
/// Soft contacts (k_n = 1e3 N/m) are used wherever the bond alone must set the level, so that an
/// implementation ignoring the bonds in the level rule would step the bonded spheres on the
/// coarsest level (64 h) and fail every number below.
///  - bonded beam (the Euler-Bernoulli chain of test_nbody_bonds): on level 0 bit-identical to
///    single rate; on level 2 the first free-free frequency to the same 2 % and to single rate at
///    the same step (4 h) within 1e-6;
///  - undamped bonded lattice on level 1: energy to 5e-3 over 10^4 of its steps, momentum to
///    round-off;
///  - two separate bonded clusters, one with bonds 100x stiffer: levels 0 and 3 (asserted), each
///    cluster conserves its own energy; the stiff bonds, refused at the contact step, run;
///  - a bond on level 2 breaks under tension at the first of its level's steps past its strength,
///    its stored energy reported; afterwards its spheres leave level 2;
///  - restart through a checkpoint file and 1 vs 2 threads: bit-identical.
#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>

#include "common/status.hpp"
#include "ssdem/io.hpp"
#include "ssdem/simulation.hpp"

using namespace ssdem;

namespace {
constexpr double kS = 0.5, kRho = 2000.0, kSoftContact = 1e3;
double sphere_mass(double s) { return kRho * 4.0 / 3.0 * M_PI * s * s * s; }

// n^3 spheres of radius kS on a cubic lattice from `origin`, pseudo-random velocities and spins.
void add_cube(Spheres& sp, int n, double spacing, double vjit, const Vec3& origin, std::uint64_t id0) {
  const double m = sphere_mass(kS);
  std::uint64_t id = id0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k, ++id) {
        const double a = std::sin(12.9898 * id + 1.0), b = std::sin(78.233 * id + 2.0), q = std::sin(37.719 * id + 3.0);
        sp.push(id, origin + spacing * Vec3(i, j, k), vjit * Vec3(a, b, q), vjit / kS * Vec3(b, q, a), m, kS);
      }
}

BondParams bond_params(double kn, double ks, double strength = 1e300, double rr = 1.0) {
  BondParams bp;
  bp.kn = kn;
  bp.ks = ks;
  bp.sigma_c = bp.tau_c = strength;
  bp.radius_ratio = rr;
  return bp;
}

// Multi-rate config: undamped linear contacts of stiffness kc, the given bonds, base step dt,
// N = steps per contact of the level rule, blocks of 64 base steps (levels 0..6), no gravity.
SimConfig mr_config(double kc, BondSet bonds, double dt, double N) {
  SimConfig c;
  c.contacts = true;
  c.contact.parts = 0u;
  c.contact.kn = kc;
  c.bonds = std::move(bonds);
  c.dt = dt;
  c.multirate = true;
  c.pair_steps_per_contact = N;
  c.gravity_every = 64;
  return c;
}

std::size_t differing(const Spheres& a, const Spheres& b) {
  std::size_t d = 0;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (a.x[i] != b.x[i] || a.v[i] != b.v[i] || a.w[i] != b.w[i]) ++d;
  return d;
}

// Kinetic + rotational energy of the spheres with ids in [lo, hi) and elastic energy of their bonds.
double cluster_energy(const Simulation& sim, std::uint64_t lo, std::uint64_t hi) {
  const Spheres& sp = sim.spheres();
  double e = 0;
  for (std::size_t i = 0; i < sp.size(); ++i)
    if (sp.id[i] >= lo && sp.id[i] < hi)
      e += 0.5 * sp.m[i] * sp.v[i].squaredNorm() + 0.5 * sp.inertia(i) * sp.w[i].squaredNorm();
  const BondSystem& b = *sim.bond_system();
  for (std::size_t k = 0; k < b.bonds().size(); ++k)
    if (b.bonds().id_a[k] >= lo && b.bonds().id_a[k] < hi) e += b.energy(k, sp);
  return e;
}

// The free-free chain of test_nbody_bonds (N spheres, first mode excited) and its period.
struct Beam {
  Spheres sp;
  double T1 = 0;  // Euler-Bernoulli first-mode period
};
Beam beam(int N) {
  Beam b;
  const double L0 = 2 * kS * 1.0002, m = sphere_mass(kS);
  const double L = N * L0, bL = 4.730040745, k = bL / L;
  const double sg = (std::cosh(bL) - std::cos(bL)) / (std::sinh(bL) - std::sin(bL));
  const double V = 1e-3;
  for (int i = 0; i < N; ++i) {
    const double x = (i + 0.5) * L0;
    const double phi = std::cosh(k * x) + std::cos(k * x) - sg * (std::sinh(k * x) + std::sin(k * x));
    const double dphi = k * (std::sinh(k * x) - std::sin(k * x) - sg * (std::cosh(k * x) + std::cos(k * x)));
    b.sp.push(i, Vec3(x, 0, 0), Vec3(0, V * phi, 0), Vec3(0, 0, V * dphi), m, kS);
  }
  const double E = 1e8 * L0, I = M_PI * std::pow(kS, 4) / 4, ml = m / L0;
  b.T1 = 2 * M_PI / (bL * bL * std::sqrt(E * I / (ml * std::pow(L, 4))));
  return b;
}
// Period from the zero crossings of the middle's deflection over `steps` base steps.
double beam_period(Simulation& sim, int N, int steps) {
  auto mid = [&] {
    double ym = 0.5 * (sim.spheres().x[N / 2 - 1].y() + sim.spheres().x[N / 2].y()), yc = 0;
    for (int i = 0; i < N; ++i) yc += sim.spheres().x[i].y() / N;
    return ym - yc;
  };
  const double h = sim.config().dt;
  double prev = mid(), t_first = -1, t_last = -1;
  int crossings = 0;
  for (int k = 0; k < steps; ++k) {
    const double t0 = sim.time();
    sim.step();
    const double y = mid();
    if ((prev < 0) != (y < 0) && k > 0) {
      const double tc = t0 + h * prev / (prev - y);
      if (t_first < 0) t_first = tc;
      t_last = tc;
      ++crossings;
    }
    prev = y;
  }
  EXPECT_GE(crossings, 5);
  return 2 * (t_last - t_first) / (crossings - 1);
}
}  // namespace

TEST(MultirateBonds, BeamOnLevelZeroIsBitIdenticalToSingleRate) {
  const int N = 24;
  Beam b = beam(N);
  const BondSet bonds = generate_bonds(b.sp, bond_params(1e8, 1e8));
  ASSERT_EQ(bonds.size(), static_cast<std::size_t>(N - 1));
  const double dt = shortest_bond_time(bonds, b.sp) / 23.7;
  SimConfig c = mr_config(kSoftContact, bonds, dt, 23.7);  // r = 1: every bond on level 0
  SimConfig c1 = c;
  c1.multirate = false;
  c1.gravity_every = 1;
  Simulation s1(b.sp, c1), s2(b.sp, c);
  const int steps = static_cast<int>(1.2 * b.T1 / dt);
  for (int k = 0; k < steps; ++k) {
    s1.step();
    s2.step();
  }
  for (auto l : s2.bond_levels()) ASSERT_EQ(l, 0);
  for (auto l : s2.levels()) ASSERT_EQ(l, 0);
  EXPECT_EQ(differing(s1.spheres(), s2.spheres()), 0u);
}

TEST(MultirateBonds, BeamOnLevelTwoVibratesAtTheEulerBernoulliFrequency) {
  const int N = 24;
  Beam b = beam(N);
  const BondSet bonds = generate_bonds(b.sp, bond_params(1e8, 1e8));
  const double tau = shortest_bond_time(bonds, b.sp);
  const double h = tau / (23.7 * 4.5);  // r = 4.5: level 2, bond step 4 h = tau / 26.7
  SimConfig c = mr_config(kSoftContact, bonds, h, 23.7);
  Simulation sim(b.sp, c);
  const double T = beam_period(sim, N, static_cast<int>(3.3 * b.T1 / h));
  for (auto l : sim.bond_levels()) ASSERT_EQ(l, 2);
  for (auto l : sim.levels()) ASSERT_EQ(l, 2);
  SimConfig c1 = c;  // single rate at the bond's step
  c1.multirate = false;
  c1.gravity_every = 1;
  c1.dt = 4 * h;
  Simulation ref(b.sp, c1);
  const double T4 = beam_period(ref, N, static_cast<int>(3.3 * b.T1 / (4 * h)));
  std::printf("beam on level 2: period %.6f s, single rate at 4 h %.6f s, Euler-Bernoulli %.6f s (rel %.2e)\n", T, T4,
              b.T1, T / b.T1 - 1);
  EXPECT_NEAR(T / b.T1, 1.0, 0.02);
  EXPECT_NEAR(T / T4, 1.0, 1e-6);  // the same step grid: round-off (drift summed in steps of h)
}

TEST(MultirateBonds, UndampedLatticeConservesEnergyAndMomentum) {
  Spheres sp;
  add_cube(sp, 3, 2 * kS * 1.002, 1e-3, Vec3::Zero(), 0);
  const BondSet bonds = generate_bonds(sp, bond_params(2e8, 0.8e8, 1e300, 0.7));
  ASSERT_EQ(bonds.size(), 54u);
  const double h = shortest_bond_time(bonds, sp) / (31.7 * 2.5);  // level 1: 39.6 steps per shortest mode
  Simulation sim(sp, mr_config(kSoftContact, bonds, h, 31.7));
  const Diagnostics d0 = sim.diagnostics();
  double pscale = 0;
  for (std::size_t i = 0; i < sp.size(); ++i) pscale += sp.m[i] * sp.v[i].norm();
  double emax = 0, pmax = 0, lmax = 0;
  for (int k = 0; k < 20000; ++k) {  // 10^4 steps of level 1
    sim.step();
    if (sim.at_gravity_boundary()) {  // every sphere synchronised
      const Diagnostics d = sim.diagnostics();
      emax = std::max(emax, std::fabs(d.total() - d0.total()) / d0.total());
      pmax = std::max(pmax, (d.momentum - d0.momentum).norm() / pscale);
      lmax = std::max(lmax, (d.angular_momentum - d0.angular_momentum).norm() / (pscale * 3 * kS));
    }
  }
  for (auto l : sim.levels()) ASSERT_EQ(l, 1);
  const Diagnostics d = sim.diagnostics();
  std::printf("bonded lattice on level 1, 10^4 steps: |dE|/E <= %.2e (bond share %.2f), |dP| %.1e, |dL| %.1e\n", emax,
              d.bond_elastic / d.total(), pmax, lmax);
  EXPECT_GT(d.bond_elastic, 0.1 * d.total());
  EXPECT_LT(emax, 5e-3);
  EXPECT_LT(pmax, 1e-12);
  EXPECT_LT(lmax, 1e-10);
}

namespace {
// Cluster A (ids 0..26): bonds k_n = 1e7; cluster B (ids 100..126, 20 m away): 100x stiffer.
// Contacts with k_n = the soft bonds' k_n A (the contact step of the scene); base step from the
// dt rule including the bonds: min(tau_c, tau_b) / 30.
SimConfig two_clusters(Spheres& sp, double strength_soft = 1e300) {
  add_cube(sp, 3, 2 * kS * 1.002, 2e-3, Vec3::Zero(), 0);
  Spheres b;
  add_cube(b, 3, 2 * kS * 1.002, 2e-4, Vec3(20, 0, 0), 100);
  const BondSet soft = generate_bonds(sp, bond_params(1e7, 0.5e7, strength_soft));
  BondSet bonds = soft;
  const BondSet stiff = generate_bonds(b, bond_params(1e9, 0.5e9));
  for (std::size_t k = 0; k < stiff.size(); ++k)
    bonds.add(stiff.id_a[k], stiff.id_b[k], stiff.kn[k], stiff.ks[k], stiff.sigma_c[k], stiff.tau_c[k],
              stiff.radius[k], stiff.length0[k], stiff.n_old[k]);
  for (std::size_t i = 0; i < b.size(); ++i) sp.push(b.id[i], b.x[i], b.v[i], b.w[i], b.m[i], b.s[i]);
  const double kc = 1e7 * M_PI * kS * kS;
  ContactParams p;
  p.parts = 0u;
  p.kn = kc;
  const double dt = std::min(p.contact_time(0.5 * sp.m[0]), shortest_bond_time(bonds, sp)) / 30.0;
  return mr_config(kc, bonds, dt, 30.0);
}
}  // namespace

TEST(MultirateBonds, StiffClusterStepsFinerAndBothConserveEnergy) {
  Spheres sp;
  SimConfig c = two_clusters(sp);
  // the stiff bonds at the contact step (tau_c / 30) are refused in single rate
  {
    SimConfig c1 = c;
    c1.multirate = false;
    c1.dt = c.contact.contact_time(0.5 * sp.m[0]) / 30.0;
    EXPECT_THROW(Simulation(sp, c1), common::InputError);
  }
  Simulation sim(sp, c);
  const double ea0 = cluster_energy(sim, 0, 100), eb0 = cluster_energy(sim, 100, 200);
  double ea = 0, eb = 0;
  const int n = 64 * 200;
  for (int k = 0; k < n; ++k) {
    sim.step();
    if (sim.at_gravity_boundary()) {
      ea = std::max(ea, std::fabs(cluster_energy(sim, 0, 100) / ea0 - 1));
      eb = std::max(eb, std::fabs(cluster_energy(sim, 100, 200) / eb0 - 1));
    }
  }
  const auto& lv = sim.levels();
  int la = -1, lb = -1;
  for (std::size_t i = 0; i < sp.size(); ++i) {
    int& l = sim.spheres().id[i] < 100 ? la : lb;
    if (l < 0) l = lv[i];
    ASSERT_EQ(lv[i], l) << "sphere id " << sim.spheres().id[i];
  }
  const double ev = static_cast<double>(sim.level_stats().evaluations) / (static_cast<double>(n) * sp.size());
  std::printf("two clusters: soft on level %d, stiff on level %d; |dE|/E soft %.2e, stiff %.2e; evaluations %.3f of "
              "single rate\n", la, lb, ea, eb, ev);
  EXPECT_EQ(la, 3);  // tau_b 10x longer: floor(log2(10))
  EXPECT_EQ(lb, 0);
  EXPECT_LT(ea, 5e-3);
  EXPECT_LT(eb, 5e-3);
  EXPECT_LT(ev, 0.6);  // 1/2 + 1/16 of the sphere-steps
  EXPECT_EQ(sim.bond_system()->broken_count(), 0u);
}

TEST(MultirateBonds, BreaksAtTheFirstStepOfItsLevelPastItsStrength) {
  const double m = sphere_mass(kS), L0 = 2 * kS * 1.001, kn = 3.7e8, A = M_PI * kS * kS;
  const double w = std::sqrt(kn * A / (0.5 * m)), v = 0.05, dc = 0.6 * v / w;
  Spheres sp;
  sp.push(0, Vec3(0, 0, 0), Vec3(-0.5 * v, 0, 0), Vec3::Zero(), m, kS);
  sp.push(1, Vec3(L0, 0, 0), Vec3(0.5 * v, 0, 0), Vec3::Zero(), m, kS);
  BondParams bp = bond_params(kn, kn);
  bp.sigma_c = kn * dc;
  const BondSet bonds = generate_bonds(sp, bp);
  const double h = shortest_bond_time(bonds, sp) / (37.3 * 5);  // level 2
  Simulation sim(sp, mr_config(kSoftContact, bonds, h, 37.3));
  ASSERT_EQ(sim.bond_levels()[0], 2);
  const double E0 = sim.diagnostics().total();
  auto stretch = [&] { return (sim.spheres().x[1] - sim.spheres().x[0]).norm() - L0; };
  double last_eval = 0;  // stretch at the bond's previous evaluation
  int k = 0;
  for (; k < 4000 && sim.bond_system()->broken_count() == 0; ++k) {
    if (k % 4 == 0) last_eval = stretch();
    sim.step();
  }
  ASSERT_EQ(sim.bond_system()->broken_count(), 1u);
  const double s = stretch();
  std::printf("level-2 bond broke after base step %d: stretch %.6e (at its previous evaluation %.6e, strength %.6e)\n",
              k, s, last_eval, dc);
  EXPECT_EQ(k % 4, 0);  // at one of its level's steps
  EXPECT_GT(s, dc);
  EXPECT_LE(last_eval, dc);
  const Diagnostics d = sim.diagnostics();
  EXPECT_NEAR(d.bond_released, 0.5 * kn * A * s * s, 1e-9 * kn * A * dc * dc);
  // Energy accounted: kinetic + released = E0 up to the break's own first-order error (the step
  // that breaks the bond closes without its force: |dE| / E0 ~ 0.48 w h_b here, h_b = 4 h), the
  // same as single-rate stepping at 4 h, whose break must come at the same step with the same
  // released energy (the same step grid after the start, where levels coarsen at their first
  // synchronisation: steps h, h, 2h before the steps of 4 h, an O(h^2) difference).
  const double budget = (d.total() + d.bond_released) / E0 - 1.0;
  SimConfig c1 = mr_config(kSoftContact, bonds, 4 * h, 37.3);
  c1.multirate = false;
  c1.gravity_every = 1;
  Simulation ref(sp, c1);
  int k1 = 0;
  for (; k1 < 1000 && ref.bond_system()->broken_count() == 0; ++k1) ref.step();
  const Diagnostics d1 = ref.diagnostics();
  std::printf("energy budget after the break %.3e (single rate at 4 h: %.3e, step %d)\n", budget,
              (d1.total() + d1.bond_released) / E0 - 1.0, k1);
  EXPECT_EQ(k, 4 * k1);
  EXPECT_NEAR(d.bond_released / d1.bond_released, 1.0, 1e-3);
  EXPECT_NEAR(budget, (d1.total() + d1.bond_released) / E0 - 1.0, 1e-4);
  EXPECT_LT(std::fabs(budget), 0.5 * w * 4 * h);
  for (int j = 0; j < 128; ++j) sim.step();
  EXPECT_EQ(sim.levels()[0], sim.levels()[1]);
  EXPECT_GT(sim.levels()[0], 2);  // the broken bond no longer holds them on level 2
}

TEST(MultirateBonds, RestartThroughCheckpointIsBitIdentical) {
  Spheres sp;
  SimConfig c = two_clusters(sp, 5e3);  // some soft bonds break
  sp.v[13] = Vec3(0.3, 0, 0);
  const int before = 2, after = 20;  // blocks of 64 base steps
  Simulation ref(sp, c);
  ref.run(64 * (before + after));
  Simulation first(sp, c);
  first.run(64 * before);
  const auto path = std::filesystem::temp_directory_path() / "ssdem_mr_bonds_ckpt.h5";
  const SimState st = first.state();
  write_checkpoint(path.string(), st, c.dt, st.gravity_block, common::Provenance{});
  SimState back = read_checkpoint(path.string());
  std::filesystem::remove(path);
  ASSERT_EQ(back.level, st.level);
  Simulation second(std::move(back), c);
  second.run(64 * after);
  std::printf("restart: %zu then %zu of %zu bonds broken, levels first %d last %d\n", first.bond_system()->broken_count(),
              ref.bond_system()->broken_count(), ref.bond_system()->bonds().size(), ref.levels().front(),
              ref.levels().back());
  EXPECT_GT(ref.bond_system()->broken_count(), first.bond_system()->broken_count());  // breaks after the restart too
  EXPECT_GT(first.bond_system()->broken_count(), 0u);
  EXPECT_EQ(ref.bond_system()->broken_count(), second.bond_system()->broken_count());
  EXPECT_EQ(ref.bond_system()->released_energy(), second.bond_system()->released_energy());
  EXPECT_EQ(ref.levels(), second.levels());
  EXPECT_EQ(differing(ref.spheres(), second.spheres()), 0u);
}

TEST(MultirateBonds, IndependentOfThreadCount) {
  // 2 197 bonded spheres (loops in parallel above 2 048) in two bodies on levels 3 and 0, the
  // soft one hit by a sphere at 5 m/s.
  Spheres sp;
  add_cube(sp, 13, 2 * kS * 1.002, 1e-3, Vec3::Zero(), 0);
  for (std::size_t i = 0; i < sp.size(); ++i)  // split at x = 6.5: two bodies 1 m apart
    if (sp.x[i].x() > 6.5) sp.x[i].x() += 1.0;
  BondSet bonds = generate_bonds(sp, bond_params(1e7, 0.5e7, 1e4));
  for (std::size_t k = 0; k < bonds.size(); ++k)  // the second body's bonds 100x stiffer: levels 0 and 3
    if (sp.x[bonds.id_a[k]].x() > 6.5) {
      bonds.kn[k] *= 100;
      bonds.ks[k] *= 100;
    }
  sp.push(9999, Vec3(-2 * kS - 0.001, 6 * 2 * kS * 1.002, 6 * 2 * kS), Vec3(5.0, 0, 0), Vec3::Zero(), sphere_mass(kS), kS);
  const double kc = 1e7 * M_PI * kS * kS;
  ContactParams p;
  p.kn = kc;
  const double dt = std::min(p.contact_time(0.5 * sp.m[0]), shortest_bond_time(bonds, sp)) / 30.0;
  SimConfig c = mr_config(kc, bonds, dt, 30.0);
  Spheres out[2];
  std::size_t broken[2];
  std::vector<std::uint8_t> levels[2];
  const int threads[2] = {1, 2};
  for (int r = 0; r < 2; ++r) {
    omp_set_num_threads(threads[r]);
    Simulation sim(sp, c);
    sim.run(64 * 4);
    out[r] = sim.spheres();
    broken[r] = sim.bond_system()->broken_count();
    levels[r] = sim.levels();
  }
  omp_set_num_threads(2);
  std::printf("%zu bonds broken; first sphere on level %d, last bonded on level %d\n", broken[0], levels[0][0],
              levels[0][sp.size() - 2]);
  EXPECT_GT(broken[0], 0u);
  EXPECT_EQ(levels[0][sp.size() - 2], 0);  // the stiff half
  EXPECT_EQ(levels[0][0], 3);              // the soft half (its far corner)
  EXPECT_EQ(levels[0], levels[1]);
  EXPECT_EQ(broken[0], broken[1]);
  EXPECT_EQ(differing(out[0], out[1]), 0u);
}
