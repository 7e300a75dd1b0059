/// @file test_branchless.cpp
/// common/branchless.hpp: the selects and floor_to_int equal their branching forms, including at
/// equality, signed zeros, infinities and NaN operands of the comparison (NaN compares false).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "common/branchless.hpp"

TEST(Branchless, SelectsEqualTernaries) {
  const double inf = std::numeric_limits<double>::infinity(), nan = std::nan("");
  std::vector<double> v = {0.0, -0.0, 1.0, -1.0, 0.5, 1e-300, -1e300, inf, -inf, nan};
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  for (int i = 0; i < 200; ++i) v.push_back(u(rng));
  for (double a : v)
    for (double b : v) {
      EXPECT_EQ(common::select_lt(a, b, 3.0, -7.0), a < b ? 3.0 : -7.0) << a << " " << b;
      EXPECT_EQ(common::select_le(a, b, 3.0, -7.0), a <= b ? 3.0 : -7.0) << a << " " << b;
    }
  // The selected value passes through bit for bit (sign of zero, NaN payload class).
  EXPECT_TRUE(std::signbit(common::select_lt(0.0, 1.0, -0.0, 1.0)));
  EXPECT_TRUE(std::isnan(common::select_le(1.0, 1.0, nan, 0.0)));
}

TEST(Branchless, FloorToIntEqualsFloor) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1e6, 1e6);
  std::vector<double> xs = {0.0, -0.0, 1.0, -1.0, 0.5, -0.5, 1e-300, -1e-300, 2147483647.0, -2147483647.0,
                            std::nextafter(1.0, 0.0), std::nextafter(-1.0, 0.0), -3.0000000000000004};
  for (int t = 0; t < 100000; ++t) xs.push_back(u(rng) * (t % 2 ? 1e-6 : 1.0));
  for (double x : xs) ASSERT_EQ(common::floor_to_int(x), static_cast<int>(std::floor(x))) << x;
}
