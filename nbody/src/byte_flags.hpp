/// @file byte_flags.hpp
/// Per-sphere byte arrays read in bulk: the set entries of a flag array (0 = clear) visited eight
/// bytes at a time (a flag array that is almost all clear, the spheres that moved past half the
/// skin or whose level changed, is passed over at one load per eight spheres), and the spheres of
/// a level array at or below a level listed without a branch per sphere.
#pragma once
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

namespace ssdem {

/// f(i) for every i < n with flags[i] != 0, ascending.
template <class F>
inline void for_each_flagged(const std::uint8_t* flags, std::size_t n, F&& f) {
  std::size_t i = 0;
  for (; i + 8 <= n; i += 8) {
    std::uint64_t w;
    std::memcpy(&w, flags + i, sizeof w);
    if (w == 0) continue;
    for (std::size_t k = i; k < i + 8; ++k)
      if (flags[k]) f(k);
  }
  for (; i < n; ++i)
    if (flags[i]) f(i);
}

/// Appends to `out` every i in [b, e) with v[i] <= t, ascending. Branch-free (every index is
/// written, the count advances by the test), so a mix of levels costs no mispredicted branches.
inline void append_at_most(const std::uint8_t* v, std::size_t b, std::size_t e, int t,
                           std::vector<std::uint32_t>& out) {
  const std::size_t m0 = out.size();
  if (e <= b) return;
  out.resize(m0 + (e - b));
  std::uint32_t* o = out.data() + m0;
  std::size_t m = 0;
  for (std::size_t i = b; i < e; ++i) {
    o[m] = static_cast<std::uint32_t>(i);
    m += v[i] <= t ? 1 : 0;
  }
  out.resize(m0 + m);
}

/// Thread `t` of `T`'s block [b, e) of n items (static: consecutive, ascending with t).
inline void static_block(std::size_t n, int t, int T, std::size_t& b, std::size_t& e) {
  b = n * static_cast<std::size_t>(t) / static_cast<std::size_t>(T);
  e = n * static_cast<std::size_t>(t + 1) / static_cast<std::size_t>(T);
}

}  // namespace ssdem
