/// @file pair_grid.hpp
/// The contact list's cell grids (contacts.hpp: the ordinary grid of edge c = 2 s_max + k, and
/// the isolated spheres' grid of edge c + 2M with M = c), their keys and the search around a
/// sphere, shared by pair_list.cpp (updates) and pair_grid.cpp (insertion, margins).
///
/// Reach of a pair: s_i + s_j + k + m_i + m_j (m = M for an isolated sphere, else 0). A search
/// starts from an ordinary sphere (built in, or just re-inserted), with m_i = 0, or m_i = M to
/// test whether it may take the margin. Rings searched around r_i, so that every partner within
/// reach is in a searched cell:
///   ordinary grid (partners without margin): reach <= 2 s_max + k + m_i = c + m_i -> 1 ring,
///   or 2 when m_i = M (= c);
///   isolated grid (partners with margin M): reach <= c + m_i + M <= 3c = its edge -> 1 ring.
/// The searched cells' table slots are prefetched first, so that their cache misses overlap.
#pragma once
#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <limits>

#include "ssdem/contacts.hpp"

namespace ssdem {
namespace grid {
constexpr int kCellBits = 21;
constexpr std::int64_t kCellMax = (std::int64_t{1} << kCellBits) - 1;
constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
inline std::uint64_t cell_key(std::int64_t cx, std::int64_t cy, std::int64_t cz) {
  return (static_cast<std::uint64_t>(cx) << (2 * kCellBits)) |
         (static_cast<std::uint64_t>(cy) << kCellBits) | static_cast<std::uint64_t>(cz);
}
/// A pair's key in the list's order: the lower index in the high 32 bits.
inline std::uint64_t pair_key(std::uint32_t i, std::uint32_t j) {
  return i < j ? (std::uint64_t{i} << 32) | j : (std::uint64_t{j} << 32) | i;
}
/// Appends to keys the cells within `rings` (1 or 2) of cell key k (inside the key range), ring
/// by ring (k, then the 26 around it, then the outer 98: a search that stops at the first sphere
/// found, the isolation test, then rarely reads the outer ring), and prefetches their slots in t; returns the
/// new count.
inline int ring_keys(const CellTable& t, std::uint64_t k, int rings, std::uint64_t* keys, int nk) {
  const std::int64_t cx = static_cast<std::int64_t>(k >> (2 * kCellBits));
  const std::int64_t cy = static_cast<std::int64_t>((k >> kCellBits) & kCellMax);
  const std::int64_t cz = static_cast<std::int64_t>(k & kCellMax);
  for (std::int64_t r = 0; r <= rings; ++r)
    for (std::int64_t dx = -r; dx <= r; ++dx)
      for (std::int64_t dy = -r; dy <= r; ++dy)
        for (std::int64_t dz = -r; dz <= r; ++dz) {
          if (std::max({std::abs(dx), std::abs(dy), std::abs(dz)}) < r) continue;  // an inner ring's
          const std::int64_t X = cx + dx, Y = cy + dy, Z = cz + dz;
          if (X < 0 || Y < 0 || Z < 0 || X > kCellMax || Y > kCellMax || Z > kCellMax) continue;
          keys[nk] = cell_key(X, Y, Z);
          t.prefetch(keys[nk++]);
        }
  return nk;
}
}  // namespace grid

template <class F>
void ContactSystem::visit_near(const Spheres& sp, std::uint32_t i, double mi, F&& f) const {
  // (i is in the ordinary grid: a sphere is searched around only there, when it is built in or
  // re-inserted; mi = M is the test whether it may take the margin)
  const Vec3 xi = xref_[i];
  const double si = sp.s[i];
  // the cells: up to 5^3 of the ordinary grid, then up to 3^3 of the isolated spheres' grid
  std::uint64_t keys[125 + 27];
  const int na = grid::ring_keys(head_, ckey_[i], mi > 0.0 ? 2 : 1, keys, 0);
  const int nb = fhead_count_ > 0 ? grid::ring_keys(fhead_, cell_of(xi, fcell_), 1, keys, na) : na;
  for (int q = 0; q < nb; ++q) {
    const std::uint32_t* head = (q < na ? head_ : fhead_).find(keys[q]);
    if (!head) continue;
    for (std::uint32_t j = *head; j != grid::kNone; j = next_[j]) {
      if (j == i) continue;
      // same operand order as the test for (min, max): the set is symmetric bit for bit (the
      // margins' sum is exact in either order, and +0 without margins)
      const double mj = fast_[j] ? margin_ : 0.0;
      const double reach = (i < j ? si + sp.s[j] + skin_ : sp.s[j] + si + skin_) + (mi + mj);
      if ((xref_[j] - xi).squaredNorm() < reach * reach && f(j)) return;
    }
  }
}

template <class F>
void ContactSystem::for_each_near(const Spheres& sp, std::uint32_t i, F&& f) const {
  visit_near(sp, i, 0.0, [&](std::uint32_t j) {
    f(j);
    return false;
  });
}

}  // namespace ssdem
