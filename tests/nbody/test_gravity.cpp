/// @file test_gravity.cpp
/// Verification of self-gravity: spline kernel, octree vs direct summation (uniform sphere,
/// clustered Plummer, coincident points), two-body orbits (energy error bounded and second order),
/// Plummer sphere energy conservation, multiple time-stepping error, momentum and angular momentum
/// drift with the tree (force-error level) against direct summation (round-off).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>

#include "kepler_pair.hpp"
#include "common/rng.hpp"
#include "ssdem/generators.hpp"
#include "ssdem/gravity.hpp"
#include "ssdem/simulation.hpp"

using namespace ssdem;

TEST(GravityKernel, SplineForceIsMinusPotentialGradientAndContinuous) {
  const double h = 1.0;
  for (double r = 0.05; r < 1.3; r += 0.01) {
    double p1, p2, p0;
    const double e = 1e-6;
    spline_force_factor(r - e, h, p1);
    spline_force_factor(r + e, h, p2);
    const double f = spline_force_factor(r, h, p0);
    // a_i = G m f (x_j - x_i), phi = -G m W  =>  f r = -dW/dr
    const double dW = (p2 - p1) / (2 * e);
    EXPECT_NEAR(f * r, -dW, 1e-6) << r;
  }
  double pa, pb;
  const double fa = spline_force_factor(0.5 - 1e-12, h, pa), fb = spline_force_factor(0.5 + 1e-12, h, pb);
  EXPECT_NEAR(fa, fb, 1e-9);
  EXPECT_NEAR(pa, pb, 1e-9);
  double pn;
  EXPECT_NEAR(spline_force_factor(1.0 - 1e-12, h, pn), 1.0, 1e-9);
  EXPECT_NEAR(pn, 1.0, 1e-9);
  double p00;
  EXPECT_NEAR(spline_force_factor(0.0, h, p00), 32.0 / 3.0, 1e-12);  // finite at r = 0
  EXPECT_NEAR(p00, 2.8, 1e-12);
}

namespace {
double rms_rel_error(const Spheres& sp, double theta, double* max_err = nullptr) {
  std::vector<Vec3> ad, at;
  direct_gravity(sp, 1.0, ad);
  GravityParams gp;
  gp.G = 1.0;
  gp.theta = theta;
  TreeGravity tree(gp);
  tree.compute(sp, at);
  double s2 = 0, mx = 0;
  for (std::size_t i = 0; i < sp.size(); ++i) {
    const double e = (at[i] - ad[i]).norm() / ad[i].norm();
    s2 += e * e;
    mx = std::max(mx, e);
  }
  if (max_err) *max_err = mx;
  return std::sqrt(s2 / sp.size());
}
Spheres uniform_ball(std::size_t n, double R, double s) {
  Spheres sp;
  for (std::size_t i = 0; i < n; ++i) {
    common::KeyedRng rng(5, i);
    Vec3 p;
    do p = Vec3(2 * rng.uniform() - 1, 2 * rng.uniform() - 1, 2 * rng.uniform() - 1);
    while (p.norm() > 1);
    sp.push(i, R * p, Vec3::Zero(), Vec3::Zero(), 1.0 / n, s);
  }
  return sp;
}
}  // namespace

TEST(GravityTree, RmsForceErrorVersusOpeningAngle) {
  const Spheres uni = uniform_ball(6000, 1.0, 1e-3);
  const Spheres clu = plummer(6000, 1.0, 0.05, 1.0, 1e-4, 9);
  std::printf("theta   rms(uniform)  max(uniform)  rms(plummer)  max(plummer)\n");
  double prev_u = 0;
  for (double th : {0.2, 0.3, 0.35, 0.4, 0.5, 0.7}) {
    double mu, mc;
    const double eu = rms_rel_error(uni, th, &mu), ec = rms_rel_error(clu, th, &mc);
    std::printf("%.2f   %.3e     %.3e     %.3e     %.3e\n", th, eu, mu, ec, mc);
    if (th == GravityParams{}.theta) {
      EXPECT_LT(eu, 1e-3);
      EXPECT_LT(ec, 1e-3);
    }
    if (prev_u > 0) {
      EXPECT_GT(eu, prev_u);
    }
    prev_u = eu;
  }
}

TEST(GravityTree, CoincidentAndCollapsedPointsStaySane) {
  // 3000 spheres within 1e-9 of one point (and 500 exactly coincident) plus a halo.
  Spheres sp;
  for (std::size_t i = 0; i < 3500; ++i) {
    common::KeyedRng rng(2, i);
    const Vec3 p = i < 500 ? Vec3(0.1, 0.1, 0.1)
                           : Vec3(0.1, 0.1, 0.1) + 1e-9 * Vec3(rng.uniform(), rng.uniform(), rng.uniform());
    sp.push(i, p, Vec3::Zero(), Vec3::Zero(), 1e-3, 1e-3);
  }
  const Spheres halo = uniform_ball(1000, 1.0, 1e-3);
  append_body(sp, halo, Vec3::Zero(), Vec3::Zero());
  GravityParams gp;
  gp.G = 1.0;
  TreeGravity tree(gp);
  std::vector<Vec3> at, ad;
  tree.compute(sp, at);
  direct_gravity(sp, 1.0, ad);
  EXPECT_LE(tree.stats().depth, static_cast<std::size_t>(gp.max_depth));
  double s2 = 0;
  for (std::size_t i = 0; i < sp.size(); ++i) {
    ASSERT_TRUE(at[i].allFinite());
    const double e = (at[i] - ad[i]).norm() / std::max(ad[i].norm(), 1e-30);
    s2 += e * e;
  }
  const double rms = std::sqrt(s2 / sp.size());
  std::printf("collapsed cluster: rms rel error %.2e, depth %zu, nodes %zu\n", rms,
              tree.stats().depth, tree.stats().nodes);
  EXPECT_LT(rms, 1e-3);
}

namespace {
// Two-body orbit with G = M = 1 (masses 0.5 + 0.5), semi-major axis 1, eccentricity e, started
// at apocentre. Returns max |dE/E| over `orbits` orbits and the max over the last orbit.
std::pair<double, double> kepler(double e, double steps_per_orbit, int orbits) {
  const double a = 1.0, P = 2 * M_PI;
  const double ra = a * (1 + e), va = std::sqrt((1 - e) / (1 + e));  // relative speed at apo
  Spheres sp;
  sp.push(0, Vec3(-0.5 * ra, 0, 0), Vec3(0, -0.5 * va, 0), Vec3::Zero(), 0.5, 1e-6);
  sp.push(1, Vec3(0.5 * ra, 0, 0), Vec3(0, 0.5 * va, 0), Vec3::Zero(), 0.5, 1e-6);
  SimConfig c;
  c.self_gravity = true;
  c.direct_gravity = true;
  c.gravity.G = 1.0;
  c.dt = P / steps_per_orbit;
  Simulation sim(sp, c);
  const double E0 = sim.diagnostics().total();
  const long n = static_cast<long>(steps_per_orbit) * orbits;
  double mx = 0, last = 0;
  for (long k = 1; k <= n; ++k) {
    sim.step();
    const double err = std::fabs(sim.diagnostics().total() / E0 - 1);
    mx = std::max(mx, err);
    if (k > n - static_cast<long>(steps_per_orbit)) last = std::max(last, err);
  }
  return {mx, last};
}
}  // namespace

TEST(GravityOrbit, CircularAndEccentricEnergyErrorBoundedAndSecondOrder) {
  for (double e : {0.0, 0.5}) {
    const auto [m1, l1] = kepler(e, 200, 20);
    const auto [m2, l2] = kepler(e, 400, 20);
    std::printf("e = %.1f: max|dE/E| = %.3e (P/200), %.3e (P/400), ratio %.2f; last orbit %.3e\n",
                e, m1, m2, m1 / m2, l2);
    // e = 0.5: second order (ratio 4). e = 0: the O(h^2) term of the KDK energy error is
    // constant along a circular orbit and cancels against E0, leaving O(h^4) (ratio 16),
    // consistent with ssdem.md §3.5 (3.9e-6 at P/100, 3.9e-10 at P/1000).
    if (e > 0)
      EXPECT_NEAR(m1 / m2, 4.0, 0.4);
    else
      EXPECT_NEAR(m1 / m2, 16.0, 1.6);
    EXPECT_LT(l2, 1.05 * m2);          // no secular drift: last orbit as large as any
    EXPECT_GT(l2, 0.8 * m2);
  }
  // ssdem.md §3.5: e = 0 at P/100: 3.9e-6 (20-line KDK script)
  const auto [m100, l100] = kepler(0.0, 100, 20);
  EXPECT_NEAR(m100, 3.9e-6, 0.3e-6);
}

TEST(GravityPlummer, EnergyConservedOverCrossingTimes) {
  // Henon units: G = M = 1, a = 3 pi / 16 (E = -1/4); crossing time ~ 2 sqrt(2) ~ 2.8.
  const double a = 3 * M_PI / 16;
  Spheres sp = plummer(1000, 1.0, a, 1.0, 0.01, 4);
  SimConfig c;
  c.self_gravity = true;
  c.gravity.G = 1.0;
  c.gravity.theta = 0.5;
  c.dt = 1.0 / 256;
  Simulation sim(sp, c);
  const Diagnostics d0 = sim.diagnostics();
  const double vir0 = 2 * d0.kinetic / std::fabs(d0.potential_self);
  const int n = 3 * 256;  // 3 time units ~ one crossing time
  for (int k = 0; k < n; ++k) sim.step();
  const Diagnostics d1 = sim.diagnostics();
  const double dE = std::fabs(d1.total() / d0.total() - 1);
  const double vir1 = 2 * d1.kinetic / std::fabs(d1.potential_self);
  std::printf("Plummer N=1000, theta 0.5: E0 = %.5f, |dE/E| = %.2e after %d steps, virial %.3f -> %.3f\n",
              d0.total(), dE, n, vir0, vir1);
  EXPECT_NEAR(d0.total(), -0.25, 0.02);
  EXPECT_LT(dE, 2e-4);
  EXPECT_NEAR(vir1, 1.0, 0.08);
  // Barnes-Hut forces are not pairwise antisymmetric: momentum is not conserved to round-off
  // with the tree (it is with direct summation, see test_nbody_conservation). Bound the drift.
  double pscale = 0;
  for (std::size_t i = 0; i < sp.size(); ++i) pscale += sp.m[i] * sp.v[i].norm();
  std::printf("tree momentum drift |P|/sum m|v| = %.2e\n", d1.momentum.norm() / pscale);
  EXPECT_LT(d1.momentum.norm() / pscale, 1e-4);
}

TEST(GravityMTS, RespaWithoutFastForcesEqualsKdkAtTheOuterStep) {
  // Impulse RESPA with gravity every k steps and no contact forces is exactly KDK with step k h
  // at block boundaries (up to round-off): a sharp check of the outer kicks.
  auto run = [](double steps_per_orbit, int k) {
    SimConfig c = kepler_config(steps_per_orbit);
    c.gravity_every = k;
    Simulation sim(kepler_pair(0.5), c);
    sim.run(static_cast<long>(steps_per_orbit) * 3);
    return sim.spheres();
  };
  const Spheres a = run(200, 1), b = run(800, 4);
  for (int i = 0; i < 2; ++i) {
    EXPECT_LT((a.x[i] - b.x[i]).norm(), 1e-11);
    EXPECT_LT((a.v[i] - b.v[i]).norm(), 1e-11);
  }
}

namespace {
struct MomentumDrift {
  double dP = 0, dL = 0, dL_rel = 0, dE = 0;
};
// Rotating Plummer sphere (Henon units, N = 2000, solid-body spin Omega = 0.4 added, net
// momentum removed), no contacts: max over `steps` KDK steps of |P - P0| / sum m|v|,
// |L - L0| / sum m |x||v| and |L - L0| / |L0| (L orbital + spin about the origin), and the
// final |dE/E|. theta <= 0: direct summation.
MomentumDrift isolated_momentum_drift(double theta, int steps) {
  const double a = 3 * M_PI / 16;
  Spheres sp = plummer(1000, 1.0, a, 1.0, 0.01, 11);
  Vec3 P = Vec3::Zero();
  for (std::size_t i = 0; i < sp.size(); ++i) {
    sp.v[i] += Vec3(0, 0, 0.4).cross(sp.x[i]);
    P += sp.m[i] * sp.v[i];
  }
  for (auto& v : sp.v) v -= P / total_mass(sp);
  SimConfig c;
  c.self_gravity = true;
  c.direct_gravity = theta <= 0;
  c.gravity.G = 1.0;
  if (theta > 0) c.gravity.theta = theta;
  c.dt = 1.0 / 128;
  Simulation sim(sp, c);
  auto momenta = [](const Spheres& s, Vec3& Pout, Vec3& L, double& pscale, double& lscale) {
    Pout.setZero();
    L.setZero();
    pscale = lscale = 0;
    for (std::size_t i = 0; i < s.size(); ++i) {
      Pout += s.m[i] * s.v[i];
      L += s.m[i] * s.x[i].cross(s.v[i]) + s.inertia(i) * s.w[i];
      pscale += s.m[i] * s.v[i].norm();
      lscale += s.m[i] * s.x[i].norm() * s.v[i].norm();
    }
  };
  Vec3 P0, L0;
  double ps, ls;
  momenta(sim.spheres(), P0, L0, ps, ls);
  const double E0 = sim.diagnostics().total();
  MomentumDrift out;
  for (int k = 0; k < steps; ++k) {
    sim.step();
    Vec3 P1, L1;
    double ps1, ls1;
    momenta(sim.spheres(), P1, L1, ps1, ls1);
    out.dP = std::max(out.dP, (P1 - P0).norm() / ps);
    out.dL = std::max(out.dL, (L1 - L0).norm() / ls);
    out.dL_rel = std::max(out.dL_rel, (L1 - L0).norm() / L0.norm());
  }
  out.dE = std::fabs(sim.diagnostics().total() / E0 - 1);
  return out;
}
}  // namespace

TEST(GravityMomentum, TreeConservesToForceErrorLevelDirectToRoundOff) {
  // Direct summation is pairwise antisymmetric: P and L conserved to round-off. Barnes-Hut
  // forces are not (a particle and a cell it sees as a multipole do not act back alike), so
  // with the tree P and L drift at the level of the force error: measured over 384 steps
  // (~one crossing time) at the default theta (0.25) and at 0.7 (printed; the bounds below hold
  // for both the former default 0.3 and 0.25); direct 8e-17 / 2e-15.
  const int steps = 384;
  const MomentumDrift direct = isolated_momentum_drift(0.0, steps);
  const MomentumDrift tree = isolated_momentum_drift(GravityParams{}.theta, steps);
  const MomentumDrift coarse = isolated_momentum_drift(0.7, steps);
  for (const auto& [name, d] : {std::pair<const char*, MomentumDrift>{"direct    ", direct},
                                {"tree dflt ", tree}, {"tree 0.7  ", coarse}}) {
    std::printf("%s max |dP|/sum m|v| = %.2e, |dL|/sum m|x||v| = %.2e, |dL|/|L0| = %.2e, "
                "|dE/E| = %.2e\n", name, d.dP, d.dL, d.dL_rel, d.dE);
  }
  EXPECT_LT(direct.dP, 1e-14);
  EXPECT_LT(direct.dL, 1e-13);
  EXPECT_LT(tree.dP, 4e-5);
  EXPECT_LT(tree.dL, 1.5e-5);
  EXPECT_LT(tree.dL_rel, 2.5e-5);
  EXPECT_GT(tree.dL, 1e4 * direct.dL);   // not round-off ...
  EXPECT_GT(coarse.dL, 4 * tree.dL);     // ... but the tree's force error
}
