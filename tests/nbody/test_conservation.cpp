/// @file test_conservation.cpp
/// Conservation (energy, linear and angular momentum) in a dense self-gravitating pile,
/// thread-count independence, bit-identical restart, history keyed by ids.
#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <cstdio>
#include <numeric>

#include "common/rng.hpp"
#include "ssdem/dt_rule.hpp"
#include "ssdem/generators.hpp"
#include "ssdem/simulation.hpp"

using namespace ssdem;

namespace {
// Dense FCC pile in G = 1 units: s = 0.1, rho = 1, R = 0.7 (~250 spheres, M ~ 1), random
// velocities of 0.3 v_esc so that contacts open and close all the time.
Spheres pile(double vfrac = 0.3, double R = 0.7, double squeeze = 0.0) {
  Spheres sp = lattice_pile(R, 0.1, 1.0, 0.0, 3);
  for (auto& x : sp.x) x *= 1.0 - squeeze;  // pre-compressed: every lattice contact overlaps
  const double M = total_mass(sp), vesc = std::sqrt(2 * M / R);
  for (std::size_t i = 0; i < sp.size(); ++i) {
    common::KeyedRng rng(17, sp.id[i]);
    sp.v[i] = vfrac * vesc * Vec3(rng.normal(), rng.normal(), rng.normal()) / std::sqrt(3.0);
    sp.w[i] = Vec3(rng.normal(), rng.normal(), rng.normal());
  }
  // remove net momentum
  Vec3 P = Vec3::Zero();
  for (std::size_t i = 0; i < sp.size(); ++i) P += sp.m[i] * sp.v[i];
  for (std::size_t i = 0; i < sp.size(); ++i) sp.v[i] -= P / M;
  return sp;
}
SimConfig pile_config(unsigned parts, bool tree, int every = 1) {
  const Spheres sp = pile();
  const double M = total_mass(sp), vesc = std::sqrt(2 * M / 0.7);
  const DtAdvice adv = choose_kn_dt(sp.m[0], 0.1, vesc, 1.0, 0.01, 30);
  SimConfig c;
  c.self_gravity = true;
  c.direct_gravity = !tree;
  c.gravity.G = 1.0;
  c.gravity_every = every;
  c.contacts = true;
  c.contact = gravel_preset(adv.kn);
  c.contact.parts = parts;
  c.dt = adv.dt;
  return c;
}
double rel(const Vec3& a, double scale) { return a.norm() / scale; }
}  // namespace

TEST(Conservation, UndampedFrictionlessPileEnergyAndMomenta1e4Steps) {
  // k_n from the static (self-weight) criterion rather than the impact one, so that gravity
  // keeps the lattice contacts closed: a dense pile with ~N contacts that persist and ring.
  Spheres sp = pile(0.002, 0.7, 0.0);
  SimConfig c = pile_config(0u, false);
  c.contact.kn /= 1000;
  c.dt *= std::sqrt(1000.0);
  Simulation sim(sp, c);
  const Diagnostics d0 = sim.diagnostics();
  double pscale = 0, lscale = 0;
  for (std::size_t i = 0; i < sp.size(); ++i) {
    pscale += sp.m[i] * sp.v[i].norm();
    lscale += sp.m[i] * sp.x[i].norm() * sp.v[i].norm() + sp.inertia(i) * sp.w[i].norm();
  }
  const double Escale = d0.kinetic + std::fabs(d0.potential_self);
  double maxdE = 0, maxP = 0, maxL = 0;
  std::size_t maxc = 0;
  for (int blk = 0; blk < 100; ++blk) {
    sim.run(100);
    const Diagnostics d = sim.diagnostics();
    maxdE = std::max(maxdE, std::fabs(d.total() - d0.total()) / Escale);
    maxP = std::max(maxP, rel(d.momentum - d0.momentum, pscale));
    maxL = std::max(maxL, rel(d.angular_momentum - d0.angular_momentum, lscale));
    maxc = std::max(maxc, d.contacts);
  }
  std::printf("pile N=%zu, 1e4 steps, dt = tau/30: max |dE|/(K+|W|) = %.2e, |dP|/sum m|v| = %.2e, "
              "|dL|/L_scale = %.2e, max contacts %zu\n",
              sp.size(), maxdE, maxP, maxL, maxc);
  EXPECT_GT(maxc, 4 * sp.size());  // a dense pile: ~ 2 x (contacts per sphere)/2 > 4 N
  EXPECT_LT(maxdE, 2e-3);
  EXPECT_LT(maxP, 1e-13);
  EXPECT_LT(maxL, 1e-13);
}

TEST(Conservation, FrictionalPileMomentaToRoundOffAndEnergyNeverCreated) {
  Spheres sp = pile();
  SimConfig c = pile_config(kPartDamping | kPartTangential | kPartRolling | kPartTwisting, false);
  Simulation sim(sp, c);
  const Diagnostics d0 = sim.diagnostics();
  double pscale = 0, lscale = 0;
  for (std::size_t i = 0; i < sp.size(); ++i) {
    pscale += sp.m[i] * sp.v[i].norm();
    lscale += sp.m[i] * sp.x[i].norm() * sp.v[i].norm() + sp.inertia(i) * sp.w[i].norm();
  }
  const double Escale = d0.kinetic + std::fabs(d0.potential_self);
  double Eprev = d0.total(), maxrise = 0, maxP = 0, maxL = 0;
  for (int blk = 0; blk < 40; ++blk) {
    sim.run(100);
    const Diagnostics d = sim.diagnostics();
    maxrise = std::max(maxrise, (d.total() - Eprev) / Escale);
    Eprev = std::min(Eprev, d.total());
    maxP = std::max(maxP, rel(d.momentum - d0.momentum, pscale));
    maxL = std::max(maxL, rel(d.angular_momentum - d0.angular_momentum, lscale));
  }
  std::printf("gravel pile: E %.4f -> %.4f, max energy rise %.2e, |dP| %.2e, |dL| %.2e\n",
              d0.total(), Eprev, maxrise, maxP, maxL);
  EXPECT_LT(Eprev, d0.total() - 0.05 * Escale);  // dissipates
  EXPECT_LT(maxrise, 1e-3);
  EXPECT_LT(maxP, 1e-13);
  EXPECT_LT(maxL, 1e-13);
}

TEST(Determinism, ResultsIndependentOfThreadCount) {
  // > 2048 spheres so that every loop really runs in parallel (smaller loops run serially)
  const Spheres sp = pile(0.3, 1.6);
  ASSERT_GT(sp.size(), 2048u);
  SimConfig c = pile_config(kPartDamping | kPartTangential | kPartRolling | kPartTwisting, true, 3);
  c.walls.push_back(Plane{Vec3(0, 0, -0.6), Vec3::UnitZ()});
  auto run = [&](int threads) {
    const int old = omp_get_max_threads();
    omp_set_num_threads(threads);
    Simulation sim(sp, c);
    sim.run(60);
    omp_set_num_threads(old);
    return sim.state();
  };
  const SimState a = run(1), b = run(2), d = run(3);
  for (std::size_t i = 0; i < sp.size(); ++i) {
    ASSERT_EQ(a.sp.x[i], b.sp.x[i]);
    ASSERT_EQ(a.sp.w[i], b.sp.w[i]);
    ASSERT_EQ(a.sp.x[i], d.sp.x[i]);
    ASSERT_EQ(a.a[i], d.a[i]);
  }
}

TEST(Restart, StateRoundTripIsBitIdentical) {
  const Spheres sp = pile();
  // gravity every 3 steps; stop at step 200 (mid-block) and restart
  SimConfig c = pile_config(kPartDamping | kPartTangential | kPartRolling | kPartTwisting, true, 3);
  c.walls.push_back(Plane{Vec3(0, 0, -0.6), Vec3::UnitZ()});
  Simulation ref(sp, c);
  ref.run(400);
  Simulation first(sp, c);
  first.run(200);
  SimState st = first.state();
  ASSERT_FALSE(st.history.empty());
  Simulation second(st, c);
  second.run(200);
  for (std::size_t i = 0; i < sp.size(); ++i) {
    ASSERT_EQ(ref.spheres().x[i], second.spheres().x[i]) << i;
    ASSERT_EQ(ref.spheres().v[i], second.spheres().v[i]) << i;
    ASSERT_EQ(ref.spheres().w[i], second.spheres().w[i]) << i;
  }
}

TEST(Restart, HistoryKeyedByIdsSurvivesReordering) {
  const Spheres sp = pile();
  SimConfig c = pile_config(kPartDamping | kPartTangential | kPartRolling | kPartTwisting, false);
  Simulation ref(sp, c);
  ref.run(300);
  Simulation first(sp, c);
  first.run(150);
  SimState st = first.state();
  // reverse the sphere order (indices change, ids do not)
  const std::size_t n = st.sp.size();
  SimState rv = st;
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t j = n - 1 - i;
    rv.sp.id[i] = st.sp.id[j];
    rv.sp.x[i] = st.sp.x[j];
    rv.sp.v[i] = st.sp.v[j];
    rv.sp.w[i] = st.sp.w[j];
    rv.sp.m[i] = st.sp.m[j];
    rv.sp.s[i] = st.sp.s[j];
    rv.a[i] = st.a[j];
    rv.alpha[i] = st.alpha[j];
    rv.ag[i] = st.ag[j];
    rv.a_prev[i] = st.a_prev[j];
    rv.alpha_prev[i] = st.alpha_prev[j];
  }
  Simulation second(rv, c);
  second.run(150);
  double mx = 0;
  for (std::size_t i = 0; i < n; ++i)
    mx = std::max(mx, (ref.spheres().x[n - 1 - i] - second.spheres().x[i]).norm());
  std::printf("reordered restart: max position difference %.2e (radius 0.1)\n", mx);
  EXPECT_LT(mx, 1e-9);
  // and without the history it would differ visibly
  SimState nohist = rv;
  nohist.history.clear();
  Simulation third(nohist, c);
  third.run(150);
  double mx3 = 0;
  for (std::size_t i = 0; i < n; ++i)
    mx3 = std::max(mx3, (ref.spheres().x[n - 1 - i] - third.spheres().x[i]).norm());
  EXPECT_GT(mx3, 100 * std::max(mx, 1e-14));
}

TEST(Gravity, MtsErrorInSelfGravitatingPileMeasured) {
  // gravity every k contact steps (RESPA) vs every step: energy and position differences.
  const Spheres sp = pile(0.1);
  auto run = [&](int k) {
    SimConfig c = pile_config(0u, true, k);
    Simulation sim(sp, c);
    const double E0 = sim.diagnostics().total();
    sim.run(960);
    const double E1 = sim.diagnostics().total();
    return std::make_pair(sim.spheres().x, std::fabs(E1 / E0 - 1));
  };
  const auto ref = run(1);
  std::printf("k   |dE/E| (960 steps)   rms |x - x_ref| / s\n");
  for (int k : {1, 4, 16}) {
    const auto r = run(k);
    double s2 = 0;
    for (std::size_t i = 0; i < sp.size(); ++i) s2 += (r.first[i] - ref.first[i]).squaredNorm();
    const double rms = std::sqrt(s2 / sp.size()) / 0.1;
    std::printf("%-3d %.2e             %.2e\n", k, r.second, rms);
    EXPECT_LT(r.second, 2e-3);
    if (k == 16) {
      EXPECT_LT(rms, 0.05);
    }
  }
}
