/// @file test_contact_edges.cpp
/// The edge impulses of contact onset and release (contact_law.hpp, "Contact edges") against
/// the exact restitution of the linear law, e = e_n, at awkward step counts: non-integer steps
/// per contact and onsets at every phase of a step, where the plain step's first-order onset and
/// release errors do not cancel (ssdem.md §3.1). The error must be second order with the edges
/// and first order without them; the same for a sphere dropped on a wall (the wall path) and for
/// the Hertz law, against its own converged restitution.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "contact_scenes.hpp"
#include "ssdem/simulation.hpp"

using namespace ssdem;

namespace {

constexpr double kPhases[] = {0.0, 0.13, 0.29, 0.5, 0.61, 0.87};

// Head-on pair (contact_scenes.hpp) started `phase` of a step farther apart; the restitution
// measured 5 steps after the spheres separate.
double head_on_e(double en, double steps, double phase, bool edges, bool hertz = false) {
  test_scenes::HeadOnPair hp = test_scenes::head_on_pair(en, steps, true, true);
  hp.cfg.contact.resolve_edges = edges;
  if (hertz) {
    hp.cfg.contact.parts = kPartHertz | kPartDamping;
    hp.cfg.contact.E = 1e8;
    hp.cfg.contact.nu = 0.25;
    hp.cfg.contact.vmax = 2.0;
    const double m = hp.sp.m[0];
    hp.cfg.dt = hp.cfg.contact.contact_time(0.5 * m, 0.5 * hp.s) / steps;
  }
  const double shift = 0.5 * phase * 2.0 * hp.v * hp.cfg.dt;
  hp.sp.x[0].x() -= shift;
  hp.sp.x[1].x() += shift;
  Simulation sim(hp.sp, hp.cfg);
  bool touched = false;
  for (int k = 0; k < 200000; ++k) {
    sim.step();
    const double gap = (sim.spheres().x[1] - sim.spheres().x[0]).norm() - 2 * hp.s;
    touched = touched || gap < 0;
    if (touched && gap > 0) break;
  }
  for (int k = 0; k < 5; ++k) sim.step();
  return (sim.spheres().v[1].x() - sim.spheres().v[0].x()) / (2 * hp.v);
}

// Largest |e - e_ref| over the onset phases.
double worst(double en, double steps, bool edges, double e_ref, bool hertz = false) {
  double w = 0;
  for (double ph : kPhases) w = std::max(w, std::fabs(head_on_e(en, steps, ph, edges, hertz) - e_ref));
  return w;
}

// A sphere dropped on the plane z = 0 (no gravity) at 1 m/s, released `phase` of a step higher.
double wall_e(double en, double steps, double phase, bool edges, bool hertz = false) {
  const double s = 0.01, rho = 2500, v = 1.0;
  const double m = rho * 4.0 / 3.0 * M_PI * s * s * s;
  ContactParams p;
  p.parts = kPartDamping;
  p.kn = 1e5;
  p.en = en;
  p.resolve_edges = edges;
  if (hertz) {
    p.parts = kPartHertz | kPartDamping;
    p.E = 1e8;
    p.nu = 0.25;
    p.vmax = 1.0;
  }
  SimConfig c;
  c.contacts = true;
  c.contact = p;
  c.walls.push_back(Plane{Vec3::Zero(), Vec3(0, 0, 1)});
  c.dt = p.contact_time(m, s) / steps;
  c.min_steps_per_contact = 5;
  Spheres sp;
  sp.push(0, Vec3(0, 0, 1.2 * s + phase * v * c.dt), Vec3(0, 0, -v), Vec3::Zero(), m, s);
  Simulation sim(sp, c);
  for (int k = 0; k < 200000 && !(sim.spheres().x[0].z() > 1.2 * s && sim.spheres().v[0].z() > 0); ++k) sim.step();
  return sim.spheres().v[0].z() / v;
}

}  // namespace

TEST(ContactEdges, RestitutionErrorIsSecondOrderAtAwkwardStepCounts) {
  // measured (worst over 6 onset phases, |e - e_n|): see the printout; the plain step is first
  // order (halves per halving of dt), the edge impulses make it second order.
  for (double en : {0.2, 0.55, 0.8}) {
    double prev_on = 0, prev_off = 0;
    for (double n : {25.3, 50.7, 101.4}) {
      const double on = worst(en, n, true, en), off = worst(en, n, false, en);
      std::printf("e_n = %.2f, %.1f steps per contact: worst |e - e_n| %.3e with edges, %.3e without\n", en, n,
                  on, off);
      EXPECT_LT(on, 0.25 * off) << "the edges must beat the plain step";
      if (prev_on > 0) {
        EXPECT_GT(prev_on / on, 3.0) << "second order: ~4x per halving of dt";
        EXPECT_LT(prev_off / off, 3.0) << "the plain step is first order";
      }
      prev_on = on;
      prev_off = off;
    }
    EXPECT_LT(prev_on, 2e-4 * en / 0.55 + 5e-5) << "at 101.4 steps";
  }
}

TEST(ContactEdges, WallRestitutionIsSecondOrder) {
  double prev = 0;
  for (double n : {25.3, 50.7, 101.4}) {
    double on = 0, off = 0;
    for (double ph : kPhases) {
      on = std::max(on, std::fabs(wall_e(0.55, n, ph, true) - 0.55));
      off = std::max(off, std::fabs(wall_e(0.55, n, ph, false) - 0.55));
    }
    std::printf("wall, e_n = 0.55, %.1f steps: worst |e - e_n| %.3e with edges, %.3e without\n", n, on, off);
    EXPECT_LT(on, 0.25 * off);
    if (prev > 0) {
      EXPECT_GT(prev / on, 3.0);
    }
    prev = on;
  }
}

TEST(ContactEdges, HertzRestitutionErrorIsMuchSmaller) {
  // No closed form for the damped Hertz restitution: the reference is the run at 3200 steps
  // with edges (measured 0.5499877, 0.5499943, 0.5499977, 0.5499980 at 400, 800, 3200, 6400).
  // Measured worst errors: 1.2e-4, 8.3e-5, 6.1e-5 with edges, 4.9e-3, 2.3e-3, 9.4e-4 without at
  // 25.3, 50.7, 101.4 steps. The order with edges stays near 1 here: the dashpot C_0 x^{1/4}
  // u_n has an unbounded derivative next to the edge, which the midpoint steps after the onset
  // integrate with an O(h^{5/4}) error that the edge impulse (over its own step) does not cover.
  const double ref = head_on_e(0.55, 3200.0, 0.37, true, true);
  EXPECT_NEAR(ref, 0.54999, 2e-5);
  for (double n : {25.3, 50.7, 101.4}) {
    const double on = worst(0.55, n, true, ref, true), off = worst(0.55, n, false, ref, true);
    std::printf("Hertz, %.1f steps: worst |e - e_ref| %.3e with edges, %.3e without\n", n, on, off);
    EXPECT_LT(on, 0.1 * off);
  }
  // the wall path (R* = s, mu = m): its own converged reference
  const double wref = wall_e(0.55, 3200.0, 0.37, true, true);
  for (double n : {25.3, 50.7, 101.4}) {
    double on = 0, off = 0;
    for (double ph : kPhases) {
      on = std::max(on, std::fabs(wall_e(0.55, n, ph, true, true) - wref));
      off = std::max(off, std::fabs(wall_e(0.55, n, ph, false, true) - wref));
    }
    std::printf("Hertz wall, %.1f steps: worst |e - e_ref| %.3e with edges, %.3e without (e_ref %.6f)\n", n, on, off,
                wref);
    EXPECT_LT(on, 0.1 * off);
  }
}

TEST(ContactEdges, ReleasedPairForceReachesBothMembersOrNeither) {
  // A pair in contact separates; at the next evaluation its edge force is its record, added to
  // both spheres (equal and opposite). In a multi-rate subset that gathers only one member (a
  // separating pair whose flag is reset, Subset::whole = 0) there is no edge force: it would reach
  // one sphere only. The record is spent at the pair's next evaluation (list not rebuilt).
  const double s = 0.01, m = 2500 * 4.0 / 3.0 * M_PI * s * s * s, h = 1e-5;
  ContactParams p;
  p.parts = kPartDamping;
  p.kn = 1e5;
  p.en = 0.55;
  const std::vector<Vec3> v = {Vec3(-1, 0, 0), Vec3(1, 0, 0)}, w(2, Vec3::Zero());
  for (int whole : {1, 0}) {
    Spheres sp;
    sp.push(0, Vec3(-s + 1e-5, 0, 0), v[0], Vec3::Zero(), m, s);  // overlap 2e-5: in contact
    sp.push(1, Vec3(s - 1e-5, 0, 0), v[1], Vec3::Zero(), m, s);
    ContactSystem cs(p, {}, 0.5 * s);
    cs.update_neighbors(sp, true);
    std::vector<Vec3> F, T;
    cs.compute(sp, v, w, h, F, T);
    ASSERT_NE(F[1].x(), 0.0);  // in contact (spring minus the separating dashpot)
    sp.x[0].x() -= 2e-5;       // now a gap of 2e-5, separating at 2 m/s: released 1e-5 s ago
    sp.x[1].x() += 2e-5;
    ContactSystem::Subset sub;
    sub.pairs = {0};
    sub.hpair = {h};
    sub.whole = {static_cast<std::uint8_t>(whole)};
    sub.spheres = whole ? std::vector<std::uint32_t>{0, 1} : std::vector<std::uint32_t>{0};
    sub.hsphere.assign(sub.spheres.size(), h);
    F.assign(2, Vec3::Zero());
    cs.compute(sp, v, w, sub, F, T);
    if (whole) {
      // released at sigma = h - q = 0 (q = gap / w = h): the previous kick took the attractive
      // dashpot for h/2 too long, so the dashpot part returns C u_n / 2 (repulsive), and the
      // spring's k w (h/2)^2/(2h) is repulsive too
      EXPECT_NE(F[0].x(), 0.0);
      EXPECT_EQ(F[0].x(), -F[1].x());
      const double C = ContactParams::damping_prefactor(p.kn, p.en) * std::sqrt(0.5 * m), un = 2.0;
      const double expect_on_1 = 0.5 * C * un + p.kn * un * (0.5 * h) * (0.5 * h) / (2.0 * h);
      EXPECT_NEAR(F[1].x(), expect_on_1, 1e-9 * std::fabs(expect_on_1));
    } else {
      EXPECT_EQ(F[0], Vec3::Zero());
    }
    // next evaluation: the pair's gap is open and it is no longer in contact: nothing left
    sp.x[0].x() -= 2e-5;
    sp.x[1].x() += 2e-5;
    cs.compute(sp, v, w, h, F, T);
    EXPECT_EQ(F[0], Vec3::Zero());
    EXPECT_EQ(F[1], Vec3::Zero());
  }
}
