/// @file test_escape_speed.cpp
/// Sphere-by-sphere escape test (analysis/escape_speed.hpp): the uniform-sphere potential and the
/// escape speed on both sides (1 %) inside and outside the body; beta_escape_speed on the
/// synthetic impact outcome.
#include <gtest/gtest.h>

#include <cmath>

#include "analysis/analyse_scene.hpp"
#include "analysis/escape_speed.hpp"
#include "analysis/run_analysis.hpp"
#include "sphere_configs.hpp"

using namespace analysis;

TEST(EscapeSpeed, UniformSpherePotentialIsContinuousAndMatchesTheCentreValue) {
  const double G = 6.674e-11, M = 2.20893e16, R = 12500.0;
  EXPECT_NEAR(uniform_sphere_potential(M, R, R, G), -G * M / R, 1e-12 * G * M / R);
  EXPECT_NEAR(uniform_sphere_potential(M, R, R * (1 - 1e-12), G), -G * M / R, 1e-9 * G * M / R);
  EXPECT_NEAR(uniform_sphere_potential(M, R, 0.0, G), -1.5 * G * M / R, 1e-12 * G * M / R);
  // surface escape speed of the paper's target: 15.36 m/s (validation-data.md §4.1)
  EXPECT_NEAR(std::sqrt(-2 * uniform_sphere_potential(M, R, R, G)), 15.36, 0.01);
}

TEST(EscapeSpeed, SpheresJustBelowAndAboveTheLocalEscapeSpeed) {
  const double G = 6.674e-11, M = 1e15, R = 3000.0;
  const Eigen::Vector3d C(10, -20, 30), V(0.5, 0, -0.25);
  std::vector<double> x, v, m;
  int expect_escaping = 0;
  for (double r : {0.0, 1500.0, 2999.0, 3000.0, 8000.0})
    for (double f : {0.99, 1.01}) {
      const double vesc = std::sqrt(-2 * uniform_sphere_potential(M, R, r, G));
      const Eigen::Vector3d pos = C + r * Eigen::Vector3d(0.6, 0.0, 0.8);
      const Eigen::Vector3d vel = V + f * vesc * Eigen::Vector3d(0, 1, 0);
      x.insert(x.end(), {pos[0], pos[1], pos[2]});
      v.insert(v.end(), {vel[0], vel[1], vel[2]});
      m.push_back(f > 1 ? 2.0 : 1.0);
      expect_escaping += f > 1;
    }
  const SpeedEscape se = escape_by_speed(x.data(), v.data(), m.data(), m.size(), M, R, C, V, G);
  EXPECT_EQ(se.escaping_count, static_cast<std::size_t>(expect_escaping));
  EXPECT_DOUBLE_EQ(se.escaping_mass, 2.0 * expect_escaping);
}

TEST(EscapeSpeed, BetaFromSpeedMatchesClumpBetaWhenEjectaAreFast) {
  // remnant cube + three fast single ejecta; momentum conserved with beta = 1.69
  common::SphereSet s;
  analysis_test::add_cube(s, {0, 0, 0}, 3, 200.0, 1e12, {0, 0, -0.0001});
  const double pimp = 2e9 * 5000.0;
  const double me = 1e6;
  for (int k = 0; k < 3; ++k) analysis_test::add(s, {5e5 * (k + 1), 0, 0}, 10.0, me, {0, 0, 0.69 * pimp / 3 / me});
  // remnant momentum from conservation: -pimp - 0.69 pimp
  for (std::size_t i = 0; i < 27; ++i) s.velocity[3 * i + 2] = -1.69 * pimp / 27e12;
  AnalyseConfig cfg;
  cfg.impact.impactor_mass = 2e9;
  cfg.impact.impactor_velocity = {0, 0, -5000};
  const SnapshotResult r = analyse_snapshot(s, cfg, 40.0);
  ASSERT_TRUE(r.beta_escape_speed);
  EXPECT_NEAR(*r.beta_escape_speed, 1.69, 1e-12);
  EXPECT_DOUBLE_EQ(r.speed_escaping_mass, 3e6);
  EXPECT_NEAR(r.beta->beta, 1.69, 1e-12);
}
