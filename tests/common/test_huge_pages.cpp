// HugePageAllocator: large blocks are 2 MiB aligned (the condition for the kernel to back them with
// transparent huge pages), small ones come from operator new, and values behave as in std::vector.
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
