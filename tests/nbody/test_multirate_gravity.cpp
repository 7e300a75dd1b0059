/// @file test_multirate_gravity.cpp
/// Self-gravity inside a multi-rate gravity block (gravity.inner_steps, multirate.hpp "Self-gravity
/// inside a block"): "held" (the block-start field as a force at the sphere's own kicks plus the
/// trapezoid residual hk (g_new - g_held) at the block's end) against "impulse" (the block's two
/// half-kicks, RESPA).
///  * A close binary in a circular orbit, its pair near (gap < skin/2, so both spheres step on
///    level 0 inside blocks of 64) but never touching, the orbit turning 5.6 degrees per block:
///    with no force but gravity the two modes have the same block endpoints in exact arithmetic
///    (KDK under a constant force is exact), so they must agree to round-off at every block end.
///    A residual of hk g_new instead of hk (g_new - g_held), or none, changes the velocity by
///    hk |g| or hk |g_new - g_held| per block (relative ~5e-2 and ~5e-3) and fails.
///  * Two spheres resting in contact under their mutual gravity, blocks of 64 steps (~2 contact
///    times): with impulses the contact spring pushes the pair apart inside each block and the
///    closing kick pulls it back (the "breathing" of a resting pile), with the held field the
///    pair settles and stays at rest.
///  * Momentum at block ends is conserved in both modes (direct summation: pairwise forces), also
///    through promotions out of whole-block steps (a sphere flying into a pile).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "ssdem/dt_rule.hpp"
#include "ssdem/generators.hpp"
#include "ssdem/simulation.hpp"

using namespace ssdem;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int kBlock = 64;

SimConfig base_config(double kn, double G, bool held) {
  SimConfig c;
  c.contacts = true;
  c.contact = gravel_preset(kn);
  c.self_gravity = true;
  c.direct_gravity = true;
  c.gravity.G = G;
  c.gravity_every = kBlock;
  c.multirate = true;
  c.pair_steps_per_contact = 30.0;
  c.gravity_held = held;
  return c;
}

// Two spheres of radius 1 m and mass m at separation d (gap 0.1 m), circular orbit of period
// 64 blocks (5.6 degrees per block: the RESPA step keeps the orbit within a few mm of circular).
struct Binary {
  Spheres sp;
  SimConfig cfg;
};
Binary close_binary(bool held) {
  Binary b;
  const double s = 1.0, m = 4.0 / 3.0 * kPi * 2000.0, d = 2.1, kn = 1e6;
  const double tau = kPi * std::sqrt(0.5 * m / kn);  // the pair's contact time (linear law)
  const double dt = tau / 30.0;
  const double period = 64.0 * kBlock * dt;
  const double vrel = 2.0 * kPi * d / period;
  const double G = vrel * vrel * d / (2.0 * m);  // circular: v_rel^2 / d = G (2m) / d^2
  b.sp.push(1, Vec3(-0.5 * d, 0, 0), Vec3(0, -0.5 * vrel, 0), Vec3::Zero(), m, s);
  b.sp.push(2, Vec3(0.5 * d, 0, 0), Vec3(0, 0.5 * vrel, 0), Vec3::Zero(), m, s);
  b.cfg = base_config(kn, G, held);
  b.cfg.dt = dt;
  return b;
}

Vec3 momentum(const Spheres& sp) {
  Vec3 p = Vec3::Zero();
  for (std::size_t i = 0; i < sp.size(); ++i) p += sp.m[i] * sp.v[i];
  return p;
}

}  // namespace

TEST(MultirateGravity, HeldAndImpulseShareBlockEndpointsWithoutContacts) {
  Binary a = close_binary(true), b = close_binary(false);
  Simulation held(a.sp, a.cfg), imp(b.sp, b.cfg);
  const double d0 = 2.1, vscale = (a.sp.v[1] - a.sp.v[0]).norm();
  double dx = 0, dv = 0, dmin = 1e9, dmax = 0;
  int level_sum = 0;
  for (int blk = 0; blk < 160; ++blk) {  // 2.5 orbits
    for (int k = 0; k < kBlock; ++k) {
      held.step();
      imp.step();
      if (k == kBlock / 2) level_sum += held.levels()[0] + held.levels()[1];
    }
    ASSERT_TRUE(held.at_gravity_boundary());
    for (int i = 0; i < 2; ++i) {
      dx = std::max(dx, (held.spheres().x[i] - imp.spheres().x[i]).norm() / d0);
      dv = std::max(dv, (held.spheres().v[i] - imp.spheres().v[i]).norm() / vscale);
    }
    const double d = (held.spheres().x[1] - held.spheres().x[0]).norm();
    dmin = std::min(dmin, d);
    dmax = std::max(dmax, d);
  }
  std::printf("binary: separation %.6f..%.6f m, held - impulse: max |dx|/d %.2e, max |dv|/v_rel %.2e\n", dmin, dmax,
              dx, dv);
  EXPECT_EQ(level_sum, 0);               // the near pair stepped on level 0 inside the blocks
  EXPECT_GT(dmin, 2.0);                  // never in contact
  EXPECT_LT(dmax - 2.0, 0.125);          // always near (gap < skin/2 = 0.125 m): held mode applied
  EXPECT_LT(dx, 1e-11);
  EXPECT_LT(dv, 1e-11);
  EXPECT_GT((held.spheres().v[0] - a.sp.v[0]).norm(), 0.1 * vscale);  // the orbit turned
}

TEST(MultirateGravity, RestingPairDoesNotBreatheWithHeldField) {
  // equal spheres (radius 1 m, 2000 kg/m^3) touching, at rest, k_n = 1e6 N/m; G raised so that
  // their weight on each other is 1 % of k_n s (static overlap ~1 cm)
  const double m = 4.0 / 3.0 * kPi * 2000.0, kn = 1e6;
  const double G = 0.01 * kn * 4.0 / (m * m);
  double vmax[2] = {0, 0};
  for (int mode = 0; mode < 2; ++mode) {
    Spheres sp;
    sp.push(1, Vec3(-1.0, 0, 0), Vec3::Zero(), Vec3::Zero(), m, 1.0);
    sp.push(2, Vec3(1.0, 0, 0), Vec3::Zero(), Vec3::Zero(), m, 1.0);
    SimConfig c = base_config(kn, G, mode == 0);
    c.dt = kPi * std::sqrt(0.5 * m / kn) / 30.0;
    Simulation sim(sp, c);
    for (int blk = 0; blk < 60; ++blk)
      for (int k = 0; k < kBlock; ++k) {
        sim.step();
        if (blk >= 40) vmax[mode] = std::max(vmax[mode], (sim.spheres().v[1] - sim.spheres().v[0]).norm());
      }
    if (mode == 0) {
      EXPECT_LT((sim.spheres().x[1] - sim.spheres().x[0]).norm(), 2.0);  // held: in contact at the end
    }
    const Vec3 p = momentum(sim.spheres());
    EXPECT_LT(p.norm(), 1e-12 * m);  // momentum (zero) kept to round-off
  }
  std::printf("resting pair, blocks of 64 steps (2.1 contact times), max relative speed after 40 blocks: "
              "held %.3e m/s, impulse %.3e m/s\n", vmax[0], vmax[1]);
  EXPECT_GT(vmax[1], 1e-2);             // impulses: the pair breathes
  EXPECT_LT(vmax[0], 1e-6 * vmax[1]);   // held: at rest
}

TEST(MultirateGravity, MomentumKeptThroughPromotionsWithHeldField) {
  // a pile of radius 4 m (1 m spheres) and a lone sphere flying into it at 3 m/s; G raised so that
  // gravity matters over a block (~0.1 m/s^2 at the pile's surface); the lone sphere is promoted out of its whole-block step when it
  // comes near, which converts its opening impulse into the held share
  Spheres sp = lattice_pile(4.0, 1.0, 2000.0, 0.05, 7);
  const double m = sp.m[0];
  sp.push(1000, Vec3(11.0, 0.3, -0.2), Vec3(-3.0, 0, 0), Vec3::Zero(), m, 1.0);
  const DtAdvice adv = choose_kn_dt(m, 1.0, 3.0, 0.55, 0.01, 30.0);
  SimConfig c = base_config(adv.kn, 1e-6, true);
  c.gravity_every = 16;
  c.dt = shortest_contact_time(c.contact, sp, false) / 30.0;
  Simulation sim(sp, c);
  const Vec3 p0 = momentum(sim.spheres());
  double pscale = 0, dp = 0;
  for (std::size_t i = 0; i < sp.size(); ++i) pscale += sp.m[i] * 3.0;
  for (int blk = 0; blk < 900; ++blk) {
    for (int k = 0; k < 16; ++k) sim.step();
    dp = std::max(dp, (momentum(sim.spheres()) - p0).norm() / pscale);
  }
  std::printf("lone sphere into a pile (held field): promotions %lld, max |dP| / sum m v0 %.2e, lone v_x %.4f m/s\n",
              static_cast<long long>(sim.level_stats().promotions), dp, sim.spheres().v.back().x());
  EXPECT_GT(sim.level_stats().promotions, 0);
  EXPECT_GT(sim.spheres().v.back().x(), -1.0);  // it hit the pile
  EXPECT_LT(dp, 1e-13);
}

// The driver asks for the potential before a series row (Simulation::want_potential): the block's
// own gravity evaluation then gives it, diagnostics() evaluates no gravity again, and the row is
// the same bits as with the second evaluation, the trajectory too. Tree gravity on a
// self-gravitating pile, multi-rate (held field) and single rate.
TEST(MultirateGravity, RowPotentialFromTheBlocksOwnEvaluationIsTheSameBits) {
  for (const bool multirate : {true, false}) {
    const Spheres sp = lattice_pile(2.5, 0.5, 2000.0, 0.05, 5);
    SimConfig c = base_config(1e5, 1e-3, true);
    c.direct_gravity = false;
    c.multirate = multirate;
    c.gravity_every = 8;
    c.dt = shortest_contact_time(c.contact, sp, false) / 30.0;
    Simulation asked(sp, c), plain(sp, c);
    int rows = 0;
    for (int k = 0; k < 400; ++k) {
      const bool due = k >= 50 * (rows + 1) - 1;  // a row every 50 steps, at the next boundary
      asked.want_potential(due);
      asked.step();
      plain.step();
      if (!due || !asked.at_gravity_boundary()) continue;
      ++rows;
      EXPECT_TRUE(asked.potential_current()) << "step " << k;
      EXPECT_FALSE(plain.potential_current());
      const Diagnostics da = asked.diagnostics(), db = plain.diagnostics();
      EXPECT_EQ(da.potential_self, db.potential_self) << "step " << k;
      EXPECT_LT(da.potential_self, 0.0);
      EXPECT_EQ(da.total(), db.total());
      for (std::size_t i = 0; i < sp.size(); ++i) {
        ASSERT_EQ(asked.spheres().x[i], plain.spheres().x[i]) << "sphere " << i << ", step " << k;
        ASSERT_EQ(asked.spheres().v[i], plain.spheres().v[i]);
      }
    }
    EXPECT_GE(rows, 6) << (multirate ? "multi-rate" : "single rate");
  }
}
