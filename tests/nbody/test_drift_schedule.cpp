/// @file test_drift_schedule.cpp
/// Scheduled re-insertion tests (drift_schedule.hpp, contacts.hpp "Scheduled tests"): a sphere's
/// test is never scheduled after the first drift at which it fires, in floating point, also far
/// from the origin and with tiny distances; and a contact list driven by kicks and levels as
/// multi-rate steps drive it lists the same pairs, re-inserts the same spheres and gives the same
/// margins at every call as the test of every sphere at every call, while testing far fewer; and
/// a multi-rate run (a pile and 2 500 fragments under self-gravity) ends bit for bit where it ends
/// when every sphere is tested at every step.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "ssdem/contact_params.hpp"
#include "ssdem/contacts.hpp"
#include "ssdem/drift_schedule.hpp"
#include "ssdem/dt_rule.hpp"
#include "ssdem/generators.hpp"
#include "ssdem/simulation.hpp"

using namespace ssdem;

namespace {

// The first of `calls` drifts x += h v after which the test |x - xr|^2 > D^2 fires (as
// ContactSystem computes it), or calls + 1.
std::int64_t first_fire(Vec3 x, const Vec3& xr, const Vec3& v, double h, double D, std::int64_t calls) {
  for (std::int64_t m = 1; m <= calls; ++m) {
    for (int c = 0; c < 3; ++c) x[c] += h * v[c];
    if ((x - xr).squaredNorm() > D * D) return m;
  }
  return calls + 1;
}

}  // namespace

// wait() against the drifts themselves on random and awkward cases: never later than the first
// firing drift; at most one call early near the origin (so it is a schedule, not "every call").
TEST(DriftSchedule, WaitIsNeverLateAndNotMuchEarly) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  const double h = 0.0024984142285771976;
  const DriftSchedule sched;
  int early = 0, cases = 0;
  for (int k = 0; k < 4000; ++k) {
    const double far = (k % 4 == 0) ? 2.5e8 : (k % 4 == 1 ? 3.0e4 : 0.0);  // rounding of x
    const double D = (k % 3 == 0) ? 1e-3 : 12.5;  // a tiny skin and a 500 m sphere's f k
    const Vec3 xr = Vec3::Constant(far) + 100.0 * Vec3(U(rng), U(rng), U(rng));
    const Vec3 x = xr + 0.999 * D * Vec3(U(rng), U(rng), U(rng)).normalized() * std::abs(U(rng));
    // speeds from 1e-6 to 1e4 D per call, some heading back through the reference point
    const double speed = D / h * std::pow(10.0, -6.0 + 10.0 * (0.5 + 0.5 * U(rng)));
    Vec3 v = speed * Vec3(U(rng), U(rng), U(rng)).normalized();
    if (k % 5 == 0) v = -speed * (x - xr).normalized();
    if (k % 97 == 0) v = Vec3::Zero();
    const std::int64_t horizon = (k % 7 == 0) ? 20000 : 1 + (k % 600);
    const std::int64_t w = sched.wait(x, xr, Vec3(h * v), D, horizon);
    ASSERT_GE(w, 1);
    const std::int64_t look = std::min<std::int64_t>(horizon, sched.ring_length());
    const std::int64_t f = first_fire(x, xr, v, h, D, look);
    ASSERT_LE(std::min(w, look + 1), f) << "case " << k << ": scheduled after the test fires";
    if (far == 0.0 && f <= look) {
      ++cases;
      early += w < f - 1;
    }
  }
  EXPECT_GT(cases, 300);
  EXPECT_LT(early, cases / 100);  // rounding slack only
  // where rounding decides: 2.5e8 m from the origin (ulp 3e-8 m), 1 mm from the distance, drifts
  // of 1e-8 to 1e-6 m per call, just inside the distance
  int fired = 0;
  for (int k = 0; k < 2000; ++k) {
    const double D = 1e-3;
    const Vec3 xr = Vec3::Constant(2.5e8) + Vec3(U(rng), U(rng), U(rng));
    const Vec3 dir = Vec3(U(rng), U(rng), U(rng)).normalized();
    const Vec3 x = xr + (1.0 - 1e-4 * (0.5 + 0.5 * U(rng))) * D * dir;
    const Vec3 v = std::pow(10.0, -8.0 + 2.0 * (0.5 + 0.5 * U(rng))) / h * (dir + 0.3 * Vec3(U(rng), U(rng), U(rng)));
    const std::int64_t horizon = 300;
    const std::int64_t w = sched.wait(x, xr, Vec3(h * v), D, horizon);
    const std::int64_t f = first_fire(x, xr, v, h, D, horizon);
    fired += f <= horizon;
    ASSERT_LE(std::min(w, horizon + 1), f) << "rounding case " << k;
  }
  EXPECT_GT(fired, 500);
}

// The schedule alone, with a ring of 64 calls (wrapped 64 times; horizons up to 1 023 calls, so
// plans are renewed): driven by kicks and levels as multi-rate steps make them, every sphere whose
// test fires at a call is among the spheres it names for that call.
TEST(DriftSchedule, NamesEverySphereWhoseTestFires) {
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  const std::size_t n = 500;
  const double h = 1e-3;
  std::vector<Vec3> x(n), xr(n), v(n);
  std::vector<double> D(n);
  std::vector<std::uint8_t> level(n, 0);
  std::vector<std::int64_t> closes(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    xr[i] = x[i] = 1e4 * Vec3(U(rng), U(rng), U(rng));
    D[i] = 0.01 + U(rng);
  }
  DriftSchedule s(64);
  std::vector<std::uint32_t> kicked, cand;
  std::vector<std::uint8_t> named(n);
  const std::int64_t block = 1024;
  std::size_t tests = 0, fires = 0;
  for (std::int64_t call = 0; call < 4 * block; ++call) {
    const bool opens = call % block == 0;
    kicked.clear();
    for (std::uint32_t i = 0; i < n; ++i)
      if (opens || closes[i] <= call || U(rng) < 0.0005) {
        const double speed = D[i] / h * std::pow(10.0, -4.0 + 3.5 * U(rng));  // 1e-4 to 0.3 D per call
        v[i] = speed * Vec3(U(rng) - 0.5, U(rng) - 0.5, U(rng) - 0.5).normalized();
        int l = U(rng) < 0.01 ? 0 : 6 + static_cast<int>(U(rng) * 5.0);
        while (l > 0 && (std::int64_t{1} << l) > block - call % block) --l;
        level[i] = static_cast<std::uint8_t>(l);
        closes[i] = call + (std::int64_t{1} << l);
        if (!opens) kicked.push_back(i);
      }
    for (std::size_t i = 0; i < n; ++i)
      for (int c = 0; c < 3; ++c) x[i][c] += h * v[i][c];
    cand.clear();
    const bool all = s.open(n, opens ? nullptr : kicked.data(), kicked.size(), level.data(), cand);
    std::fill(named.begin(), named.end(), 0);
    if (all)
      for (std::uint32_t i = 0; i < n; ++i) cand.push_back(i);
    for (std::uint32_t i : cand) named[i] = 1;
    for (std::uint32_t i = 0; i < n; ++i)
      ASSERT_TRUE(named[i] || (x[i] - xr[i]).squaredNorm() <= D[i] * D[i]) << "call " << call << " sphere " << i;
    tests += cand.size();
    for (std::uint32_t i : cand) {
      if ((x[i] - xr[i]).squaredNorm() > D[i] * D[i]) {  // re-inserted
        xr[i] = x[i];
        ++fires;
      }
      if (s.planning()) s.enter(i, s.wait(x[i], xr[i], Vec3(h * v[i]), D[i], s.horizon(i)));
    }
    if (all) s.set_valid();
  }
  EXPECT_GT(fires, 20000u);
  // the first block tests every sphere (no statistics yet); the other three are planned (measured:
  // 9 % of their spheres per call, the fast ones firing every few calls)
  EXPECT_LT(tests - block * n, 3 * block * n / 5);
}

namespace {

struct Driver {  // kicks and levels as multi-rate steps make them, on kinematic spheres
  Spheres sp;
  std::vector<std::uint8_t> level;
  std::vector<std::int64_t> closes;  // call at whose end the sphere closes (is kicked)
  std::mt19937_64 rng{17};
  std::uniform_real_distribution<double> U{0.0, 1.0};
  Vec3 random_velocity(std::size_t i) {
    // most slow, a few fast fragments (several cells per call), some at rest
    const double r = U(rng);
    const double speed = r < 0.05 ? 0.0 : (r < 0.06 ? 3000.0 : 2.0 * std::pow(10.0, -3.0 + 3.0 * U(rng)));
    Vec3 d(U(rng) - 0.5, U(rng) - 0.5, U(rng) - 0.5);
    (void)i;
    return speed * d.normalized();
  }
  void kick(std::uint32_t i, std::int64_t now, int block_left) {
    sp.v[i] = random_velocity(i);
    // levels 5-7, a few spheres on the base step: about 1/40 kicked per call, so blocks are planned
    int l = U(rng) < 0.005 ? 0 : 5 + static_cast<int>(U(rng) * 3.0);
    while (l > 0 && (std::int64_t{1} << l) > block_left) --l;
    level[i] = static_cast<std::uint8_t>(l);
    closes[i] = now + (std::int64_t{1} << l);
  }
};

ContactParams linear() {
  ContactParams p;
  p.kn = 1e7;
  p.en = 0.5;
  return p;
}

}  // namespace

TEST(ScheduledTests, SameListAsTestingEverySphere) {
  Driver d;
  std::uniform_real_distribution<double> U(0.0, 1.0);
  const std::size_t n = 3000;  // above the parallel test's threshold (2048)
  for (std::size_t i = 0; i < n; ++i) {
    // a loose cloud of clumps: many pairs within reach, many isolated spheres
    const double clump = std::floor(U(d.rng) * 40.0);
    const Vec3 c(1e5 + 37.0 * std::fmod(clump, 7.0), 41.0 * std::floor(clump / 7.0), 0.0);
    const Vec3 x = c + 6.0 * Vec3(U(d.rng), U(d.rng), U(d.rng));
    d.sp.push(i, x, Vec3::Zero(), Vec3::Zero(), 0.2 + 0.8 * U(d.rng), 1.0);
  }
  d.level.assign(n, 0);
  d.closes.assign(n, 0);
  const double h = 1e-3;
  ContactSystem a(linear(), {}, 0.1), b(linear(), {}, 0.1);
  a.set_reinsert_fraction(0.25);
  b.set_reinsert_fraction(0.25);
  std::vector<std::uint32_t> kicked;
  const int block = 256;
  for (std::int64_t call = 0; call < 6 * block; ++call) {
    const bool opens = call % block == 0;
    // kicks of this call: everyone when a block opens, else the spheres whose step closed, and a
    // few promoted early (kicked before their step's end)
    kicked.clear();
    for (std::uint32_t i = 0; i < n; ++i)
      if (opens || d.closes[i] <= call || U(d.rng) < 0.001) {
        d.kick(i, call, block - static_cast<int>(call % block));
        if (!opens) kicked.push_back(i);
      }
    for (std::size_t i = 0; i < n; ++i) d.sp.x[i] += h * d.sp.v[i];  // the drift (every sphere)
    ContactSystem::Drift drift;
    drift.h = h;
    drift.kicked = opens ? nullptr : kicked.data();
    drift.nkicked = kicked.size();
    drift.level = d.level.data();
    a.update_neighbors(d.sp, drift);
    b.update_neighbors(d.sp);
    ASSERT_EQ(a.pair_i(), b.pair_i()) << "call " << call;
    ASSERT_EQ(a.pair_j(), b.pair_j()) << "call " << call;
    ASSERT_EQ(a.reinsert_count(), b.reinsert_count()) << "call " << call;
    ASSERT_EQ(a.margin_count(), b.margin_count()) << "call " << call;
    ASSERT_EQ(a.reference_positions(), b.reference_positions()) << "call " << call;
  }
  EXPECT_GT(b.reinsert_count(), 10000u);  // the fast fragments, every call or so
  EXPECT_GT(a.margin_count(), 1000u);
  // the first block tests every sphere (no statistics yet); the others are planned (measured:
  // 4 % of the tests of every sphere at every call)
  const std::size_t first = (block - 1) * n;  // (call 0 builds the list: no tests)
  EXPECT_LT(a.test_count() - first, (b.test_count() - first) / 10);
}

// Simulation: a small pile in contact (fine levels) and 2 500 lone fragments at 0.01-30 m/s on
// long steps, self-gravity in blocks of 256 steps (above 2 048 spheres: the parallel test in
// unplanned blocks; the driver above has 3 000, the schedule's own test 500). The second run touches spheres_mut() before
// every step, so its list tests every sphere at every step: same final state, bit for bit.
TEST(ScheduledTests, MultirateRunIsBitIdentical) {
  Spheres sp = lattice_pile(4.0, 1.0, 2000.0, 0.05, 3);
  ASSERT_GT(sp.size(), 10u);
  const double m = sp.m[0];
  std::mt19937_64 rng(23);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  for (int k = 0; k < 2500;) {
    const Vec3 dir = Vec3(U(rng) - 0.5, U(rng) - 0.5, U(rng) - 0.5).normalized();
    const Vec3 x = (8.0 + 100.0 * U(rng)) * dir;
    bool clear = true;  // no initial overlap, few near pairs
    for (std::size_t j = 0; j < sp.size() && clear; ++j) clear = (sp.x[j] - x).norm() > 3.0;
    if (!clear) continue;
    ++k;
    const Vec3 v = 0.01 * std::pow(3000.0, U(rng)) * Vec3(U(rng) - 0.5, U(rng) - 0.5, U(rng) - 0.5).normalized();
    sp.push(1000 + k, x, v, Vec3::Zero(), m, 1.0);
  }
  const DtAdvice adv = choose_kn_dt(m, 1.0, 3.0, 0.55, 0.01, 30.0);
  SimConfig c;
  c.contacts = true;
  c.contact = gravel_preset(adv.kn);
  c.self_gravity = true;
  c.gravity.G = 1e-6;
  c.gravity_every = 256;
  c.multirate = true;
  c.pair_steps_per_contact = 30.0;
  c.dt = shortest_contact_time(c.contact, sp, false) / 30.0;
  Simulation a(sp, c), b(sp, c);
  for (int s = 0; s < 8 * 256; ++s) {
    a.step();
    b.spheres_mut();
    b.step();
  }
  for (std::size_t i = 0; i < sp.size(); ++i) {
    ASSERT_EQ(a.spheres().x[i], b.spheres().x[i]) << "sphere " << i;
    ASSERT_EQ(a.spheres().v[i], b.spheres().v[i]) << "sphere " << i;
    ASSERT_EQ(a.spheres().w[i], b.spheres().w[i]) << "sphere " << i;
  }
  const ContactSystem& ca = *a.contact_system();
  const ContactSystem& cb = *b.contact_system();
  EXPECT_EQ(ca.reinsert_count(), cb.reinsert_count());
  EXPECT_GT(cb.reinsert_count(), 2500u);
  EXPECT_GT(a.level_stats().promotions, 0);  // fragments meeting: kicked before their step's end
  // the first block tests every sphere; measured 27 % of the tests in all
  EXPECT_LT(ca.test_count(), cb.test_count() / 3);
}
