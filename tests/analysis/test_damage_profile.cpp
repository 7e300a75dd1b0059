/// @file test_damage_profile.cpp
/// Damage profiles (analysis/damage_profile.hpp): a field linear in the axis coordinate gives
/// exact bin means; shells; cylinder selection; empty bins.
#include <gtest/gtest.h>

#include <cmath>

#include <Eigen/Geometry>

#include "analysis/damage_profile.hpp"

using namespace analysis;

TEST(DamageProfile, LinearFieldAlongAnObliqueAxisGivesExactBinMeans) {
  const Eigen::Vector3d axis = Eigen::Vector3d(1, 1, 1).normalized();
  const Eigen::Vector3d t1 = axis.unitOrthogonal(), t2 = axis.cross(t1);
  const Eigen::Vector3d o(100, -50, 20);
  const double a = 0.3, b = 0.01;  // D = a + b s
  std::vector<double> x, m, d;
  // 10 bins on [-50, 50]; in each bin items symmetric about the bin centre in s (pairs of equal
  // mass), with different masses between pairs and arbitrary transverse offsets.
  for (int k = 0; k < 10; ++k) {
    const double c = -45.0 + 10.0 * k;
    for (int p = 0; p < 4; ++p) {
      const double ds = 1.0 + p, mass = 1.0 + 3.0 * p + k;
      for (double sgn : {-1.0, 1.0}) {
        const double s = c + sgn * ds;
        const Eigen::Vector3d pos = o + s * axis + (7.0 * p - 3) * t1 + sgn * 2.0 * t2;
        for (int q = 0; q < 3; ++q) x.push_back(pos[q]);
        m.push_back(mass);
        d.push_back(a + b * s);
      }
    }
  }
  ProfileSpec spec;
  spec.origin = o;
  spec.axis = 3.0 * axis;  // normalised internally
  spec.bins = 10;
  spec.lo = -50;
  spec.hi = 50;
  const auto prof = axial_profile(x.data(), m.data(), d.data(), m.size(), spec);
  ASSERT_EQ(prof.size(), 10u);
  for (int k = 0; k < 10; ++k) {
    EXPECT_NEAR(prof[k].centre(), -45.0 + 10.0 * k, 1e-12);
    EXPECT_EQ(prof[k].count, 8u);
    EXPECT_NEAR(prof[k].mean, a + b * prof[k].centre(), 1e-13);
    EXPECT_DOUBLE_EQ(prof[k].mass, 2 * (4 * (1.0 + k) + 3.0 * 6));
  }
  // Automatic range: the data extent [-49 + ..., ...] still bins every item once.
  spec.lo = spec.hi = 0;
  spec.bins = 7;
  std::size_t total = 0;
  for (const auto& bin : axial_profile(x.data(), m.data(), d.data(), m.size(), spec)) total += bin.count;
  EXPECT_EQ(total, m.size());
}

TEST(DamageProfile, RadialShellsAndCylinderSelection) {
  std::vector<double> x, m, d;
  // points on spheres of radius 0.5, 1.5, 2.5 with damage = radius/3 (exact shell means)
  for (double r : {0.5, 1.5, 2.5})
    for (int k = 0; k < 12; ++k) {
      const double th = 0.4 + 0.2 * k, ph = 1.3 * k;
      x.insert(x.end(), {r * std::sin(th) * std::cos(ph), r * std::sin(th) * std::sin(ph), r * std::cos(th)});
      m.push_back(1.0 + k);
      d.push_back(r / 3.0);
    }
  ProfileSpec spec;
  spec.bins = 3;
  spec.lo = 0;
  spec.hi = 3;
  const auto rad = radial_profile(x.data(), m.data(), d.data(), m.size(), spec);
  ASSERT_EQ(rad.size(), 3u);
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(rad[k].count, 12u);
    EXPECT_NEAR(rad[k].mean, (0.5 + k) / 3.0, 1e-15);
  }
  // Cylinder of radius 0.6 about z: only the points with transverse distance <= 0.6.
  spec.cylinder_radius = 0.6;
  spec.lo = -3;
  spec.hi = 3;
  spec.bins = 1;
  const auto ax = axial_profile(x.data(), m.data(), d.data(), m.size(), spec);
  std::size_t expect = 0;
  for (std::size_t i = 0; i < m.size(); ++i) expect += std::hypot(x[3 * i], x[3 * i + 1]) <= 0.6;
  EXPECT_EQ(ax[0].count, expect);
  EXPECT_GT(expect, 12u);  // all 12 inner points plus some outer ones near the poles
  EXPECT_LT(expect, 36u);
  // Selection mask and empty bins.
  std::vector<char> sel(m.size(), 0);
  sel[0] = 1;
  spec.cylinder_radius = 0;
  spec.bins = 4;
  const auto one = axial_profile(x.data(), m.data(), d.data(), m.size(), spec, sel.data());
  std::size_t nonempty = 0;
  for (const auto& bin : one) nonempty += bin.count;
  EXPECT_EQ(nonempty, 1u);
  EXPECT_TRUE(std::isnan(one[0].mean) || std::isnan(one[3].mean));
}
