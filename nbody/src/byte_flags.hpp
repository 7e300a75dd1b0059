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

/// The number of i < n with flags[i] != 0 (eight bytes at a time, as for_each_flagged: a byte
/// sum widened to 64 bits lane by lane cost ~20 us per base step over the 155 805 spheres of
/// the 2.42 km 375 m row, where few are set).
inline std::size_t count_flagged(const std::uint8_t* flags, std::size_t n) {
  std::size_t c = 0;
  for_each_flagged(flags, n, [&](std::size_t) { ++c; });
  return c;
}

/// Appends to `out` every i in [b, e) with v[i] <= t, ascending. Eight bytes at a time: a group
/// with no byte below t + 1 (the usual case on debris, where few spheres are synchronised at a
/// step) costs one load and a test ("a word has a byte less than n", exact for n <= 128; Anderson,
/// Bit Twiddling Hacks); the spheres of a group with one are appended one by one. (A branch-free
/// loop that wrote every index, and value-initialised the room for them, cost 2/3 of the level
/// rules on the 2.42 km 750 m debris segment: nbody/README.md, "Level rules on debris".)
inline void append_at_most(const std::uint8_t* v, std::size_t b, std::size_t e, int t,
                           std::vector<std::uint32_t>& out) {
  if (e <= b || t < 0) return;
  std::size_t i = b;
  if (t < 127) {
    const std::uint64_t ones = 0x0101010101010101ull, high = 0x8080808080808080ull;
    const std::uint64_t below = ones * static_cast<std::uint64_t>(t + 1);
    for (; i + 8 <= e; i += 8) {
      std::uint64_t w;
      std::memcpy(&w, v + i, sizeof w);
      if (((w - below) & ~w & high) == 0) continue;
      for (std::size_t k = i; k < i + 8; ++k)
        if (v[k] <= t) out.push_back(static_cast<std::uint32_t>(k));
    }
  }
  for (; i < e; ++i)
    if (v[i] <= t) out.push_back(static_cast<std::uint32_t>(i));
}

}  // namespace ssdem
