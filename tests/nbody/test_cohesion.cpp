/// @file test_cohesion.cpp
/// Verification of the cohesion part (contact/cohesion.hpp): the kernel's force against
/// F_c - k_n x with F_c = sigma_c pi (beta Rbar)^2; a dynamic pull-off (two spheres at their
/// equilibrium overlap separate iff mu v^2/2 > F_c^2/(2 k_n), with the exit speed
/// sqrt(v^2 - v_c^2) from energy conservation including the cohesive potential -F_c x); a
/// cohesive sphere under a plate hangs below g_c = F_c / m and falls above it.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "ssdem/contact_law.hpp"
#include "ssdem/simulation.hpp"

using namespace ssdem;

namespace {
ContactParams cohesive(double kn, double sigma, double beta) {
  ContactParams p;
  p.parts = kPartCohesion;
  p.kn = kn;
  p.sigma_c = sigma;
  p.beta = beta;
  return p;
}
}  // namespace

TEST(Cohesion, KernelForceIsFcMinusSpring) {
  const double s1 = 0.3, s2 = 0.71, kn = 3.3e5, sigma = 250.0, beta = 0.43;
  const ContactParams p = cohesive(kn, sigma, beta);
  const ContactCoeffs c(p);
  const double Rbar = s1 * s2 / (s1 + s2), Fc = sigma * M_PI * beta * beta * Rbar * Rbar;
  ContactHistory hist(p.parts);
  hist.assign(1);
  const Vec3 dir = Vec3(0.2, -0.7, 0.4).normalized();
  for (double x : {1e-9, 1e-5, 1e-4, 3e-3}) {
    bool act = true;
    PairResult r;
    const Vec3 z = Vec3::Zero();
    ASSERT_TRUE((contact_pair<kPartCohesion, false>(c, (s1 + s2 - x) * dir, s1, s2, 1.0, z, z, z, z, z,
                                                    z, z, z, 1e-3, act, hist.row(0), r)));
    // force on p along n (towards n): F_c - k_n x (tension when positive)
    // (x itself is known to ~1 ulp of the distance: kn * 1e-15 m)
    EXPECT_NEAR(r.F.dot(dir), Fc - kn * x, 1e-12 * (Fc + kn * x) + kn * 1e-15) << x;
    EXPECT_NEAR((r.F - r.F.dot(dir) * dir).norm(), 0.0, 1e-12 * Fc);
  }
  // the largest tensile force before separation (x -> 0+) is F_c: the pull-off force
  bool act = true;
  PairResult r;
  const Vec3 z = Vec3::Zero();
  EXPECT_FALSE((contact_pair<kPartCohesion, false>(c, (s1 + s2 + 1e-12) * dir, s1, s2, 1.0, z, z, z, z,
                                                   z, z, z, z, 1e-3, act, hist.row(0), r)));
  // walls: Rbar = s; off with walls = false
  ContactParams pw = p;
  pw.cohesion_walls = false;
  const ContactCoeffs cw(pw);
  EXPECT_DOUBLE_EQ(Cohesion::force<true>(c, s1), sigma * M_PI * beta * beta * s1 * s1);
  EXPECT_EQ(Cohesion::force<true>(cw, s1), 0.0);
}

namespace {
// Two spheres at rest relative to each other at the equilibrium overlap x_eq = F_c / k_n are
// given relative speed f v_c apart, v_c = F_c / sqrt(mu k_n). Returns the relative speed at the
// end (0 if they stayed together) and the largest gap seen.
struct PullOff {
  double v_end = 0, max_gap = -1, e_drift = 0;
  bool separated = false;
};
PullOff pull_off(double f) {
  const double s1 = 0.5, s2 = 0.8, rho = 2000, kn = 2e5, sigma = 400.0, beta = 0.5;
  const double m1 = rho * 4.0 / 3.0 * M_PI * std::pow(s1, 3), m2 = rho * 4.0 / 3.0 * M_PI * std::pow(s2, 3);
  const double mu = m1 * m2 / (m1 + m2), Rbar = s1 * s2 / (s1 + s2);
  const double Fc = sigma * M_PI * beta * beta * Rbar * Rbar, xeq = Fc / kn;
  const double vc = Fc / std::sqrt(mu * kn), v = f * vc;
  Spheres sp;
  sp.push(0, Vec3(0, 0, 0), Vec3(-v * m2 / (m1 + m2), 0, 0), Vec3::Zero(), m1, s1);
  sp.push(1, Vec3(s1 + s2 - xeq, 0, 0), Vec3(v * m1 / (m1 + m2), 0, 0), Vec3::Zero(), m2, s2);
  SimConfig c;
  c.contacts = true;
  c.contact = cohesive(kn, sigma, beta);
  // oscillation period / 837.3: the jump of F_c at x = 0 makes the energy error at separation first
  // order in h (~0.7 % of the kinetic energy at 83.7 steps per period, measured)
  c.dt = 2 * M_PI * std::sqrt(mu / kn) / 837.3;
  Simulation sim(sp, c);
  const double E0 = sim.diagnostics().total();
  PullOff r;
  for (int k = 0; k < 3000; ++k) {
    sim.step();
    const double gap = (sim.spheres().x[1] - sim.spheres().x[0]).norm() - s1 - s2;
    r.max_gap = std::max(r.max_gap, gap);
    r.e_drift = std::max(r.e_drift, std::fabs(sim.diagnostics().total() - E0) / (0.5 * mu * v * v));
  }
  r.separated = r.max_gap > 0.0;
  r.v_end = (sim.spheres().v[1] - sim.spheres().v[0]).norm() / vc;  // in units of v_c
  return r;
}
}  // namespace

TEST(Cohesion, PullOffFromEquilibriumNeedsTheCohesiveWork) {
  const PullOff below = pull_off(0.97), above = pull_off(1.03);
  std::printf("pull-off: f = 0.97: max gap %.2e m, energy drift %.1e; f = 1.03: separated, exit speed "
              "%.4f v_c (energy: %.4f), drift %.1e\n",
              below.max_gap, below.e_drift, above.v_end, std::sqrt(1.03 * 1.03 - 1.0), above.e_drift);
  EXPECT_FALSE(below.separated);
  EXPECT_TRUE(above.separated);
  EXPECT_NEAR(above.v_end / std::sqrt(1.03 * 1.03 - 1.0), 1.0, 0.02);
  EXPECT_LT(below.e_drift, 2e-3);  // energy incl. the cohesive potential -F_c x
}

namespace {
// A sphere under a plate (wall at z = 0, domain below) in gravity g = f g_c, g_c = F_c / m.
double hang(double f, std::size_t* contacts) {
  const double s = 0.5, rho = 2000, kn = 1e5, sigma = 100.0, beta = 0.5;
  const double m = rho * 4.0 / 3.0 * M_PI * s * s * s;
  const double Fc = sigma * M_PI * beta * beta * s * s, gc = Fc / m;
  Spheres sp;
  sp.push(0, Vec3(0, 0, -s + 1e-6), Vec3::Zero(), Vec3::Zero(), m, s);
  SimConfig c;
  c.contacts = true;
  c.contact = cohesive(kn, sigma, beta);
  c.contact.parts |= kPartDamping;
  c.contact.en = 0.3;
  c.walls.push_back(Plane{Vec3::Zero(), Vec3(0, 0, -1)});
  c.uniform_g = Vec3(0, 0, -f * gc);
  c.dt = M_PI * std::sqrt(m / kn) / 41.3;
  Simulation sim(sp, c);
  for (int k = 0; k < 4000; ++k) sim.step();
  *contacts = sim.contact_stats().wall_contacts;
  return -sim.spheres().x[0].z() - s;  // gap below the plate (< 0: overlapping)
}
}  // namespace

TEST(Cohesion, SphereUnderAPlateHangsBelowTheThresholdGravity) {
  std::size_t c1 = 0, c2 = 0;
  const double gap_hold = hang(0.95, &c1), gap_fall = hang(1.05, &c2);
  std::printf("under a plate: g = 0.95 g_c: gap %.3e m (contacts %zu); g = 1.05 g_c: gap %.3e m\n",
              gap_hold, c1, gap_fall);
  EXPECT_EQ(c1, 1u);
  EXPECT_LT(gap_hold, 0.0);
  // equilibrium overlap (F_c - m g)/k_n = 0.05 F_c / k_n
  const double Fc = 100.0 * M_PI * 0.25 * 0.25;
  EXPECT_NEAR(-gap_hold, 0.05 * Fc / 1e5, 0.02 * 0.05 * Fc / 1e5);
  EXPECT_EQ(c2, 0u);
  EXPECT_GT(gap_fall, 0.1);
}
