/// @file test_huge_pages.cpp
/// HugePageAllocator: large blocks are 2 MiB aligned (the condition for the kernel to back them with
/// transparent huge pages), small ones come from operator new, and values behave as in std::vector.
#include <gtest/gtest.h>

#include <cstdint>
#include <numeric>

#include "common/huge_pages.hpp"

TEST(HugePages, LargeBlocksAreHugePageAlignedAndHoldTheirValues) {
  const std::size_t n = (std::size_t(6) << 20) / sizeof(double) + 3;  // 6 MiB + 24 B: rounded to 8 MiB
  common::huge_vector<double> v(n, 1.5);
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(v.data()) % common::kHugePage, 0u);
  EXPECT_EQ(v.size(), n);
  EXPECT_DOUBLE_EQ(std::accumulate(v.begin(), v.end(), 0.0), 1.5 * static_cast<double>(n));
  v.resize(2 * n, -1.0);  // reallocation through the allocator keeps the old values
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(v.data()) % common::kHugePage, 0u);
  EXPECT_DOUBLE_EQ(v[n - 1], 1.5);
  EXPECT_DOUBLE_EQ(v[2 * n - 1], -1.0);
}

TEST(HugePages, SmallBlocksAndCopiesBehaveLikeStdVector) {
  common::huge_vector<std::uint32_t> a(1000);
  std::iota(a.begin(), a.end(), 0u);
  common::huge_vector<std::uint32_t> b = a;  // small: operator new path
  EXPECT_EQ(a, b);
  b.insert(b.end(), a.begin(), a.end());
  EXPECT_EQ(b.size(), 2000u);
  EXPECT_EQ(b[1999], 999u);
  common::huge_vector<std::uint32_t> big(std::size_t(5) << 20);  // 20 MiB, value-initialised
  EXPECT_EQ(big.front(), 0u);
  EXPECT_EQ(big.back(), 0u);
  big.clear();
  big.shrink_to_fit();  // frees through the matching path
  EXPECT_EQ(big.capacity(), 0u);
}

TEST(HugePages, BufferIsAlignedMovableAndFreesThroughTheAllocator) {
  const std::size_t n = (std::size_t(5) << 20) / sizeof(std::uint32_t);  // 5 MiB: huge-page path
  common::huge_buffer<std::uint32_t> a(n);
  EXPECT_EQ(a.size(), n);
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(a.data()) % common::kHugePage, 0u);
  for (std::size_t i = 0; i < n; ++i) a[i] = static_cast<std::uint32_t>(3 * i);
  common::huge_buffer<std::uint32_t> b(std::move(a));
  EXPECT_EQ(a.size(), 0u);
  EXPECT_EQ(a.data(), nullptr);
  EXPECT_EQ(b[n - 1], static_cast<std::uint32_t>(3 * (n - 1)));
  common::huge_buffer<std::uint32_t> small(10);  // operator new path
  small[9] = 7;
  b = std::move(small);  // swap: both blocks are freed by their destructors (ASan checks)
  EXPECT_EQ(b.size(), 10u);
  EXPECT_EQ(b[9], 7u);
  EXPECT_EQ(small.size(), n);
  common::huge_buffer<double> empty(0);
  EXPECT_EQ(empty.data(), nullptr);
}

TEST(HugePages, ResizeHugeGivesValueInitialisedVectors) {
  std::vector<double> big;
  common::resize_huge(big, (std::size_t(5) << 20) / sizeof(double));  // 5 MiB: advised
  ASSERT_EQ(big.size(), (std::size_t(5) << 20) / sizeof(double));
  for (double x : big) ASSERT_EQ(x, 0.0);
  std::vector<std::int32_t> small;
  common::resize_huge(small, 7);  // below the threshold: plain resize
  EXPECT_EQ(small, std::vector<std::int32_t>(7, 0));
  common::resize_huge(small, 9);  // not empty: no advice, values kept
  EXPECT_EQ(small.size(), 9u);
}
