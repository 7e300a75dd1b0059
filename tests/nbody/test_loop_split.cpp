/// @file test_loop_split.cpp
/// The cuts of a team's loop that follow measured times (nbody/include/ssdem/loop_split.hpp), on
/// scripted costs: items with an uneven cost per item, the times a thread would take over its
/// block, and the cuts must settle where the times are equal (not where the counts are), stay
/// apart per loop size, ignore a call in which a thread did not report, and never starve a
/// thread. That the contact results do not depend on the cuts is checked by the team tests
/// (test_omp_team.cpp: every loop on a team against the serial bits, with the cuts moving).
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <vector>

#include "ssdem/loop_split.hpp"

using namespace ssdem;

namespace {

// One call of a loop of n items on T threads: each thread's time is the sum of cost(i) over its
// block (cost per unit of the loop's length, integrated exactly over the block's items).
void call(LoopSplit& s, std::size_t n, int T, const std::function<double(std::size_t)>& cost) {
  s.begin(n, T);
  for (int t = 0; t < T; ++t) {
    std::size_t lo, hi;
    s.block(n, t, T, lo, hi);
    double time = 0.0;
    for (std::size_t i = lo; i < hi; ++i) time += cost(i);
    s.record(t, time);
  }
  s.end();
}

// The blocks of all threads tile [0, n) in order.
void expect_tiling(const LoopSplit& s, std::size_t n, int T) {
  std::size_t prev = 0;
  for (int t = 0; t < T; ++t) {
    std::size_t lo, hi;
    s.block(n, t, T, lo, hi);
    EXPECT_EQ(lo, prev) << "thread " << t;
    EXPECT_LE(lo, hi);
    prev = hi;
  }
  EXPECT_EQ(prev, n);
}

}  // namespace

TEST(LoopSplit, StartsWithEqualCountsAndOneThreadTakesAll) {
  LoopSplit s;
  std::size_t lo, hi;
  s.block(1000, 0, 2, lo, hi);
  EXPECT_EQ(lo, 0u);
  EXPECT_EQ(hi, 500u);
  s.block(1000, 1, 2, lo, hi);
  EXPECT_EQ(lo, 500u);
  EXPECT_EQ(hi, 1000u);
  s.block(1000, 0, 1, lo, hi);
  EXPECT_EQ(lo, 0u);
  EXPECT_EQ(hi, 1000u);
  expect_tiling(s, 7, 3);
}

TEST(LoopSplit, SettlesWhereTheTimesAreEqual) {
  // the first half of the items costs 3 per item, the second 1: equal times at n/3
  const std::size_t n = 30000;
  LoopSplit s;
  auto cost = [&](std::size_t i) { return i < n / 2 ? 3e-9 : 1e-9; };
  call(s, n, 2, cost);
  EXPECT_NEAR(s.cuts(n, 2)[0], 5.0 / 12.0, 1e-9);  // half way from 1/2 to the equal-time 1/3
  for (int k = 0; k < 30; ++k) call(s, n, 2, cost);
  EXPECT_NEAR(s.cuts(n, 2)[0], 1.0 / 3.0, 2e-3);
  expect_tiling(s, n, 2);
  // three threads: a cost growing linearly with i (cumulative i^2) is equal at sqrt(1/3), sqrt(2/3)
  LoopSplit s3;
  auto ramp = [&](std::size_t i) { return 1e-9 * (static_cast<double>(i) + 0.5); };
  for (int k = 0; k < 60; ++k) call(s3, n, 3, ramp);
  const std::vector<double> c = s3.cuts(n, 3);
  ASSERT_EQ(c.size(), 2u);
  EXPECT_NEAR(c[0], std::sqrt(1.0 / 3.0), 3e-3);
  EXPECT_NEAR(c[1], std::sqrt(2.0 / 3.0), 3e-3);
  expect_tiling(s3, n, 3);
}

TEST(LoopSplit, FollowsAChangeOfWhereTheCostLies) {
  const std::size_t n = 10000;
  LoopSplit s;
  for (int k = 0; k < 30; ++k) call(s, n, 2, [&](std::size_t i) { return i < n / 2 ? 3e-9 : 1e-9; });
  EXPECT_NEAR(s.cuts(n, 2)[0], 1.0 / 3.0, 3e-3);
  for (int k = 0; k < 30; ++k) call(s, n, 2, [&](std::size_t i) { return i < n / 2 ? 1e-9 : 3e-9; });
  EXPECT_NEAR(s.cuts(n, 2)[0], 2.0 / 3.0, 3e-3);
}

TEST(LoopSplit, SizeClassesAreApart) {
  LoopSplit s;
  for (int k = 0; k < 30; ++k) call(s, 40000, 2, [](std::size_t i) { return i < 20000 ? 3e-9 : 1e-9; });
  EXPECT_NEAR(s.cuts(40000, 2)[0], 1.0 / 3.0, 3e-3);
  EXPECT_NEAR(s.cuts(41000, 2)[0], 1.0 / 3.0, 3e-3);  // the same quarter octave
  EXPECT_EQ(s.cuts(400, 2)[0], 0.5);                  // a loop of another size: untouched
  EXPECT_EQ(s.cuts(40000, 3)[0], 1.0 / 3.0);          // another team size: uniform
}

TEST(LoopSplit, ACallWithoutEveryThreadsTimeMovesNothing) {
  LoopSplit s;
  s.begin(1000, 2);
  s.record(0, 5e-6);  // thread 1 never reports (the region got one thread)
  s.end();
  EXPECT_EQ(s.cuts(1000, 2)[0], 0.5);
  s.begin(1000, 1);  // no team: nothing to move
  s.record(0, 5e-6);
  s.end();
  EXPECT_EQ(s.cuts(1000, 2)[0], 0.5);
}

TEST(LoopSplit, NoThreadIsStarved) {
  // all the cost in the last 10 items: the equal-time cut would leave thread 1 five items; its
  // block keeps 1/(8T) of the loop instead (a burst of noise cannot starve a thread)
  LoopSplit s;
  for (int k = 0; k < 50; ++k) call(s, 1000, 2, [](std::size_t i) { return i >= 990 ? 1e-9 : 0.0; });
  EXPECT_NEAR(s.cuts(1000, 2)[0], 1.0 - 1.0 / 16.0, 1e-12);
  for (int k = 0; k < 50; ++k) call(s, 1000, 2, [](std::size_t i) { return i < 10 ? 1e-9 : 0.0; });
  EXPECT_NEAR(s.cuts(1000, 2)[0], 1.0 / 16.0, 1e-12);
  expect_tiling(s, 1000, 2);
}

TEST(LoopSplit, FloorsKeepTheCutsInOrderOnLargerTeams) {
  // all the cost in the last item: every cut is pushed up against the floors of the blocks after
  // it, and the cuts stay strictly increasing with each block at least 1/(8T)
  for (int T : {3, 5, 8}) {
    LoopSplit s;
    const std::size_t n = 100000;
    for (int k = 0; k < 80; ++k) call(s, n, T, [&](std::size_t i) { return i + 1 == n ? 1e-6 : 0.0; });
    const std::vector<double> c = s.cuts(n, T);
    ASSERT_EQ(c.size(), static_cast<std::size_t>(T - 1));
    const double floor_len = 1.0 / (8.0 * T);
    double prev = 0.0;
    for (int j = 0; j < T - 1; ++j) {
      EXPECT_GE(c[static_cast<std::size_t>(j)] - prev, floor_len * (1 - 1e-9)) << "T " << T << " cut " << j;
      prev = c[static_cast<std::size_t>(j)];
    }
    EXPECT_NEAR(1.0 - prev, floor_len, 1e-9) << "T " << T;
    expect_tiling(s, n, T);
  }
}

TEST(LoopSplit, TilesShortAndEmptyLoopsAfterTheCutsMoved) {
  LoopSplit s;
  for (int k = 0; k < 20; ++k) call(s, 5, 8, [](std::size_t i) { return i < 1 ? 1e-6 : 1e-9; });
  expect_tiling(s, 5, 8);
  expect_tiling(s, 3, 8);
  expect_tiling(s, 0, 8);
  call(s, 0, 8, [](std::size_t) { return 1e-9; });  // nothing to measure: no change, no crash
  expect_tiling(s, 0, 8);
}

TEST(LoopSplit, ASmallerTeamThanAskedTunesItsOwnCuts) {
  // begin() was told 3 threads (omp_get_max_threads), the region got 2: their cuts move, the
  // 3-thread cuts stay uniform
  const std::size_t n = 30000;
  LoopSplit s;
  for (int k = 0; k < 30; ++k) {
    s.begin(n, 3);
    for (int t = 0; t < 2; ++t) {
      std::size_t lo, hi;
      s.block(n, t, 2, lo, hi);
      double time = 0.0;
      for (std::size_t i = lo; i < hi; ++i) time += i < n / 2 ? 3e-9 : 1e-9;
      s.record(t, time);
    }
    s.end();
  }
  EXPECT_NEAR(s.cuts(n, 2)[0], 1.0 / 3.0, 3e-3);
  EXPECT_NEAR(s.cuts(n, 3)[0], 1.0 / 3.0, 1e-15);
  EXPECT_NEAR(s.cuts(n, 3)[1], 2.0 / 3.0, 1e-15);
  // and back on 3 threads, the 2-thread cuts are kept apart from the new ones
  for (int k = 0; k < 30; ++k) call(s, n, 3, [&](std::size_t i) { return i < n / 2 ? 3e-9 : 1e-9; });
  EXPECT_NEAR(s.cuts(n, 3)[0], 2.0 / 9.0, 3e-3);  // cumulative 6x over the first half
  EXPECT_NEAR(s.cuts(n, 3)[1], 4.0 / 9.0, 3e-3);
}

TEST(LoopSplit, NonFiniteTimesMoveNothing) {
  LoopSplit s;
  for (double bad : {std::numeric_limits<double>::infinity(), std::numeric_limits<double>::quiet_NaN()}) {
    s.begin(1000, 2);
    s.record(0, 1e-6);
    s.record(1, bad);
    s.end();
    EXPECT_EQ(s.cuts(1000, 2)[0], 0.5);
  }
}

TEST(LoopSplit, PinnedCutsOverrideAndFreeze) {
  LoopSplit s;
  LoopSplit::pinned() = {0.1};
  std::size_t lo, hi;
  s.block(1000, 0, 2, lo, hi);
  EXPECT_EQ(hi, 100u);
  call(s, 1000, 2, [](std::size_t i) { return i < 500 ? 3e-9 : 1e-9; });
  LoopSplit::pinned().clear();
  EXPECT_EQ(s.cuts(1000, 2)[0], 0.5);  // nothing was learnt while pinned
}
