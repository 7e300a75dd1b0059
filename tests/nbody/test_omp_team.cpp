/// @file test_omp_team.cpp
/// OpenMP regions entered only where they pay (nbody/src/omp_team.hpp): with the thresholds at
/// 1, every region that omp_team.hpp decides runs on a team of 3 threads; the same run on one
/// thread starts no such region. Both must give the same spheres, levels, level statistics and
/// contact statistics bit for bit, single rate and multi rate, with a floor and an adaptive
/// gravity cadence, so that no region's conversion (its static blocks, its thread-local sums,
/// its merged statistics) changes a result.
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <vector>

#include "../../nbody/src/omp_team.hpp"
#include "ssdem/dt_rule.hpp"
#include "ssdem/generators.hpp"
#include "ssdem/loop_split.hpp"
#include "ssdem/simulation.hpp"

using namespace ssdem;

namespace {

// Thread count and thresholds for one scope, restored on every path out of it.
struct TeamSetting {
  int old_threads = omp_get_max_threads();
  TeamThresholds old_thresholds = team_thresholds();
  TeamSetting(int threads, TeamThresholds t) {
    omp_set_num_threads(threads);
    team_thresholds() = t;
  }
  ~TeamSetting() {
    omp_set_num_threads(old_threads);
    team_thresholds() = old_thresholds;
  }
};

// A pile (FCC, radius 6 m, spheres of 1 m) on a floor that its lowest spheres overlap by 2 cm,
// and a sparse cloud of 60 spheres of 0.6 m (a ball of 6 m) 2 m away flying into it at 10 m/s;
// self-gravity by the tree with the error-controlled cadence; k_n for 3 m/s at 1 % overlap.
SimConfig scene(Spheres& sp, bool multirate) {
  sp = lattice_pile(6.0, 1.0, 2000.0, 0.05, 11);
  double zmin = 0;
  for (std::size_t i = 0; i < sp.size(); ++i) zmin = std::min(zmin, sp.x[i].z() - sp.s[i]);
  append_body(sp, random_cloud(60, 6.0, 0.6, 2000.0, 12), Vec3(14.0, 1.0, 0.5), Vec3(-10.0, 0, 0));
  SimConfig c;
  c.contacts = true;
  c.contact = gravel_preset(choose_kn_dt(sp.m[0], 1.0, 3.0, 0.55).kn);
  c.dt = shortest_contact_time(c.contact, sp, false) / 30.0;
  c.self_gravity = true;
  c.adaptive_gravity = true;
  c.gravity_every = 1;
  c.walls.push_back(Plane{Vec3(0, 0, zmin + 0.02), Vec3::UnitZ()});
  c.multirate = multirate;
  c.pair_steps_per_contact = 30.0;
  c.teams = TeamMode::size;  // the thresholds each run sets hold for all its steps
  return c;
}

struct Result {
  Spheres sp;
  std::vector<std::uint8_t> levels;
  LevelStats ls;
  ContactStats cs;  // summed over the steps (max_overlap_frac and the worst pair: the last step's)
};

// rotate > 0: the team rules in turn, each for `rotate` base steps (TeamTuner::force_rotation)
Result run(const Spheres& sp, const SimConfig& c, int threads, TeamThresholds t, int steps, int rotate = 0) {
  const TeamSetting setting(threads, t);
  Simulation sim(sp, c);
  if (rotate > 0) sim.team_tuner().force_rotation(rotate);
  ContactStats sum;
  for (int k = 0; k < steps; ++k) {
    sim.step();
    const ContactStats& s = sim.contact_stats();
    sum.contacts += s.contacts;
    sum.wall_contacts += s.wall_contacts;
    sum.kernel_pairs += s.kernel_pairs;
    sum.max_overlap_frac = s.max_overlap_frac;
    sum.worst_a = s.worst_a;
    sum.worst_b = s.worst_b;
  }
  return Result{sim.spheres(), sim.levels(), sim.level_stats(), sum};
}

void expect_same(const Result& a, const Result& b) {
  ASSERT_EQ(a.sp.size(), b.sp.size());
  std::size_t d = 0;
  for (std::size_t i = 0; i < a.sp.size(); ++i)
    if (a.sp.x[i] != b.sp.x[i] || a.sp.v[i] != b.sp.v[i] || a.sp.w[i] != b.sp.w[i] ||
        a.sp.dissipated[i] != b.sp.dissipated[i])
      ++d;
  EXPECT_EQ(d, 0u);
  EXPECT_EQ(a.levels, b.levels);
  EXPECT_EQ(a.ls.sphere_time, b.ls.sphere_time);
  EXPECT_EQ(a.ls.evaluations, b.ls.evaluations);
  EXPECT_EQ(a.ls.promotions, b.ls.promotions);
  EXPECT_EQ(a.cs.contacts, b.cs.contacts);
  EXPECT_EQ(a.cs.wall_contacts, b.cs.wall_contacts);
  EXPECT_EQ(a.cs.kernel_pairs, b.cs.kernel_pairs);
  EXPECT_EQ(a.cs.max_overlap_frac, b.cs.max_overlap_frac);
  EXPECT_EQ(a.cs.worst_a, b.cs.worst_a);
  EXPECT_EQ(a.cs.worst_b, b.cs.worst_b);
}

// One thread (no region started by omp_team.hpp) against every such region on a team of 3.
void serial_equals_teams(bool multirate, int steps) {
  Spheres sp;
  const SimConfig c = scene(sp, multirate);
  const Result serial = run(sp, c, 1, TeamThresholds{}, steps);
  const Result teams = run(sp, c, 3, TeamThresholds{1, 1}, steps);
  // the listed opening kicks and level assignments shared by count at every step (for_joined_share)
  const Result shared = run(sp, c, 3, TeamThresholds{1, 1, 0, 0}, steps);
  EXPECT_GT(serial.cs.contacts, 0u);
  EXPECT_GT(serial.cs.wall_contacts, 0u);
  int levels_used = 0;
  for (double t : serial.ls.sphere_time) levels_used += t > 0 ? 1 : 0;
  std::printf("%s: %zu spheres, %zu contact-steps, %zu on the floor, %lld evaluations, %lld promotions, %d levels\n",
              multirate ? "multi-rate" : "single rate", sp.size(), serial.cs.contacts, serial.cs.wall_contacts,
              static_cast<long long>(serial.ls.evaluations), static_cast<long long>(serial.ls.promotions), levels_used);
  if (multirate) {  // the cloud on long steps, promoted as it reaches the pile
    EXPECT_GE(levels_used, 3);
    EXPECT_GT(serial.ls.promotions, 0);
  }
  expect_same(serial, teams);
  expect_same(serial, shared);
}

}  // namespace

TEST(OmpTeam, ThresholdsDecideBeforeTheRegion) {
  {
    const TeamSetting two(2, TeamThresholds{});
    EXPECT_FALSE(use_team(2047, Work::items));
    EXPECT_TRUE(use_team(2048, Work::items));
    EXPECT_FALSE(use_team(16383, Work::stream));
    EXPECT_TRUE(use_team(16384, Work::stream));
  }
  {
    const TeamSetting one(1, TeamThresholds{});  // one thread: never a region, whatever the work
    EXPECT_FALSE(use_team(1u << 30, Work::items));
  }
  // for_blocks covers every index once, in consecutive blocks, on a team or not; below the
  // threshold it starts no region at all (omp_get_level() is 1 in a region of one thread too)
  std::vector<int> hits(1000, 0);
  int level = -1, blocks = 0;
  auto visit = [&](std::size_t lo, std::size_t hi) {
    for (std::size_t i = lo; i < hi; ++i) ++hits[i];
#pragma omp critical(test_omp_team)
    {
      ++blocks;
      if (lo == 0) level = omp_get_level();
    }
  };
  {
    const TeamSetting teams(3, TeamThresholds{1, 1});
    for_blocks(hits.size(), Work::items, visit);
  }
  EXPECT_EQ(level, 1);
  EXPECT_EQ(blocks, 3);
  for (int h : hits) EXPECT_EQ(h, 1);
  blocks = 0;
  {
    const TeamSetting defaults(3, TeamThresholds{});
    for_blocks(hits.size(), Work::items, visit);  // 1 000 items: below the threshold
  }
  EXPECT_EQ(level, 0);
  EXPECT_EQ(blocks, 1);
  for (int h : hits) EXPECT_EQ(h, 2);
  // called from inside a parallel region, a body that runs alone gets a region of its own, so an
  // orphaned `omp for` in it covers every index on that one thread
  std::vector<int> seen(2, 0);
#pragma omp parallel num_threads(2)
  {
    const int t = omp_get_thread_num();
    in_team(false, [&] {
      int count = 0;
#pragma omp for schedule(static)
      for (int i = 0; i < 100; ++i) ++count;
      seen[static_cast<std::size_t>(t)] = count;
    });
  }
  EXPECT_EQ(seen[0], 100);
  EXPECT_EQ(seen[1], 100);
}

TEST(OmpTeam, MultirateStepsOnTeamsEqualTheSerialBits) { serial_equals_teams(true, 3000); }

TEST(OmpTeam, SingleRateStepsOnTeamsEqualTheSerialBits) { serial_equals_teams(false, 400); }

// The contact loops' blocks (loop_split.hpp) decide only who computes what: with the cuts pinned
// to extremes (thread 2, then thread 0, with 90 % of every loop) the steps give the serial bits.
TEST(OmpTeam, ExtremeLoopCutsEqualTheSerialBits) {
  Spheres sp;
  const SimConfig c = scene(sp, true);
  const Result serial = run(sp, c, 1, TeamThresholds{}, 1500);
  for (std::vector<double> cuts : {std::vector<double>{0.05, 0.1}, std::vector<double>{0.9, 0.95}}) {
    LoopSplit::pinned() = cuts;
    const Result skewed = run(sp, c, 3, TeamThresholds{1, 1}, 1500);
    LoopSplit::pinned().clear();
    expect_same(serial, skewed);
  }
}

// The measured team rule (team_tuner.hpp) changes the rule between base steps: every rule, each
// switched to in mid-run, and the measured choice itself must give the serial bits.
TEST(OmpTeam, TeamRulesSwitchedInMidRunEqualTheSerialBits) {
  Spheres sp;
  SimConfig c = scene(sp, true);
  const Result serial = run(sp, c, 1, TeamThresholds{}, 3000);
  // the size rule at 64 items and 256 for passes over every sphere: with the 147 spheres, the
  // three rules put different loops on the team; 7: switches at odd steps
  const Result rotated = run(sp, c, 3, TeamThresholds{64, 256}, 3000, 7);
  expect_same(serial, rotated);
  c.teams = TeamMode::automatic;
  const Result measured = run(sp, c, 3, TeamThresholds{64, 256}, 3000);
  expect_same(serial, measured);
  // a simulation's tuner restores the thresholds it found when it ends, whatever rule it set
  const TeamSetting setting(3, TeamThresholds{64, 256});
  {
    Simulation sim(sp, c);
    sim.team_tuner().force(TeamTuner::one_thread);
    sim.step();
    EXPECT_EQ(team_thresholds().items, static_cast<std::size_t>(-1));
  }
  EXPECT_EQ(team_thresholds().items, 64u);
  EXPECT_EQ(team_thresholds().stream, 256u);
}

// for_joined_share: every listed item once, each thread's share within one of an equal split,
// whatever the lists' sizes (all items in one thread's list: the pile in one block; empty lists;
// fewer items than threads).
TEST(OmpTeam, JoinedListsAreSharedByCount) {
  const int T = 3;
  for (const std::vector<std::size_t>& sizes : {std::vector<std::size_t>{0, 1000, 0}, std::vector<std::size_t>{7, 0, 2},
                                               std::vector<std::size_t>{1, 0, 0}, std::vector<std::size_t>{0, 0, 0},
                                               std::vector<std::size_t>{333, 334, 335}}) {
    std::vector<std::vector<std::uint32_t>> lists(T);
    std::uint32_t next = 0;
    for (int k = 0; k < T; ++k)
      for (std::size_t r = 0; r < sizes[static_cast<std::size_t>(k)]; ++r) lists[static_cast<std::size_t>(k)].push_back(next++);
    std::vector<int> hits(next, 0), owner(next, -1);
    std::vector<std::size_t> share(T, 0);
    for (int t = 0; t < T; ++t)  // (each thread's share is a function of t alone: call them in turn)
      for_joined_share(lists.data(), t, T, [&](std::uint32_t i) {
        ++hits[i];
        owner[i] = t;
        ++share[static_cast<std::size_t>(t)];
      });
    for (int h : hits) EXPECT_EQ(h, 1);
    const std::size_t m = next;
    for (int t = 0; t < T; ++t) {
      EXPECT_GE(share[static_cast<std::size_t>(t)], m / T);
      EXPECT_LE(share[static_cast<std::size_t>(t)], (m + T - 1) / T);
    }
    for (std::size_t i = 1; i < m; ++i) EXPECT_LE(owner[i - 1], owner[i]);  // consecutive shares
  }
}
