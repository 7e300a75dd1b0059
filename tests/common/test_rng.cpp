/// @file test_rng.cpp
/// Keyed random streams: reproducible per (seed, id, stream), statistically sound.
#include <gtest/gtest.h>

#include <cmath>

#include "common/rng.hpp"

using common::KeyedRng;

TEST(KeyedRng, SameKeySameStreamDifferentKeyDifferentStream) {
  KeyedRng a(1, 42, 0), b(1, 42, 0), c(1, 43, 0), d(2, 42, 0), e(1, 42, 1);
  const auto x = a.next_u64();
  EXPECT_EQ(x, b.next_u64());
  EXPECT_NE(x, c.next_u64());
  EXPECT_NE(x, d.next_u64());
  EXPECT_NE(x, e.next_u64());
}

TEST(KeyedRng, UniformMomentsAcrossIds) {
  // One draw per id (as a per-particle sampler does): mean 1/2, variance 1/12.
  const int n = 200000;
  double s = 0, s2 = 0;
  for (int i = 0; i < n; ++i) {
    const double u = KeyedRng(7, i).uniform();
    ASSERT_GE(u, 0.0);
    ASSERT_LT(u, 1.0);
    s += u;
    s2 += u * u;
  }
  const double mean = s / n, var = s2 / n - mean * mean;
  EXPECT_NEAR(mean, 0.5, 5 * std::sqrt(1.0 / 12 / n));
  EXPECT_NEAR(var, 1.0 / 12, 5 * std::sqrt(1.0 / 180 / n));
}

TEST(KeyedRng, PoissonMeanAndVariance) {
  for (double mean : {0.3, 4.0, 80.0}) {
    KeyedRng r(3, 9);
    const int n = 100000;
    double s = 0, s2 = 0;
    for (int i = 0; i < n; ++i) {
      const double k = static_cast<double>(r.poisson(mean));
      s += k;
      s2 += k * k;
    }
    const double m = s / n, v = s2 / n - m * m;
    EXPECT_NEAR(m, mean, 5 * std::sqrt(mean / n)) << mean;
    EXPECT_NEAR(v, mean, 0.05 * mean + 5 * mean * std::sqrt(2.0 / n)) << mean;
  }
  KeyedRng r(1, 1);
  EXPECT_EQ(r.poisson(0.0), 0u);
  EXPECT_EQ(r.poisson(-1.0), 0u);
}
