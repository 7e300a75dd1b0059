/// @file test_cell_table.cpp
/// The contact list's cell index (cell_table.hpp): against std::map under random inserts and
/// erases (growth from 16 slots, repeated hits on the same runs), a 64 000-key block of grid keys,
/// and a probe run that wraps past the table's end, erased from its start. The list built on it
/// is checked against brute force in test_neighbors.cpp.
#include <gtest/gtest.h>

#include <map>
#include <random>

#include "ssdem/cell_table.hpp"

using namespace ssdem;

namespace {
void expect_same(const CellTable& t, const std::map<std::uint64_t, std::uint32_t>& ref,
                 const std::vector<std::uint64_t>& universe) {
  ASSERT_EQ(t.size(), ref.size());
  for (std::uint64_t k : universe) {
    const std::uint32_t* v = t.find(k);
    const auto it = ref.find(k);
    if (it == ref.end()) {
      EXPECT_EQ(v, nullptr) << "key " << k << " erased but found";
    } else {
      ASSERT_NE(v, nullptr) << "key " << k << " lost";
      EXPECT_EQ(*v, it->second);
    }
  }
}
}  // namespace

TEST(CellTable, MatchesAMapUnderRandomInsertsAndErases) {
  // Keys from a small universe, so that inserts and erases hit the same runs of slots again and
  // again (an erase that breaks a probe run loses keys behind it; a wrong backward shift moves a
  // key before its home slot, where find no longer reaches it).
  for (std::uint64_t seed : {1u, 2u, 3u}) {
    std::mt19937_64 rng(seed);
    std::vector<std::uint64_t> universe;
    for (int k = 0; k < 300; ++k) universe.push_back(rng() >> 1);  // cell keys use 63 bits
    CellTable t;
    t.reset(4);
    std::map<std::uint64_t, std::uint32_t> ref;
    for (int op = 0; op < 20000; ++op) {
      const std::uint64_t k = universe[rng() % universe.size()];
      if (rng() % 3 != 0) {
        const auto v = static_cast<std::uint32_t>(rng());
        std::uint32_t& got = t.get_or_insert(k, v);
        auto [it, fresh] = ref.try_emplace(k, v);
        ASSERT_EQ(got, it->second) << "op " << op;
        if (!fresh) {  // writes through the returned reference stick
          got = v;
          it->second = v;
        }
      } else {
        t.erase(k);
        ref.erase(k);
      }
      ASSERT_LE(2 * t.size(), t.capacity());
      if (op % 997 == 0) expect_same(t, ref, universe);
    }
    expect_same(t, ref, universe);
  }
}

TEST(CellTable, NeighbouringCellKeysAndWrapAround) {
  // The grid's keys: x << 42 | y << 21 | z around 2^20 per axis, a 40^3 block of cells (the
  // keys the list uses, consecutive in z). Fill to the load limit, erase every other, refill.
  CellTable t;
  t.reset(40 * 40 * 40);
  std::map<std::uint64_t, std::uint32_t> ref;
  std::vector<std::uint64_t> universe;
  const std::uint64_t c = std::uint64_t{1} << 20;
  for (std::uint64_t x = 0; x < 40; ++x)
    for (std::uint64_t y = 0; y < 40; ++y)
      for (std::uint64_t z = 0; z < 40; ++z) universe.push_back(((c + x) << 42) | ((c + y) << 21) | (c + z));
  for (std::size_t k = 0; k < universe.size(); ++k) {
    t.get_or_insert(universe[k], static_cast<std::uint32_t>(k));
    ref[universe[k]] = static_cast<std::uint32_t>(k);
  }
  const std::size_t cap = t.capacity();
  EXPECT_EQ(cap, std::size_t{131072});  // the power of two >= 2 x 64 000: no growth while filling
  expect_same(t, ref, universe);
  for (std::size_t k = 0; k < universe.size(); k += 2) {
    t.erase(universe[k]);
    ref.erase(universe[k]);
  }
  t.erase(universe[0]);  // absent: no effect
  expect_same(t, ref, universe);
  for (std::size_t k = 0; k < universe.size(); k += 2) {
    t.get_or_insert(universe[k], 7u);
    ref[universe[k]] = 7u;
  }
  expect_same(t, ref, universe);
  EXPECT_EQ(t.capacity(), cap);
  t.reset(10);
  EXPECT_EQ(t.size(), 0u);
  EXPECT_EQ(t.find(universe[1]), nullptr);
}

TEST(CellTable, EraseShiftsARunThatWrapsPastTheEnd) {
  // Keys chosen by the table's hash (Fibonacci, top 4 bits of k * 0x9E3779B97F4A7C15 for 16
  // slots): A, B, C start at the last slot, D at slot 0. Inserted A, B, D, C they fill slots
  // 15, 0, 1, 2 (B and C wrap round the end, D is pushed by B). Erasing A must move B to 15, D to
  // 0 and C to 1; erasing B then moves D and C up again.
  auto home = [](std::uint64_t k) { return (k * 0x9E3779B97F4A7C15ull) >> 60; };
  std::vector<std::uint64_t> last, first;
  for (std::uint64_t k = 1; last.size() < 3 || first.empty(); ++k) {
    if (home(k) == 15 && last.size() < 3) last.push_back(k);
    if (home(k) == 0 && first.empty()) first.push_back(k);
  }
  const std::uint64_t A = last[0], B = last[1], C = last[2], D = first[0];
  CellTable t;
  t.reset(4);
  ASSERT_EQ(t.capacity(), 16u);
  t.get_or_insert(A, 1);
  t.get_or_insert(B, 2);
  t.get_or_insert(D, 4);
  t.get_or_insert(C, 3);
  t.erase(A);
  EXPECT_EQ(t.find(A), nullptr);
  for (auto [k, v] : {std::pair{B, 2u}, {C, 3u}, {D, 4u}}) {
    ASSERT_NE(t.find(k), nullptr) << "key " << k << " lost by the shift";
    EXPECT_EQ(*t.find(k), v);
  }
  t.erase(B);
  for (auto [k, v] : {std::pair{C, 3u}, {D, 4u}}) {
    ASSERT_NE(t.find(k), nullptr) << "key " << k << " lost by the shift";
    EXPECT_EQ(*t.find(k), v);
  }
  EXPECT_EQ(t.size(), 2u);
}
