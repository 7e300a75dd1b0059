/// @file test_fof.cpp
/// Friends-of-friends on sphere surfaces (analysis/fof.hpp): constructed configurations with known
/// clump counts, the linking threshold on both sides, and a brute-force O(N^2) cross-check.
#include <gtest/gtest.h>
#include <omp.h>

#include <numeric>
#include <random>

#include "analysis/fof.hpp"
#include "sphere_configs.hpp"

using namespace analysis;
using analysis_test::add;
using analysis_test::add_cube;

namespace {
FofResult fof(const common::SphereSet& s, double eps) {
  return friends_of_friends(s.position.data(), s.radius.data(), s.mass.data(), s.count(), eps);
}
}  // namespace

TEST(Fof, TwoSeparatedTouchingClustersAreTwoClumps) {
  common::SphereSet s;
  add_cube(s, {0, 0, 0}, 3, 1.0, 1.0);      // 27 touching spheres, mass 27
  add_cube(s, {40, 3, -7}, 3, 1.0, 2.0);    // 27 touching spheres, mass 54 (heavier)
  const FofResult r = fof(s, 0.2);
  ASSERT_EQ(r.count(), 2u);
  EXPECT_DOUBLE_EQ(r.clump_mass[0], 54.0);  // the heavier cluster is clump 0
  EXPECT_DOUBLE_EQ(r.clump_mass[1], 27.0);
  EXPECT_EQ(r.clump_count[0], 27);
  EXPECT_EQ(r.clump_first[0], 27);
  for (std::size_t i = 0; i < 27; ++i) EXPECT_EQ(r.clump_of[i], 1);
  for (std::size_t i = 27; i < 54; ++i) EXPECT_EQ(r.clump_of[i], 0);
  EXPECT_EQ(r.singles(), 0u);
}

TEST(Fof, ChainLinkedWithinEpsIsOneClumpAndSplitsJustAboveEps) {
  const double r = 0.5, eps = 0.1;
  const Eigen::Vector3d dir = Eigen::Vector3d(1, 2, -3).normalized();  // a chain crossing cell faces obliquely
  for (double gap : {0.099, 0.101}) {
    common::SphereSet s;
    for (int i = 0; i < 200; ++i) add(s, Eigen::Vector3d(5, -2, 1) + i * (2 * r + gap) * dir, r, 1.0);
    const FofResult f = fof(s, eps);
    EXPECT_EQ(f.count(), gap < eps ? 1u : 200u) << "gap " << gap;
    if (gap < eps) {
      EXPECT_DOUBLE_EQ(f.clump_mass[0], 200.0);
    }
  }
  // An axis-aligned chain on both sides of eps.
  for (double gap : {0.0999, 0.1001}) {
    common::SphereSet s;
    for (int i = 0; i < 200; ++i) add(s, {i * (2 * r + gap), 0, 0}, r, 1.0);
    EXPECT_EQ(fof(s, eps).count(), gap < eps ? 1u : 200u) << "gap " << gap;
  }
}

TEST(Fof, IsolatedSpheresAreSingles) {
  common::SphereSet s;
  for (int i = 0; i < 10; ++i)
    for (int j = 0; j < 10; ++j) add(s, {3.0 * i, 3.0 * j, 0.0}, 1.0, 1.0 + i + 10 * j);  // gaps of 1 > eps
  const FofResult f = fof(s, 0.5);
  EXPECT_EQ(f.count(), 100u);
  EXPECT_EQ(f.singles(), 100u);
  EXPECT_DOUBLE_EQ(f.clump_mass[0], 100.0);  // heaviest single first
  EXPECT_EQ(f.clump_of[99], 0);
}

TEST(Fof, PolydisperseSpheresTouchingALargeOneAreLinked) {
  common::SphereSet s;
  add(s, {0, 0, 0}, 10.0, 1000.0);
  // small spheres on the big one's surface in many directions: cell size must use r_max
  for (int k = 0; k < 20; ++k) {
    const double th = 0.3 * k, ph = 0.7 * k;
    const Eigen::Vector3d n(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th));
    add(s, (10.0 + 0.1 + 0.04) * n, 0.1, 1.0);  // gap 0.04 < eps
  }
  add(s, (10.0 + 0.1 + 0.2) * Eigen::Vector3d(0.6, -0.8, 0.0), 0.1, 1.0);  // gap 0.2 > eps: single
  const FofResult f = fof(s, 0.05);
  ASSERT_EQ(f.count(), 2u);
  EXPECT_EQ(f.clump_count[0], 21);
  EXPECT_DOUBLE_EQ(f.clump_mass[0], 1020.0);
}

TEST(Fof, FarAwaySpheresDoNotNeedABoundingGrid) {
  common::SphereSet s;
  add_cube(s, {0, 0, 0}, 2, 100.0, 1.0);
  add(s, {8.1e10, -3e10, 5e9}, 100.0, 1.0);
  add(s, {8.1e10 + 205.0, -3e10, 5e9}, 100.0, 1.0);  // gap 5 m
  const FofResult f = fof(s, 20.0);
  ASSERT_EQ(f.count(), 2u);
  EXPECT_EQ(f.clump_count[0], 8);
  EXPECT_EQ(f.clump_count[1], 2);
}

TEST(Fof, AgreesWithBruteForceAndIsThreadCountIndependent) {
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> u(0.0, 40.0), ur(0.2, 1.2);
  common::SphereSet s;
  for (int i = 0; i < 3000; ++i) add(s, {u(rng), u(rng), u(rng)}, ur(rng), ur(rng));
  const double eps = 0.15;
  // Brute force with a simple serial union-find.
  const std::size_t n = s.count();
  std::vector<std::size_t> p(n);
  std::iota(p.begin(), p.end(), 0);
  auto find = [&](std::size_t x) {
    while (p[x] != x) x = p[x] = p[p[x]];
    return x;
  };
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 1; j < n; ++j) {
      const double d = (Eigen::Vector3d(&s.position[3 * i]) - Eigen::Vector3d(&s.position[3 * j])).norm();
      if (d - s.radius[i] - s.radius[j] < eps) p[std::max(find(i), find(j))] = std::min(find(i), find(j));
    }
  const int saved = omp_get_max_threads();
  omp_set_num_threads(1);
  const FofResult one = fof(s, eps);
  omp_set_num_threads(2);
  const FofResult two = fof(s, eps);
  omp_set_num_threads(saved);
  std::size_t comps = 0;
  for (std::size_t i = 0; i < n; ++i) comps += (find(i) == i);
  ASSERT_EQ(one.count(), comps);
  ASSERT_GT(comps, 10u);     // non-trivial: several clumps ...
  ASSERT_LT(comps, n - 10);  // ... and several links
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j : {std::size_t(0), i / 2, (i * 7) % n}) EXPECT_EQ(one.clump_of[i] == one.clump_of[j], find(i) == find(j));
  EXPECT_EQ(one.clump_of, two.clump_of);
  EXPECT_EQ(one.clump_mass, two.clump_mass);  // bitwise (same summation order)
}

TEST(Fof, DefaultLinkLengthIsFractionOfMedianRadius) {
  const std::vector<double> r{1.0, 5.0, 2.0, 3.0, 100.0};
  EXPECT_DOUBLE_EQ(default_link_length(r.data(), r.size(), 0.2), 0.2 * 3.0);
  const std::vector<double> r4{1.0, 2.0, 4.0, 100.0};
  EXPECT_DOUBLE_EQ(default_link_length(r4.data(), r4.size(), 0.5), 0.5 * 3.0);
}
