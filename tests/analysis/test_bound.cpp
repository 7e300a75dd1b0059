/// @file test_bound.cpp
/// Bound mass (analysis/bound.hpp): analytic two-body escape speed on both sides (1 %), Galilean
/// invariance, an iteration where a clump is bound only after another joins, bookkeeping sums.
#include <gtest/gtest.h>

#include <cmath>

#include "analysis/analyse_scene.hpp"
#include "analysis/bound.hpp"
#include "analysis/run_analysis.hpp"
#include "sphere_configs.hpp"

using namespace analysis;
using analysis_test::add;
using analysis_test::add_cube;

namespace {
constexpr double G = 6.674e-11;

BoundResult bound_of(const common::SphereSet& s, double eps) {
  const FofResult f = friends_of_friends(s.position.data(), s.radius.data(), s.mass.data(), s.count(), eps);
  return bound_to_largest(clump_properties(s.position.data(), s.velocity.data(), s.mass.data(), s.count(), f), G);
}
}  // namespace

TEST(Bound, SphereJustBelowEscapeSpeedIsBoundJustAboveIsNot) {
  // Remnant: 27 touching spheres (radius 500 m, 1e13 kg each) moving at V; test sphere of 1e10 kg
  // at distance d from the remnant's centre of mass with speed f * v_esc relative to V.
  const double r = 500.0, m0 = 1e13, m = 1e10;
  const Eigen::Vector3d V(3.0, -2.0, 1.0);
  const Eigen::Vector3d com(2 * r, 2 * r, 2 * r);  // centre of the 3x3x3 cube from the origin corner
  const Eigen::Vector3d dir = Eigen::Vector3d(1, 0.5, -0.25).normalized();
  const double d = 2.0e4;
  const double M = 27 * m0;
  const double vesc = std::sqrt(2 * G * (M + m) / d);
  ASSERT_NEAR(vesc, 1.3424, 1e-4);  // sqrt(2 * 6.674e-11 * 2.7001e14 / 2e4)
  for (double f : {0.99, 1.01}) {
    common::SphereSet s;
    add_cube(s, {0, 0, 0}, 3, r, m0, V);
    // velocity perpendicular-ish and radial mix: energy only depends on |v - V|
    const Eigen::Vector3d vdir = Eigen::Vector3d(0.3, -1, 0.2).normalized();
    add(s, com + d * dir, r, m, V + f * vesc * vdir);
    const BoundResult b = bound_of(s, 50.0);
    EXPECT_DOUBLE_EQ(b.lr_mass, M);
    if (f < 1) {
      EXPECT_EQ(b.n_bound_clumps, 2u);
      EXPECT_DOUBLE_EQ(b.bound_mass, M + m);
      EXPECT_DOUBLE_EQ(b.escaping_mass, 0.0);
    } else {
      EXPECT_EQ(b.n_bound_clumps, 1u);
      EXPECT_DOUBLE_EQ(b.bound_mass, M);
      EXPECT_DOUBLE_EQ(b.escaping_mass, m);
      EXPECT_NEAR((b.escaping_momentum - m * (V + f * vesc * vdir)).norm(), 0.0, 1e-9 * m * vesc);
    }
    // Energy of the test sphere relative to the LR: sign and value.
    const double E = two_body_energy(M, com, V, m, com + d * dir, V + f * vesc * vdir, G);
    EXPECT_NEAR(E, 0.5 * (f * f - 1) * vesc * vesc, 1e-9 * vesc * vesc);
  }
}

TEST(Bound, IterationAddsAClumpBoundOnlyToTheGrownRemnant) {
  const double M = 1e15, mB = 1e9, dA = 1000.0, L = 2.0e5;
  common::SphereSet s;
  add(s, {0, 0, 0}, 100.0, M * 1.0000001);  // LR (slightly heavier than A)
  add(s, {dA, 0, 0}, 100.0, M);             // A at rest: bound in pass 1
  // B: unbound to the LR alone, bound to LR + A (mass 2M at x = dA/2):
  // 1/2 v^2 = G 1.5 M / L  =>  E1 = G (1.5 M - M - mB)/L > 0, E2 < 0.
  const double v = std::sqrt(2 * G * 1.5 * M / L);
  add(s, {0, L, 0}, 100.0, mB, {v, 0, 0});
  const BoundResult b = bound_of(s, 1.0);
  EXPECT_EQ(b.n_bound_clumps, 3u);
  EXPECT_EQ(b.iterations, 3);  // add A, add B, no change
  EXPECT_DOUBLE_EQ(b.bound_mass, M * 2.0000001 + mB);
  EXPECT_DOUBLE_EQ(b.escaping_mass, 0.0);
  // Same with B a little faster than the grown remnant's escape speed: not bound.
  common::SphereSet s2 = s;
  const Eigen::Vector3d R2(dA / 2 * (M / (M * 2.0000001)), 0, 0);
  const double d2 = (Eigen::Vector3d(0, L, 0) - R2).norm();
  s2.velocity[6] = 1.01 * std::sqrt(2 * G * (M * 2.0000001 + mB) / d2);
  const BoundResult b2 = bound_of(s2, 1.0);
  EXPECT_EQ(b2.n_bound_clumps, 2u);
  EXPECT_DOUBLE_EQ(b2.escaping_mass, mB);
}

TEST(Bound, BookkeepingSumsAndLargestRemnantVelocity) {
  common::SphereSet s;
  add_cube(s, {0, 0, 0}, 2, 1.0, 5.0, {1, 0, 0});
  add(s, {1e6, 0, 0}, 1.0, 2.0, {0, 300, 0});
  add(s, {-1e6, 0, 0}, 1.0, 3.0, {0, 0, -400});
  const BoundResult b = bound_of(s, 0.2);
  EXPECT_DOUBLE_EQ(b.total_mass, 45.0);
  EXPECT_DOUBLE_EQ(b.lr_mass, 40.0);
  EXPECT_DOUBLE_EQ(b.bound_mass, 40.0);
  EXPECT_DOUBLE_EQ(b.escaping_mass, 5.0);
  EXPECT_TRUE(b.lr_momentum.isApprox(Eigen::Vector3d(40, 0, 0)));
  EXPECT_TRUE(b.escaping_momentum.isApprox(Eigen::Vector3d(0, 600, -1200)));
  EXPECT_TRUE(b.total_momentum.isApprox(Eigen::Vector3d(40, 600, -1200)));
  EXPECT_TRUE(b.bound_com.isApprox(Eigen::Vector3d(1, 1, 1)));
}
