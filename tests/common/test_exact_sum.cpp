/// @file test_exact_sum.cpp
/// ExactSum (common/exact_sum.hpp): exact against integer arithmetic, independent of the order
/// and of how the terms are split into accumulators, correctly rounded, and non-finite terms.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include "common/exact_sum.hpp"

using common::ExactSum;

namespace {
double sum_of(const std::vector<double>& v) {
  ExactSum s;
  for (double x : v) s += x;
  return s.value();
}
}  // namespace

TEST(ExactSum, CancellationKeepsTheSmallTerms) {
  // naive left-to-right summation gives 0 for both
  EXPECT_EQ(sum_of({1e100, 1.0, -1e100}), 1.0);
  EXPECT_EQ(sum_of({1e308, 1e308, -1e308, -1e308, 3e-320}), 3e-320);
  EXPECT_EQ(sum_of({0.1, 0.2, -0.3}), std::ldexp(1.0, -55));  // the doubles' exact sum
  EXPECT_EQ(sum_of({}), 0.0);
  EXPECT_EQ(sum_of({-2.5}), -2.5);
  EXPECT_EQ(sum_of({std::numeric_limits<double>::denorm_min(), -std::numeric_limits<double>::denorm_min()}), 0.0);
}

TEST(ExactSum, EqualsIntegerArithmeticOnRepresentableTerms) {
  // terms k 2^-20 with |k| < 2^40: their exact sum is an integer multiple of 2^-20 below 2^53
  std::mt19937_64 rng(7);
  std::uniform_int_distribution<std::int64_t> k(-(std::int64_t{1} << 40), std::int64_t{1} << 40);
  std::vector<double> v;
  std::int64_t exact = 0;
  for (int i = 0; i < 5000; ++i) {
    const std::int64_t q = k(rng);
    exact += q;
    v.push_back(std::ldexp(static_cast<double>(q), -20));
  }
  EXPECT_EQ(sum_of(v), std::ldexp(static_cast<double>(exact), -20));
}

TEST(ExactSum, CorrectlyRounded) {
  // 1 + 2^-53 is a tie: rounds to even (1); one more 2^-80 below it breaks the tie upwards
  EXPECT_EQ(sum_of({1.0, std::ldexp(1.0, -53)}), 1.0);
  EXPECT_EQ(sum_of({1.0, std::ldexp(1.0, -53), std::ldexp(1.0, -80)}), std::nextafter(1.0, 2.0));
  // ties broken by a term more than three 32-bit digits below the leading one (the sticky bit)
  EXPECT_EQ(sum_of({1.0, std::ldexp(1.0, -53), std::ldexp(1.0, -150)}), std::nextafter(1.0, 2.0));
  EXPECT_EQ(sum_of({0x1p33, 0x1p-20, 1e-200}), std::nextafter(0x1p33, 0x1p34));
  EXPECT_EQ(sum_of({0x1p33, 0x1p-20, -1e-200}), 0x1p33);
  EXPECT_EQ(sum_of({-1.0, -std::ldexp(1.0, -53), -std::ldexp(1.0, -150)}), -std::nextafter(1.0, 2.0));
  // beyond the double range
  EXPECT_EQ(sum_of({1.7e308, 1.7e308}), std::numeric_limits<double>::infinity());
}

TEST(ExactSum, CorrectlyRoundedAgainstAnIndependentIntegerReference) {
  // 2 to 16 terms m 2^e, |m| < 2^53, e in [-60, 10], mixed signs: their exact sum times 2^60 is an
  // integer below 2^127 (__int128), whose conversion to double is correctly rounded by the compiler
  std::mt19937_64 rng(3);
  std::uniform_int_distribution<int> count(2, 16), ex(-60, 10);
  int checked = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    ExactSum s;
    __int128 ref = 0;
    const int n = count(rng);
    for (int i = 0; i < n; ++i) {
      const std::int64_t m = static_cast<std::int64_t>(rng() >> 11) * ((rng() & 1) ? 1 : -1);
      const int e = ex(rng);
      s += std::ldexp(static_cast<double>(m), e);
      ref += static_cast<__int128>(m) << (e + 60);
    }
    const double want = std::ldexp(static_cast<double>(ref), -60);
    EXPECT_EQ(s.value(), want) << "trial " << trial;
    checked += s.value() == want;
  }
  EXPECT_EQ(checked, 20000);
  // a negative total whose tie is broken by the sticky bit, far below the leading digits
  EXPECT_EQ(sum_of({-1.0, std::ldexp(1.0, -54), std::ldexp(1.0, -200)}), -std::nextafter(1.0, 0.0));
  EXPECT_EQ(sum_of({-1.0, std::ldexp(1.0, -54), -std::ldexp(1.0, -200)}), -1.0);
}

TEST(ExactSum, SameBitsInAnyOrderAndAnySplit) {
  std::mt19937_64 rng(11);
  std::lognormal_distribution<double> mag(0.0, 12.0);
  std::vector<double> v;
  for (int i = 0; i < 20000; ++i) v.push_back((rng() & 1 ? -1.0 : 1.0) * mag(rng));
  const double ref = sum_of(v);
  for (int round = 0; round < 5; ++round) {
    std::shuffle(v.begin(), v.end(), rng);
    EXPECT_EQ(sum_of(v), ref);
    // split among "ranks" at random points, merged one way and summed limb-wise the other
    std::vector<ExactSum> part(3 + round);
    for (double x : v) part[rng() % part.size()] += x;
    ExactSum merged;
    for (const ExactSum& p : part) merged.merge(p);
    EXPECT_EQ(merged.value(), ref);
    std::array<std::int64_t, ExactSum::kLimbs> limbs{};
    for (const ExactSum& p : part) {
      const auto l = p.limbs();
      for (int k = 0; k < ExactSum::kLimbs; ++k) limbs[k] += l[k];
    }
    EXPECT_EQ(ExactSum::from_limbs(limbs.data(), 0.0, false).value(), ref);
  }
  // and naive summation does depend on the order here: the test would see a non-exact sum
  double a = 0.0, b = 0.0;
  for (double x : v) a += x;
  for (auto it = v.rbegin(); it != v.rend(); ++it) b += *it;
  EXPECT_NE(a, b);
}

TEST(ExactSum, ManyTermsPastTheNormalisationInterval) {
  // three normalisations on the way (every 2^20 additions); the product is correctly rounded too
  ExactSum s;
  const double x = 0x1.fffffffffffffp+1000;
  const std::int64_t n = 3 * (std::int64_t{1} << 20) + 5;
  for (std::int64_t i = 0; i < n; ++i) s += x;
  EXPECT_EQ(s.value(), std::ldexp(0x1.fffffffffffffp+0, 1000) * static_cast<double>(n));
}

TEST(ExactSum, NonFiniteTermsShowInTheValue) {
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_EQ(sum_of({1.0, inf, 2.0}), inf);
  EXPECT_TRUE(std::isnan(sum_of({1.0, inf, -inf})));
  EXPECT_TRUE(std::isnan(sum_of({std::nan(""), 1.0})));
  ExactSum a, b;
  a += 1.0;
  b += -inf;
  a.merge(b);
  EXPECT_EQ(a.value(), -inf);
}
