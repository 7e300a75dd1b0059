/// @file test_byte_flags.cpp
/// The per-sphere byte scans (nbody/src/byte_flags.hpp) against plain loops: append_at_most on
/// random level arrays (sparse and dense, every threshold 0-31, ranges that start and end inside
/// an eight-byte group), and for_each_flagged.
#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <vector>

#include "../../nbody/src/byte_flags.hpp"

using namespace ssdem;

TEST(ByteFlags, AppendAtMostMatchesAPlainLoop) {
  std::mt19937_64 rng(3);
  for (int trial = 0; trial < 400; ++trial) {
    const std::size_t n = 1 + rng() % 300;
    std::vector<std::uint8_t> v(n);
    const bool sparse = trial % 2 == 0;  // debris: most spheres on one long level
    for (auto& x : v) x = static_cast<std::uint8_t>(sparse ? (rng() % 50 == 0 ? rng() % 12 : 11) : rng() % 31);
    const std::size_t b = rng() % n, e = b + rng() % (n - b + 1);
    const int t = static_cast<int>(rng() % 32);
    std::vector<std::uint32_t> got = {7u}, want = {7u};  // appended after what is there
    append_at_most(v.data(), b, e, t, got);
    for (std::size_t i = b; i < e; ++i)
      if (v[i] <= t) want.push_back(static_cast<std::uint32_t>(i));
    ASSERT_EQ(got, want) << "trial " << trial << " t " << t << " [" << b << ", " << e << ")";
  }
}

TEST(ByteFlags, ForEachFlaggedVisitsTheSetOnesAscending) {
  std::mt19937_64 rng(4);
  for (int trial = 0; trial < 200; ++trial) {
    const std::size_t n = rng() % 200;
    std::vector<std::uint8_t> f(n);
    for (auto& x : f) x = rng() % 9 == 0 ? static_cast<std::uint8_t>(1 + rng() % 255) : 0;
    std::vector<std::size_t> got, want;
    for_each_flagged(f.data(), n, [&](std::size_t i) { got.push_back(i); });
    for (std::size_t i = 0; i < n; ++i)
      if (f[i]) want.push_back(i);
    ASSERT_EQ(got, want) << "trial " << trial;
    EXPECT_EQ(count_flagged(f.data(), n), want.size()) << "trial " << trial;
  }
}
