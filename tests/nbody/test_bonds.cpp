/// @file test_bonds.cpp
/// Verification of the parallel bonds (bonds.hpp, Potyondy & Cundall 2004): a free-free bonded
/// chain vibrates at the first Euler-Bernoulli frequency of its equivalent beam (E = k_n L0,
/// I = pi R_b^4/4, mass per length m/L0); a bond under tension breaks in the step its stress
/// passes sigma_c and its stored energy goes to the released account; an undamped bonded lattice
/// conserves energy (stated level) and momentum (round-off) over 10^4 steps; a bond 100x stiffer
/// than the step allows is refused naming bonds.kn; a bonded body hit at 5 km/s stays finite and
/// closes its energy budget with the released bond energy; a checkpoint restart is bit-identical.
#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

#include <hdf5.h>

#include "common/status.hpp"
#include "ssdem/dt_rule.hpp"
#include "ssdem/io.hpp"
#include "ssdem/simulation.hpp"

using namespace ssdem;

namespace {
constexpr double kS = 0.5, kRho = 2000.0;
double sphere_mass(double s) { return kRho * 4.0 / 3.0 * M_PI * s * s * s; }

SimConfig bonded_config(const Spheres& sp, const BondParams& bp, double steps_per_mode, double contact_kn) {
  SimConfig c;
  c.contacts = true;
  c.contact.parts = 0u;  // linear normal only, undamped
  c.contact.kn = contact_kn;
  c.bonds = generate_bonds(sp, bp);
  const double tau = std::min(shortest_bond_time(c.bonds, sp), c.contact.contact_time(0.5 * sp.m[0]));
  c.dt = tau / steps_per_mode;
  return c;
}
}  // namespace

TEST(Bonds, ChainVibratesAtTheEulerBernoulliFrequency) {
  const int N = 24;
  const double L0 = 2 * kS * 1.0002, m = sphere_mass(kS);
  BondParams bp;
  bp.kn = bp.ks = 1e8;
  bp.sigma_c = bp.tau_c = 1e300;
  Spheres sp;
  // first free-free mode: phi = cosh bx + cos bx - sg (sinh bx + sin bx), bL = 4.73004
  const double L = N * L0, bL = 4.730040745, b = bL / L;
  const double sg = (std::cosh(bL) - std::cos(bL)) / (std::sinh(bL) - std::sin(bL));
  const double V = 1e-3;
  for (int i = 0; i < N; ++i) {
    const double x = (i + 0.5) * L0;
    const double phi = std::cosh(b * x) + std::cos(b * x) - sg * (std::sinh(b * x) + std::sin(b * x));
    const double dphi = b * (std::sinh(b * x) - std::sin(b * x) - sg * (std::cosh(b * x) + std::cos(b * x)));
    sp.push(i, Vec3(x, 0, 0), Vec3(0, V * phi, 0), Vec3(0, 0, V * dphi), m, kS);
  }
  SimConfig c = bonded_config(sp, bp, 23.7, 1e8 * M_PI * kS * kS);
  ASSERT_EQ(c.bonds.size(), static_cast<std::size_t>(N - 1));
  const double E = bp.kn * L0, I = M_PI * std::pow(kS, 4) / 4, ml = m / L0;
  const double w1 = bL * bL * std::sqrt(E * I / (ml * std::pow(L, 4)));
  const double T1 = 2 * M_PI / w1;
  Simulation sim(sp, c);
  auto mid = [&] {
    double ym = 0.5 * (sim.spheres().x[N / 2 - 1].y() + sim.spheres().x[N / 2].y()), yc = 0;
    for (int i = 0; i < N; ++i) yc += sim.spheres().x[i].y() / N;
    return ym - yc;
  };
  double prev = mid(), t_first = -1, t_last = -1;
  int crossings = 0;
  const int steps = static_cast<int>(3.3 * T1 / c.dt);
  for (int k = 0; k < steps; ++k) {
    const double t0 = sim.time();
    sim.step();
    const double y = mid();
    if ((prev < 0) != (y < 0) && k > 0) {
      const double tc = t0 + c.dt * prev / (prev - y);
      if (t_first < 0) t_first = tc;
      t_last = tc;
      ++crossings;
    }
    prev = y;
  }
  ASSERT_GE(crossings, 5);
  const double T = 2 * (t_last - t_first) / (crossings - 1);
  std::printf("bonded chain N = %d: period %.5f s, Euler-Bernoulli %.5f s (rel %.2e), %d crossings\n", N, T,
              T1, T / T1 - 1, crossings);
  EXPECT_NEAR(T / T1, 1.0, 0.02);
}

TEST(Bonds, BreaksInTheStepItsTensileStrengthIsPassed) {
  const double m = sphere_mass(kS), L0 = 2 * kS * 1.001, kn = 3.7e8, A = M_PI * kS * kS;
  const double mu = 0.5 * m, w = std::sqrt(kn * A / mu), v = 0.05, amp = v / w;
  const double dc = 0.6 * amp;  // breaks on the way out, at 60 % of the undisturbed amplitude
  BondParams bp;
  bp.kn = kn;
  bp.ks = kn;
  bp.sigma_c = kn * dc;  // sigma = F_n / A = k_n (d - L0)
  bp.tau_c = 1e300;
  Spheres sp;
  sp.push(0, Vec3(0, 0, 0), Vec3(-0.5 * v, 0, 0), Vec3::Zero(), m, kS);
  sp.push(1, Vec3(L0, 0, 0), Vec3(0.5 * v, 0, 0), Vec3::Zero(), m, kS);
  SimConfig c = bonded_config(sp, bp, 37.3, 1e3);
  Simulation sim(sp, c);
  double stretch_prev = 0;
  int k = 0;
  for (; k < 1000 && sim.bond_system()->broken_count() == 0; ++k) {
    stretch_prev = (sim.spheres().x[1] - sim.spheres().x[0]).norm() - L0;
    sim.step();
  }
  ASSERT_EQ(sim.bond_system()->broken_count(), 1u);
  const double stretch = (sim.spheres().x[1] - sim.spheres().x[0]).norm() - L0;
  std::printf("bond break at step %d: stretch %.6e m (previous step %.6e, strength %.6e)\n", k, stretch,
              stretch_prev, dc);
  EXPECT_GT(stretch, dc);
  EXPECT_LE(stretch_prev, dc);
  EXPECT_NEAR(sim.bond_system()->released_energy(), 0.5 * kn * A * stretch * stretch, 1e-9 * kn * A * dc * dc);
  // broken is irreversible: the spheres fly apart with no force
  const Vec3 v0 = sim.spheres().v[1];
  for (int j = 0; j < 200; ++j) sim.step();
  EXPECT_EQ(sim.bond_system()->broken_count(), 1u);
  EXPECT_EQ(sim.spheres().v[1], v0);
  const Diagnostics d = sim.diagnostics();
  EXPECT_EQ(d.bond_elastic, 0.0);
  EXPECT_EQ(d.bonds_broken, 1u);
}

namespace {
Spheres cube(int n, double spacing, double vjit) {
  Spheres sp;
  std::uint64_t id = 0;
  const double m = sphere_mass(kS);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k, ++id) {
        const double a = std::sin(12.9898 * id + 1.0), b = std::sin(78.233 * id + 2.0), q = std::sin(37.719 * id + 3.0);
        sp.push(id, spacing * Vec3(i, j, k), vjit * Vec3(a, b, q), vjit / kS * Vec3(b, q, a), m, kS);
      }
  return sp;
}
}  // namespace

TEST(Bonds, UndampedLatticeConservesEnergyAndMomentum) {
  Spheres sp = cube(3, 2 * kS * 1.002, 1e-3);
  BondParams bp;
  bp.kn = 2e8;
  bp.ks = 0.8e8;
  bp.sigma_c = bp.tau_c = 1e300;
  bp.radius_ratio = 0.7;
  SimConfig c = bonded_config(sp, bp, 31.7, 1e8);
  ASSERT_EQ(c.bonds.size(), 54u);  // 3 x 3 x 2 per axis
  Simulation sim(sp, c);
  Diagnostics d0 = sim.diagnostics();
  double emax = 0, pmax = 0, lmax = 0, pscale = 0;
  for (std::size_t i = 0; i < sp.size(); ++i) pscale += sp.m[i] * sp.v[i].norm();
  for (int k = 0; k < 10000; ++k) {
    sim.step();
    if (k % 50 == 0 || k == 9999) {
      const Diagnostics d = sim.diagnostics();
      emax = std::max(emax, std::fabs(d.total() - d0.total()) / d0.total());
      pmax = std::max(pmax, (d.momentum - d0.momentum).norm() / pscale);
      lmax = std::max(lmax, (d.angular_momentum - d0.angular_momentum).norm() / (pscale * 3 * kS));
    }
  }
  const Diagnostics d = sim.diagnostics();
  std::printf("bonded lattice, 10^4 steps at 31.7 per shortest mode: |dE|/E <= %.2e (bond share of E %.2f), "
              "|dP| %.1e, |dL| %.1e\n", emax, d.bond_elastic / d.total(), pmax, lmax);
  EXPECT_GT(d.bond_elastic, 0.1 * d.total());  // the bonds really are loaded
  EXPECT_LT(emax, 5e-3);
  EXPECT_LT(pmax, 1e-12);
  EXPECT_LT(lmax, 1e-10);
}

TEST(Bonds, TooStiffForTheStepIsRefusedNamingTheKeys) {
  Spheres sp = cube(2, 2 * kS, 0.0);
  BondParams bp;
  bp.kn = bp.ks = 1e8;
  bp.sigma_c = bp.tau_c = 1e300;
  SimConfig c = bonded_config(sp, bp, 10.0, 1e3);  // exactly 10 steps per shortest bond mode
  EXPECT_NO_THROW(Simulation(sp, c));
  c.bonds = generate_bonds(sp, [&] {
    BondParams b = bp;
    b.kn = b.ks = 100 * bp.kn;
    return b;
  }());
  try {
    Simulation s(sp, c);
    FAIL() << "accepted";
  } catch (const common::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("bonds.kn"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("time.min_steps_per_contact"), std::string::npos) << e.what();
  }
}

TEST(Bonds, BondedBodyHitAt5kmsStaysFiniteAndAccountsTheReleasedEnergy) {
  Spheres sp = cube(4, 2 * kS, 0.0);
  const double m = sphere_mass(kS);
  sp.push(1000, Vec3(1.5 * 2 * kS + 0.1, 1.5 * 2 * kS + 0.2, -3 * kS), Vec3(0, 0, 5000.0), Vec3::Zero(), m, kS);
  BondParams bp;
  bp.kn = bp.ks = 1e9;
  bp.sigma_c = bp.tau_c = 1e6;
  const DtAdvice a = choose_kn_dt(m, kS, 5000.0, 1.0, 0.1, 30.0);
  SimConfig c;
  c.contacts = true;
  c.contact.parts = 0u;  // no dissipation: the budget must close
  c.contact.kn = a.kn;
  c.dt = a.dt;
  c.bonds = generate_bonds(sp, bp);
  ASSERT_EQ(c.bonds.size(), 144u);
  Simulation sim(sp, c);
  const double E0 = sim.diagnostics().total();
  for (int k = 0; k < 4000; ++k) sim.step();  // the impactor crosses the 4 m body
  const Diagnostics d = sim.diagnostics();
  for (std::size_t i = 0; i < sim.spheres().size(); ++i) ASSERT_TRUE(sim.spheres().v[i].allFinite());
  const double budget = (d.total() + d.bond_released - E0) / E0;
  std::printf("5 km/s on a bonded body: %zu of %zu bonds broken, released %.3e J (of E0 %.3e J), "
              "budget error %.1e\n", d.bonds_broken, d.bonds, d.bond_released, E0, budget);
  EXPECT_GT(d.bonds_broken, 0u);
  EXPECT_GT(d.bond_released, 0.0);
  EXPECT_LT(std::fabs(budget), 1e-2);
}

TEST(Bonds, CheckpointRestartIsBitIdentical) {
  Spheres sp = cube(3, 2 * kS * 1.002, 2e-3);
  BondParams bp;
  bp.kn = 2e8;
  bp.ks = 1e8;
  bp.sigma_c = 5e4;  // some bonds break during the run
  bp.tau_c = 1e300;
  SimConfig c = bonded_config(sp, bp, 30.0, 1e8);
  sp.v[13] = Vec3(0.3, 0, 0);
  Simulation ref(sp, c);
  ref.run(600);
  Simulation first(sp, c);
  first.run(300);
  const std::string path = (std::filesystem::temp_directory_path() / "ssdem_bonds_ckpt.h5").string();
  write_checkpoint(path, first.state(), c.dt, 1, common::Provenance{});
  SimState st = read_checkpoint(path);
  std::filesystem::remove(path);
  ASSERT_EQ(st.bonds.size(), c.bonds.size());
  Simulation second(st, c);
  second.run(300);
  EXPECT_GT(ref.bond_system()->broken_count(), 0u);
  EXPECT_EQ(ref.bond_system()->broken_count(), second.bond_system()->broken_count());
  EXPECT_EQ(ref.bond_system()->released_energy(), second.bond_system()->released_energy());
  for (std::size_t i = 0; i < sp.size(); ++i) {
    ASSERT_EQ(ref.spheres().x[i], second.spheres().x[i]) << i;
    ASSERT_EQ(ref.spheres().w[i], second.spheres().w[i]) << i;
  }
}

TEST(Bonds, CheckpointKeepsEachBondsReleasedEnergyAndAnOlderFilesTotal) {
  // each broken bond's released energy in /ssdem_state/bonds/released; a checkpoint without that
  // dataset (written before 2026-12-05) keeps its total as released_base, which a later
  // checkpoint carries on (attribute released_base)
  Spheres sp = cube(3, 2 * kS * 1.002, 2e-3);
  BondParams bp;
  bp.kn = 2e8;
  bp.ks = 1e8;
  bp.sigma_c = 5e4;
  bp.tau_c = 1e300;
  SimConfig c = bonded_config(sp, bp, 30.0, 1e8);
  sp.v[13] = Vec3(0.3, 0, 0);
  Simulation ref(sp, c);
  ref.run(600);
  const SimState s0 = ref.state();
  const double total = ref.bond_system()->released_energy();
  ASSERT_GT(s0.bonds.broken_count(), 0u);
  ASSERT_GT(total, 0.0);
  std::size_t with_energy = 0;
  for (std::size_t k = 0; k < s0.bonds.size(); ++k) {
    EXPECT_EQ(s0.bonds.released[k] > 0.0, s0.bonds.broken[k] != 0) << k;  // broken bonds only
    with_energy += s0.bonds.released[k] > 0.0;
  }
  const std::string path = (std::filesystem::temp_directory_path() / "ssdem_bonds_released.h5").string();
  write_checkpoint(path, s0, c.dt, 1, common::Provenance{});
  SimState st = read_checkpoint(path);
  EXPECT_EQ(st.bonds.released, s0.bonds.released);
  EXPECT_EQ(st.bonds.released_base, 0.0);
  EXPECT_EQ(st.bonds.released_total(), total);
  {  // an older file: no per-bond dataset
    const hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    ASSERT_GE(f, 0);
    ASSERT_GE(H5Ldelete(f, "/ssdem_state/bonds/released", H5P_DEFAULT), 0);
    ASSERT_GE(H5Adelete_by_name(f, "/ssdem_state/bonds", "released_base", H5P_DEFAULT), 0);
    H5Fclose(f);
  }
  st = read_checkpoint(path);
  EXPECT_EQ(st.bonds.released_base, total);
  for (double e : st.bonds.released) EXPECT_EQ(e, 0.0);
  EXPECT_EQ(st.bonds.released_total(), total);
  Simulation cont(st, c);
  EXPECT_EQ(cont.bond_system()->released_energy(), total);
  write_checkpoint(path, cont.state(), c.dt, 1, common::Provenance{});
  st = read_checkpoint(path);
  std::filesystem::remove(path);
  EXPECT_EQ(st.bonds.released_base, total);
  EXPECT_EQ(st.bonds.released_total(), total);
  std::printf("%zu broken bonds hold %.6e J; an older checkpoint's total carried as the base: %.6e J\n", with_energy,
              total, st.bonds.released_base);
}

TEST(Bonds, ParallelEvaluationEqualsTheSerialLoopBitForBit) {
  // 13^3 bonded spheres (6 084 bonds: the parallel path from 2 048 on) hit by a sphere that
  // breaks bonds: 1, 2 and 3 threads give the same bits (1 thread: the serial loop; more: every
  // bond on its own, then each sphere adds its bonds' terms in bond order), and so does a run
  // that changes its thread count while bonds break (2, then 1, then 2 threads)
  Spheres sp = cube(13, 2 * kS * 1.002, 2e-3);
  sp.push(99999, Vec3(-2 * kS - 0.01, 6 * 2 * kS, 6 * 2 * kS), Vec3(8.0, 0, 0), Vec3::Zero(), sphere_mass(kS), kS);
  BondParams bp;
  bp.kn = 2e8;
  bp.ks = 1e8;
  bp.sigma_c = bp.tau_c = 2e5;
  const SimConfig c = bonded_config(sp, bp, 30.0, 1e8);
  ASSERT_GE(c.bonds.size(), 2048u);
  Spheres out[4];
  std::vector<std::uint8_t> broken[4];
  double released[4];
  for (int t = 0; t < 4; ++t) {
    omp_set_num_threads(t < 3 ? t + 1 : 2);
    Simulation sim(sp, c);
    if (t < 3) {
      sim.run(400);
    } else {  // the impact's breaks on one thread between parallel stretches
      sim.run(100);
      omp_set_num_threads(1);
      sim.run(150);
      omp_set_num_threads(2);
      sim.run(150);
    }
    out[t] = sim.spheres();
    broken[t] = sim.bond_system()->bonds().broken;
    released[t] = sim.bond_system()->released_energy();
  }
  omp_set_num_threads(2);
  std::size_t nb = 0;
  for (std::uint8_t b : broken[0]) nb += b;
  std::size_t mid = 0;  // broken in the one-thread stretch of the 2-1-2 run (steps 101-250)
  {
    omp_set_num_threads(1);
    Simulation sim(sp, c);
    sim.run(100);
    mid = sim.bond_system()->broken_count();
    sim.run(150);
    mid = sim.bond_system()->broken_count() - mid;
    omp_set_num_threads(2);
  }
  std::printf("%zu bonds, %zu broken by the impact (%zu in steps 101-250), released %.6e J\n", c.bonds.size(), nb,
              mid, released[0]);
  EXPECT_GT(mid, 0u);
  EXPECT_GT(nb, 0u);
  for (int t = 1; t < 4; ++t) {
    const char* run = t == 1 ? "2 threads" : t == 2 ? "3 threads" : "2, 1, 2 threads";
    EXPECT_EQ(broken[t], broken[0]) << run;
    EXPECT_EQ(released[t], released[0]) << run;
    std::size_t differing = 0;
    for (std::size_t i = 0; i < sp.size(); ++i)
      differing += out[t].x[i] != out[0].x[i] || out[t].v[i] != out[0].v[i] || out[t].w[i] != out[0].w[i];
    EXPECT_EQ(differing, 0u) << run;
  }
}
