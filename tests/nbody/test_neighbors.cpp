/// @file test_neighbors.cpp
/// Neighbour list (contacts.hpp): no contact is ever missed by the incremental pair list, contact
/// history survives local updates bit for bit (against a list rebuilt from scratch every step, the
/// old behaviour), and on debris (few fast, many slow) full rebuilds are rare.
#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "ssdem/contact_params.hpp"
#include "ssdem/contacts.hpp"
#include "ssdem/generators.hpp"
#include "../../nbody/src/omp_team.hpp"

using namespace ssdem;

namespace {

// Pile of radius R (spheres of radius 1) with per-sphere velocities log-uniform in [vlo, vhi]
// in random directions (kinematic: they pass through each other, which is fine for the list).
Spheres moving_pile(double R, double vlo, double vhi, std::uint64_t seed) {
  Spheres sp = lattice_pile(R, 1.0, 2000.0, 0.05, seed);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  for (std::size_t i = 0; i < sp.size(); ++i) {
    Vec3 d(U(rng) - 0.5, U(rng) - 0.5, U(rng) - 0.5);
    sp.v[i] = vlo * std::pow(vhi / vlo, U(rng)) * d.normalized();
  }
  return sp;
}

// Every pair with a gap below g (brute force O(N^2); g = 0: every overlapping pair) must be in the
// list; returns the number missed and adds the number of such pairs to `found`.
std::size_t missed(const ContactSystem& cs, const Spheres& sp, std::size_t& found, double g = 0.0) {
  std::size_t miss = 0;
  for (std::size_t i = 0; i < sp.size(); ++i)
    for (std::size_t j = i + 1; j < sp.size(); ++j) {
      const double r = sp.s[i] + sp.s[j] + g;
      if ((sp.x[j] - sp.x[i]).squaredNorm() < r * r) {
        ++found;
        if (!cs.listed(i, j)) ++miss;
      }
    }
  return miss;
}

ContactParams linear(unsigned parts) {
  ContactParams p;
  p.parts = parts;
  p.kn = 1e7;
  p.en = 0.5;
  p.et = 0.5;
  p.mu_s = 0.6;
  p.mu_r = 0.1;
  p.mu_t = 0.1;
  return p;
}

}  // namespace

// A 5 km/s fragment through a pile and a 100 m/s one into it, pile spheres moving at 0.1-50 m/s
// (so local updates happen every step, in varying subsets): no overlapping pair is ever unlisted,
// and with re-insertion at skin/4 (multi-rate) no pair closer than skin/2 either, although new
// pairs wait to be merged until one is that close.
TEST(Neighbors, NoMissedContactFastFragments) {
  for (bool margins : {true, false})  // isolated spheres' margins (contacts.hpp) on and off
  for (double f : {0.5, 0.25})
  for (double skin : {0.0, 0.1, 0.5, 2.0}) {
    Spheres sp = moving_pile(6.0, 0.1, 50.0, 7);
    const std::size_t n0 = sp.size();
    sp.push(1000000, Vec3(-20.0, 0.3, 0.2), Vec3(5000.0, 0, 0), Vec3::Zero(), 1.0, 0.8);
    sp.push(1000001, Vec3(0.4, -8.5, 0.1), Vec3(0, 100.0, 0), Vec3::Zero(), 1.0, 1.2);
    ContactSystem cs(linear(0), {}, skin);
    cs.set_reinsert_fraction(f);
    cs.set_margins(margins);
    const double dt = 1e-4;  // fast fragment: 0.5 m per step; pile: up to 0.005 m per step
    std::size_t found = 0, fast_found = 0, miss = 0;
    for (int step = 0; step < 600; ++step) {
      cs.update_neighbors(sp);
      miss += missed(cs, sp, found, (1.0 - 2.0 * f) * skin);
      for (std::size_t i = 0; i < n0; ++i)
        for (std::size_t k : {n0, n0 + 1}) {
          const double r = sp.s[i] + sp.s[k];
          if ((sp.x[k] - sp.x[i]).squaredNorm() < r * r) ++fast_found;
        }
      for (std::size_t i = 0; i < sp.size(); ++i) sp.x[i] += dt * sp.v[i];
    }
    EXPECT_EQ(miss, 0u) << "skin " << skin << ", re-insertion at " << f << " skin, margins " << margins;
    EXPECT_GT(found, 1000u);
    EXPECT_GT(fast_found, 50u) << "the fragments must actually meet the pile";
    EXPECT_GT(cs.reinsert_count() + cs.rebuild_count(), 50u);
    if (margins && skin > 0.0) {  // (skin 0: every moving sphere re-inserts, a rebuild each step)
      EXPECT_GT(cs.margin_count(), 0u) << "the fragments fly alone first: they take margins";
    } else if (!margins) {
      EXPECT_EQ(cs.margin_count(), 0u);
    }
    if (skin > 0.0) {
      EXPECT_LT(cs.rebuild_count(), 600u / 4) << "skin " << skin;
    }
  }
}

namespace {

struct DemRun {
  Spheres sp;
  ContactSystem cs;
  std::vector<Vec3> F, T;
};

// Symplectic Euler with the contact forces of `cs`; force_rebuild: rebuild the list from scratch
// every step (the old behaviour whenever any sphere had moved more than skin/2).
void step(DemRun& r, double dt, bool force_rebuild) {
  r.cs.update_neighbors(r.sp, force_rebuild);
  r.cs.compute(r.sp, r.sp.v, r.sp.w, dt, r.F, r.T);
  for (std::size_t i = 0; i < r.sp.size(); ++i) {
    r.sp.v[i] += dt * r.F[i] / r.sp.m[i];
    r.sp.w[i] += dt * r.T[i] / r.sp.inertia(i);
    r.sp.x[i] += dt * r.sp.v[i];
  }
}

}  // namespace

// Full history (tangential spring, rolling, twisting, damping) through local updates: a pile whose
// spheres collide with each other, an oblique 5 m/s fragment and spheres flying past the contact
// region, against the same run with the list rebuilt from scratch every step. Trajectories and
// the exported history must agree bit for bit.
TEST(Neighbors, HistoryBitIdenticalToRebuildEveryStep) {
  const unsigned parts = kPartDamping | kPartTangential | kPartRolling | kPartTwisting;
  Spheres sp = moving_pile(4.0, 0.05, 1.0, 3);
  const double m = 2000.0 * 4.0 / 3.0 * M_PI;
  sp.push(500000, Vec3(-7.0, 1.1, 0.3), Vec3(5.0, 0.0, 0.0), Vec3(0, 0, 1.0), m, 1.0);
  for (int k = 0; k < 6; ++k)  // through the pile, re-inserted every few steps: new pairs
    sp.push(600000 + k, Vec3(-9.0 + 0.4 * k, -3.0 + 1.2 * k, -1.0 + 0.3 * k),
            Vec3(3.0 + k, 0.0, 0.0), Vec3::Zero(), m, 1.0);
  DemRun a{sp, ContactSystem(linear(parts), {}, 0.1), {}, {}};
  DemRun b{sp, ContactSystem(linear(parts), {}, 0.1), {}, {}};
  const double dt = 5e-4;  // ~130 steps per contact
  std::size_t diff = 0, contacts = 0;
  for (int s = 0; s < 2000; ++s) {
    step(a, dt, false);
    step(b, dt, true);
    for (std::size_t i = 0; i < sp.size(); ++i)
      for (int c = 0; c < 3; ++c)
        if (a.sp.x[i][c] != b.sp.x[i][c] || a.sp.w[i][c] != b.sp.w[i][c]) ++diff;
    contacts += a.cs.export_history(a.sp).size();
  }
  EXPECT_EQ(diff, 0u);
  const auto ha = a.cs.export_history(a.sp), hb = b.cs.export_history(b.sp);
  ASSERT_EQ(ha.size(), hb.size());
  for (std::size_t k = 0; k < ha.size(); ++k) {
    EXPECT_EQ(ha[k].id_a, hb[k].id_a);
    EXPECT_EQ(ha[k].id_b, hb[k].id_b);
    EXPECT_TRUE(ha[k].vec("S") == hb[k].vec("S"));
    EXPECT_TRUE(ha[k].vec("theta_r") == hb[k].vec("theta_r"));
    EXPECT_EQ(ha[k].scal("theta_q"), hb[k].scal("theta_q"));
  }
  EXPECT_GT(contacts, 3000u) << "the test must have contacts with history";
  std::printf("merges %zu, re-insertions %zu, full rebuilds %zu\n", a.cs.local_update_count(),
              a.cs.reinsert_count(), a.cs.rebuild_count());
  // (new pairs wait until one is in contact and are then merged together: few merges)
  EXPECT_GE(a.cs.local_update_count(), 1u) << "the test must exercise merges";
  EXPECT_LT(a.cs.rebuild_count(), 100u);  // vs 2000
  EXPECT_EQ(b.cs.rebuild_count(), 2000u);
}

// Oblique contact of two spheres with the tangential spring while both are re-inserted during the
// contact and a third sphere changes their pair set: S continues exactly as with full rebuilds.
TEST(Neighbors, TangentialSpringContinuity) {
  const double m = 2000.0 * 4.0 / 3.0 * M_PI;
  Spheres sp;
  sp.push(1, Vec3(-0.95, 0.0, 0.0), Vec3(1.0, 0.0, 0.0), Vec3::Zero(), m, 1.0);
  sp.push(2, Vec3(0.95, 0.9, 0.0), Vec3(-1.0, 0.0, 0.0), Vec3::Zero(), m, 1.0);
  sp.push(3, Vec3(-0.3, 2.905, 0.0), Vec3(3.0, 0.0, 0.0), Vec3::Zero(), m, 1.0);  // flies past
  const ContactParams p = linear(kPartTangential);
  DemRun a{sp, ContactSystem(p, {}, 0.02), {}, {}};
  DemRun b{sp, ContactSystem(p, {}, 0.02), {}, {}};
  const double dt = 2e-4;
  int in_contact = 0;
  double smax = 0.0;
  for (int s = 0; s < 4000; ++s) {
    step(a, dt, false);
    step(b, dt, true);
    const auto ha = a.cs.export_history(a.sp), hb = b.cs.export_history(b.sp);
    ASSERT_EQ(ha.size(), hb.size()) << "step " << s;
    for (std::size_t k = 0; k < ha.size(); ++k) {
      ASSERT_TRUE(ha[k].vec("S") == hb[k].vec("S")) << "step " << s;
      smax = std::max(smax, ha[k].vec("S").norm());
    }
    in_contact += !ha.empty();
  }
  EXPECT_GT(in_contact, 50);
  EXPECT_GT(smax, 1e-4) << "the spring must be loaded";
  std::printf("merges %zu, re-insertions %zu\n", a.cs.local_update_count(), a.cs.reinsert_count());
  EXPECT_GE(a.cs.local_update_count(), 1u);
  EXPECT_GE(a.cs.reinsert_count(), 20u);
  EXPECT_EQ(a.cs.rebuild_count(), 1u);
}

// Debris-like set: 1000 slow spheres (0.001-0.01 m/s) and 5 fragments at 1 km/s. The old rule
// (any sphere moved more than skin/2 -> rebuild) rebuilt every step; now only the fragments are
// re-inserted and full rebuilds are rare.
TEST(Neighbors, FewRebuildsOnDebris) {
  Spheres sp = moving_pile(7.0, 0.001, 0.01, 11);
  for (int k = 0; k < 5; ++k)
    sp.push(900000 + k, Vec3(10.0 + k, 3.0 * k, 0.0),
            1000.0 * Vec3(1.0, 0.1 * k, -0.05 * k).normalized(), Vec3::Zero(), 1.0, 0.5);
  const Spheres start = sp;
  const double dt = 1e-3;
  const int steps = 1000;
  {
    ContactSystem cs(linear(0), {}, 0.1);
    cs.set_margins(false);
    for (int s = 0; s < steps; ++s) {
      cs.update_neighbors(sp);
      for (std::size_t i = 0; i < sp.size(); ++i) sp.x[i] += dt * sp.v[i];
    }
    EXPECT_LE(cs.rebuild_count(), 5u);                 // vs `steps` with the old rule
    EXPECT_GE(cs.reinsert_count(), 5u * (steps - 1));  // the fragments, every step
    EXPECT_LT(cs.reinsert_count(), 5u * steps + sp.size());
  }
  // With margins (the default) a lone fragment, 1 m per step, is re-inserted once its travel
  // passes f k + M = 0.05 + (2 s_max + k) = 2.15 m, every third step, and takes the margin again
  // each time once the five have drifted apart.
  sp = start;
  ContactSystem cs(linear(0), {}, 0.1);
  for (int s = 0; s < steps; ++s) {
    cs.update_neighbors(sp);
    for (std::size_t i = 0; i < sp.size(); ++i) sp.x[i] += dt * sp.v[i];
  }
  EXPECT_LE(cs.rebuild_count(), 5u);
  EXPECT_GE(cs.reinsert_count(), 5u * (steps / 3 - 1));
  EXPECT_LT(cs.reinsert_count(), 5u * (steps / 3 + 1) + sp.size());
  EXPECT_GE(cs.margin_count(), 5u * (steps / 3) * 9 / 10);
  EXPECT_EQ(cs.fast_spheres(), 5u);
}

// A rebuilt list holds exactly the pairs within reach (|x_i - x_j| < s_i + s_j + skin), against
// brute force on polydisperse spheres (radii 0.2-3, reach often far below the cell edge
// 2 s_max + skin), far from the origin (rounding of the cell index), with a third of them moved
// onto cell faces, edges and corners, and after re-insertions of a moving subset (the cell
// table's erase and insert, cell_table.hpp).
TEST(Neighbors, ListIsExactlyThePairsWithinReach) {
  for (double origin : {0.0, -3.7e6, 5.5e6}) {  // (|x| / c < 2^20: no cell index clamped)
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> U(0.0, 1.0);
    Spheres sp;
    const std::size_t n = 3000;
    for (std::size_t i = 0; i < n; ++i) {
      const double s = 0.2 * std::pow(15.0, U(rng));
      sp.push(static_cast<std::uint64_t>(i), Vec3(origin + 40.0 * U(rng), origin + 40.0 * U(rng), origin + 40.0 * U(rng)),
              Vec3::Zero(), Vec3::Zero(), 1000.0 * s * s * s, s);
    }
    const double skin = 0.7;
    ContactSystem cs(linear(0), {}, skin);
    cs.set_reinsert_fraction(0.25);  // multi-rate's: every pair with a gap below skin/2 listed
    cs.update_neighbors(sp, true);
    const double c = cs.cell_edge();
    for (std::size_t i = 0; i < n; i += 3)  // onto a face, an edge or a corner of the grid
      for (int a = 0; a < 1 + static_cast<int>(i % 9) / 3; ++a) sp.x[i][a] = std::round(sp.x[i][a] / c) * c;
    auto check = [&](const char* what) {
      std::size_t within = 0, wrong = 0;
      for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = i + 1; j < n; ++j) {
          const double r = sp.s[i] + sp.s[j] + skin;
          const bool in = (sp.x[j] - sp.x[i]).squaredNorm() < r * r;
          within += in;
          wrong += in != cs.listed(i, j);
        }
      EXPECT_EQ(wrong, 0u) << what << ", origin " << origin << ": " << within << " pairs within reach";
      EXPECT_GT(within, 2 * n);  // the test has pairs to find
    };
    cs.update_neighbors(sp, true);
    EXPECT_NEAR(cs.cell_edge(), c, 1e-12 * c);
    check("rebuilt");
    for (std::size_t i = 1; i < n; i += 5) sp.x[i] += Vec3(0.4, -0.3, 0.5);  // past skin/4: re-inserted
    EXPECT_FALSE(cs.update_neighbors(sp));  // a local update (a fifth moved)
    // it lists every pair with a gap below skin/2 (new pairs farther apart wait to be merged);
    // a rebuild from the same positions gives exactly the pairs within reach again
    std::size_t found = 0;
    const std::size_t missed_pairs = missed(cs, sp, found, 0.5 * skin);
    EXPECT_GT(found, n / 2);
    EXPECT_EQ(missed_pairs, 0u) << "origin " << origin << ", after re-insertion";
    cs.update_neighbors(sp, true);
    check("rebuilt after moves");
  }
}

// Contacts that only the isolated spheres' grid can reveal (contacts.hpp, "Isolated spheres"):
// two lone fragments on a head-on course, each holding a margin long before they meet, and a
// touching cluster drifting onto a slow lone sphere that holds one (the cluster's spheres find it
// only by searching that grid: it is not re-inserted again). No pair closer than (1 - 2 f) k may be
// unlisted at any step, and the spheres must have held margins and must meet.
TEST(Neighbors, NoMissedContactWithSpheresHoldingMargins) {
  for (double f : {0.5, 0.25}) {
    Spheres sp;
    sp.push(1, Vec3(-40.0, 0.0, 0.0), Vec3(30.0, 0.0, 0.0), Vec3::Zero(), 1.0, 1.0);
    sp.push(2, Vec3(40.0, 0.3, 0.0), Vec3(-30.0, 0.0, 0.0), Vec3::Zero(), 1.0, 1.0);
    // the lone one, slow: re-inserted once after f k (it then takes the margin, and its next
    // re-insertion, after f k + 2.4 m at 0.1 m/s, is beyond the test's 12 s)
    sp.push(3, Vec3(0.0, 60.0, 0.0), Vec3(0.1, 0.0, 0.0), Vec3::Zero(), 1.0, 1.0);
    for (int a = 0; a < 3; ++a)  // a touching cluster of 9 drifting towards it at 2 m/s
      for (int b = 0; b < 3; ++b)
        sp.push(10 + 3 * a + b, Vec3(-1.9 + 1.95 * a, 75.0 + 1.95 * b, 0.0), Vec3(0.0, -2.0, 0.0), Vec3::Zero(), 1.0,
                1.0);
    const double skin = 0.4;
    ContactSystem cs(linear(0), {}, skin);
    cs.set_reinsert_fraction(f);
    const double dt = 2e-3;
    std::size_t found = 0, miss = 0;
    bool held_margins = false, head_on = false, cluster_met = false;
    for (int step = 0; step < 6000; ++step) {
      cs.update_neighbors(sp);
      held_margins = held_margins || cs.fast_spheres() >= 3;
      miss += missed(cs, sp, found, (1.0 - 2.0 * f) * skin);
      head_on = head_on || (sp.x[1] - sp.x[0]).norm() < 2.0;
      for (std::size_t k = 3; k < sp.size(); ++k) cluster_met = cluster_met || (sp.x[k] - sp.x[2]).norm() < 2.0;
      for (std::size_t i = 0; i < sp.size(); ++i) sp.x[i] += dt * sp.v[i];
    }
    EXPECT_EQ(miss, 0u) << "f " << f;
    EXPECT_TRUE(held_margins) << "f " << f;
    EXPECT_TRUE(head_on) << "the fragments must meet";
    EXPECT_TRUE(cluster_met) << "the cluster must reach the lone sphere";
    EXPECT_GT(found, 100u);
  }
}

// The searches around re-inserted spheres run on a team (ContactSystem::search_moved) and the
// margins are then given in ascending order, as one loop of search and margin would: a pile at
// rest, and far from it lone spheres re-inserted in one update: pairs 6 m apart (spheres of 1 m,
// skin 0.4, margin M = c = 2.4: each is isolated while neither holds a margin, 6 > 4.8, but once
// the first takes one the second is not, 6 < 7.2: one margin per pair), singles (one each) and
// pairs 4 m apart (none: 4 < 4.8). One thread and a team of 3 with every region on a team must
// give these margins and the same list.
TEST(Neighbors, SearchesOnATeamGiveTheMarginsInOrder) {
  Spheres base = lattice_pile(10.0, 1.0, 2000.0, 0.05, 5);
  const std::size_t npile = base.size();
  std::uint64_t id = 100000;
  auto lone = [&](const Vec3& x) { base.push(id++, x, Vec3::Zero(), Vec3::Zero(), 1.0, 1.0); };
  for (int k = 0; k < 30; ++k) {  // the first of each takes the margin: its index is the lower
    lone(Vec3(100.0 + 30.0 * k, 0.0, 0.0));
    lone(Vec3(100.0 + 30.0 * k, 6.0, 0.0));
  }
  for (int k = 0; k < 10; ++k) lone(Vec3(100.0 + 30.0 * k, 60.0, 0.0));
  for (int k = 0; k < 10; ++k) {
    lone(Vec3(100.0 + 30.0 * k, 120.0, 0.0));
    lone(Vec3(100.0 + 30.0 * k, 124.0, 0.0));
  }
  for (int k = 0; k < 10; ++k) {  // and touching pairs that move with them (their pairs listed)
    lone(Vec3(100.0 + 30.0 * k, 180.0, 0.0));
    lone(Vec3(100.0 + 30.0 * k, 181.9, 0.0));
  }
  ASSERT_LE(4 * (base.size() - npile), base.size()) << "a local update, not a rebuild";
  struct Out {
    std::size_t margins = 0, fast = 0;
    std::vector<std::uint8_t> listed, margin;
  };
  struct Setting {  // thread count and thresholds for one run, restored on every path out of it
    int threads = omp_get_max_threads();
    TeamThresholds t = team_thresholds();
    ~Setting() {
      omp_set_num_threads(threads);
      team_thresholds() = t;
    }
  };
  auto run = [&](int threads, TeamThresholds t) {
    const Setting restore;
    omp_set_num_threads(threads);
    team_thresholds() = t;
    Spheres sp = base;
    ContactSystem cs(linear(0), {}, 0.4);
    cs.update_neighbors(sp, true);
    Out o;
    for (int round = 0; round < 3; ++round) {  // past f k + M = 2.6: every lone sphere re-inserted
      for (std::size_t i = npile; i < sp.size(); ++i) sp.x[i] += Vec3(0.0, 0.0, 3.0);
      EXPECT_FALSE(cs.update_neighbors(sp)) << "round " << round << ": a local update";
      o.margins = cs.margin_count();
      o.fast = cs.fast_spheres();
      EXPECT_EQ(o.fast, 30u + 10u) << "round " << round << ", " << threads << " thread(s)";
    }
    for (std::size_t i = 0; i < sp.size(); ++i) {
      o.margin.push_back(cs.holds_margin(i) ? 1 : 0);
      for (std::size_t j = i + 1; j < sp.size(); ++j) o.listed.push_back(cs.listed(i, j) ? 1 : 0);
    }
    for (std::size_t k = 0; k < 30; ++k) {
      EXPECT_TRUE(cs.holds_margin(npile + 2 * k)) << "the lower index of pair " << k;
      EXPECT_FALSE(cs.holds_margin(npile + 2 * k + 1)) << "the higher index of pair " << k;
    }
    for (std::size_t k = 0; k < 10; ++k)
      EXPECT_TRUE(cs.listed(npile + 90 + 2 * k, npile + 90 + 2 * k + 1)) << "touching pair " << k;
    return o;
  };
  const Out serial = run(1, TeamThresholds{});
  const Out team = run(3, TeamThresholds{1, 1, 0, 0});
  EXPECT_EQ(serial.margins, 3u * 40u);
  EXPECT_EQ(team.margins, serial.margins);
  EXPECT_EQ(team.fast, serial.fast);
  EXPECT_TRUE(team.margin == serial.margin);
  EXPECT_TRUE(team.listed == serial.listed);
}
