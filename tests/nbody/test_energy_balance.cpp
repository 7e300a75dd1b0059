/// @file test_energy_balance.cpp
/// The energy the contacts dissipate (contact_law.hpp, "Dissipation"; Spheres::dissipated) closes
/// the energy balance E_conservative + D = E_0 up to the integration error, which then converges
/// with the step; so the run's reported energy error is an integration error, not the physical
/// loss. Checked against analytic losses:
///  - head-on damped impact: D = (1 - e_n^2) mu v^2 / 2 (the KE lost, e_n the law's restitution);
///  - gross-sliding oblique impact on a wall with an undamped normal spring (sliding throughout):
///    D = the kinetic energy lost to Coulomb friction, (m/2)(v_t^2 - v_t'^2) - I w'^2 / 2;
///  - both slip rules, rolling and twisting sliders in a settling heap under gravity: balance
///    closes and the error shrinks when the step is halved;
///  - thread-count independence (1 vs 2 threads bit-identical per-sphere D), multi-rate steps.
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>

#include "common/rng.hpp"
#include "ssdem/contact_params.hpp"
#include "ssdem/simulation.hpp"
#include "contact_scenes.hpp"

using namespace ssdem;

namespace {

struct Balance {
  double E0 = 0, D = 0, err = 0, ke_lost = 0;
};

// Two equal spheres approaching head-on at 2 v; run until well after separation.
Balance head_on(double en, double steps_per_contact) {
  const test_scenes::HeadOnPair hp = test_scenes::head_on_pair(en, steps_per_contact);
  const double tc = hp.tc;
  const SimConfig& c = hp.cfg;
  Simulation sim(hp.sp, c);
  Balance b;
  const Diagnostics d0 = sim.diagnostics();
  b.E0 = d0.accounted();
  EXPECT_EQ(d0.dissipated, 0.0);
  // the gap of 0.4 radius closes at 2 v, then one contact time, then 2 t_c more (well apart)
  const double t_touch = 0.4 * hp.s / (2.0 * hp.v);
  const int n = static_cast<int>(std::ceil((t_touch + 3.0 * tc) / c.dt));
  for (int k = 0; k < n; ++k) sim.step();
  const Diagnostics d = sim.diagnostics();
  EXPECT_EQ(d.contacts, 0u);
  b.D = d.dissipated;
  b.err = d.accounted() - b.E0;
  b.ke_lost = d0.kinetic - d.kinetic;
  return b;
}

// One sphere sliding throughout an oblique impact on a wall (undamped normal law, Coulomb
// friction): the Chung & Ooi test 4 scene of test_contact.cpp (contact_scenes.hpp).
Balance gross_sliding(double steps_per_contact, SlipRule rule) {
  const test_scenes::GrossSliding g = test_scenes::gross_sliding(steps_per_contact, rule);
  const double vn = g.vn, vt = g.vt, s = g.s, m = g.m;
  const ContactParams& p = g.cfg.contact;
  Simulation sim(g.sp, g.cfg);
  Balance b;
  const Diagnostics d0 = sim.diagnostics();
  b.E0 = d0.accounted();
  const int n = static_cast<int>(std::ceil(10.0 * steps_per_contact));
  for (int k = 0; k < n; ++k) sim.step();
  const Diagnostics d = sim.diagnostics();
  EXPECT_EQ(d.wall_contacts, 0u);
  b.D = d.dissipated;
  b.err = d.accounted() - b.E0;
  // analytic loss of the rigid-body limit (e = 1): v_t' = v_t - mu (1+e) v_n, R w' = (5/2) mu (1+e) v_n
  const double vt2 = vt - p.mu_s * 2.0 * vn, Rw = 2.5 * p.mu_s * 2.0 * vn;
  b.ke_lost = 0.5 * m * (vt * vt - vt2 * vt2) - 0.5 * (0.4 * m * s * s) * (Rw / s) * (Rw / s);
  return b;
}

// A loose random cloud of n spheres falling onto a floor under uniform gravity with every
// dissipative part on; returns the simulation after `steps` steps of dt = tc / N.
struct Heap {
  std::unique_ptr<Simulation> sim;
  double E0 = 0;
};
Heap heap(std::size_t n, double N, int steps, SlipRule rule, bool multirate = false, unsigned parts = 0) {
  const double s = 0.05, rho = 2500;
  Spheres sp;
  const int side = static_cast<int>(std::ceil(std::cbrt(static_cast<double>(n))));
  for (std::size_t i = 0; i < n; ++i) {
    const int ix = static_cast<int>(i) % side, iy = (static_cast<int>(i) / side) % side,
              iz = static_cast<int>(i) / (side * side);
    common::KeyedRng g(7, i);
    const double r = s * (0.8 + 0.4 * g.uniform());
    const Vec3 x(2.05 * s * ix, 2.05 * s * iy, s + 2.05 * s * iz + 0.02 * s * g.uniform());
    const Vec3 v(0.3 * (g.uniform() - 0.5), 0.3 * (g.uniform() - 0.5), -0.2);
    sp.push(i, x, v, Vec3(0, 0, 2.0 * (g.uniform() - 0.5)), rho * 4.0 / 3.0 * M_PI * r * r * r, r);
  }
  ContactParams p = gravel_preset(2e4);
  p.mu_s = 0.5;
  p.mu_r = 0.1;
  p.mu_t = 0.3;
  p.slip = rule;
  if (parts) p.parts = parts;
  const double mmin = rho * 4.0 / 3.0 * M_PI * std::pow(0.8 * s, 3);
  SimConfig c;
  c.contacts = true;
  c.contact = p;
  c.uniform_g = Vec3(0, 0, -9.81);
  c.walls.push_back(Plane{Vec3::Zero(), Vec3::UnitZ()});
  c.dt = p.contact_time(0.5 * mmin) / N;
  c.min_steps_per_contact = 5;
  c.multirate = multirate;
  c.pair_steps_per_contact = N;
  if (multirate) c.dt /= 4;  // base step: heavy pairs run on coarser levels
  Heap h;
  h.sim = std::make_unique<Simulation>(sp, c);
  h.E0 = h.sim->diagnostics().accounted();
  const int total = multirate ? 4 * steps : steps;
  for (int k = 0; k < total; ++k) h.sim->step();
  return h;
}

}  // namespace

TEST(EnergyBalance, HeadOnDissipationIsTheRestitutionLoss) {
  // At 50.5 steps per contact (not an integer: a plain step's onset/release errors would not
  // cancel) the counted dissipation equals the kinetic energy lost to within the restitution
  // error, the balance closes to the same order, and it converges with the step (second order
  // with the edge impulses: measured 3.0e-3 -> 5.6e-5 of D at 50.5 -> 202 steps for e_n = 0.2).
  for (double en : {0.2, 0.55, 0.8}) {
    const Balance a = head_on(en, 50.5), b = head_on(en, 101.0), c = head_on(en, 202.0);
    std::printf("e_n %.2f: D/KE_lost = %.6f; error/D at 50.5, 101, 202 steps: %.3e %.3e %.3e\n", en,
                a.D / a.ke_lost, a.err / a.D, b.err / b.D, c.err / c.D);
    EXPECT_GT(a.D, 0.0);
    EXPECT_NEAR(a.D / a.ke_lost, 1.0, 2e-2);
    EXPECT_LT(std::fabs(a.err / a.D), 2e-2);
    EXPECT_LT(std::fabs(c.err), 0.3 * std::fabs(a.err));  // converging (second order: ~1/16)
  }
}

TEST(EnergyBalance, SlidingFrictionLossMatchesTheRigidBodyLimit) {
  // Coulomb rule: D = the analytic friction loss to the rigid-body limit's accuracy (the normal
  // spring's overlap, as in test_contact.cpp), measured ratio 1.0018 at 200 steps per contact;
  // the balance error halves when the step does (first order: 1.4e-3, 7.0e-4 of D).
  const Balance a = gross_sliding(200, SlipRule::coulomb), b = gross_sliding(400, SlipRule::coulomb);
  std::printf("coulomb: D = %.6e J, analytic loss %.6e J (ratio %.6f); error/D %.3e (200), %.3e (400)\n", a.D,
              a.ke_lost, a.D / a.ke_lost, a.err / a.D, b.err / b.D);
  EXPECT_NEAR(a.D / a.ke_lost, 1.0, 3e-3);
  EXPECT_LT(std::fabs(a.err / a.D), 3e-3);
  EXPECT_LT(std::fabs(b.err), 0.6 * std::fabs(a.err));
  // pkdgrav rule without a dashpot: a sliding contact zeroes its spring whenever it exceeds the
  // cap and applies min(mu |F_N|, C_t |u_t|) = 0, so the spring is rebuilt over a few steps again
  // and again; each cycle's leapfrog error is a large part of its energy. The balance error is
  // large (measured -11.7 % of D at 200 steps) but first order: it halves with the step.
  const Balance c = gross_sliding(200, SlipRule::pkdgrav), d = gross_sliding(400, SlipRule::pkdgrav);
  std::printf("pkdgrav: D = %.6e J; error/D %.3e (200), %.3e (400)\n", c.D, c.err / c.D, d.err / d.D);
  EXPECT_LT(std::fabs(c.err / c.D), 0.15);
  EXPECT_LT(std::fabs(d.err), 0.6 * std::fabs(c.err));
}

TEST(EnergyBalance, SettlingHeapClosesAndConverges) {
  // 343 spheres fall onto a floor. With the dashpots and the tangential slider (coulomb) the
  // balance error is below 1e-3 of D and shrinks with the step, though not monotonically (signed
  // sums of onset, stick-slip and release errors; measured 1.2e-4, 2.1e-4, 9.4e-5 at 20, 40, 80
  // steps per contact with the edge impulses, 6.4e-4, 2.1e-4, 1.4e-4 without). With every part
  // (rolling and twisting too) it is below 1e-2 of D; the rolling part leaves ~3e-3 that does not
  // shrink with the step (its v_roll carries the lever-arm term, so its moment's work on the
  // spheres is not its spring's energy change: a property of the law, not of the integrator).
  {
    const unsigned parts = kPartDamping | kPartTangential;
    double e[3], D0 = 0;
    for (int k = 0; k < 3; ++k) {
      const double N = 20.0 * (1 << k);
      Heap a = heap(343, N, static_cast<int>(200 * N), SlipRule::coulomb, false, parts);
      const Diagnostics da = a.sim->diagnostics();
      e[k] = (da.accounted() - a.E0) / da.dissipated;
      if (k == 0) {
        D0 = da.dissipated;
        EXPECT_GT(da.dissipated, 0.5 * (a.E0 - da.total()));  // most of the lost energy went through the contacts
      }
      EXPECT_LT(std::fabs(e[k]), 1e-3) << N << " steps per contact";
    }
    std::printf("heap (damping, tangential): D = %.4e J; error/D %.3e (20 steps/contact), %.3e (40), %.3e (80)\n",
                D0, e[0], e[1], e[2]);
    EXPECT_LT(std::fabs(e[2]), 0.6 * std::max(std::fabs(e[0]), std::fabs(e[1])));
  }
  for (SlipRule rule : {SlipRule::coulomb, SlipRule::pkdgrav}) {
    Heap a = heap(343, 20, 4000, rule);
    const Diagnostics da = a.sim->diagnostics();
    const double ea = (da.accounted() - a.E0) / da.dissipated;
    std::printf("heap (all parts, %s): D = %.4e J; error/D %.3e\n", rule == SlipRule::coulomb ? "coulomb" : "pkdgrav",
                da.dissipated, ea);
    EXPECT_GT(da.contacts, 100u);
    EXPECT_GT(da.dissipated, 0.5 * (a.E0 - da.total()));
    EXPECT_LT(std::fabs(ea), 1e-2);
  }
}

TEST(EnergyBalance, PerSphereDissipationIsThreadIndependent) {
  // 2744 spheres: above the 2048-item threshold of the parallel loops.
  omp_set_num_threads(1);
  Heap a = heap(2744, 20, 300, SlipRule::coulomb);
  omp_set_num_threads(2);
  Heap b = heap(2744, 20, 300, SlipRule::coulomb);
  const Spheres &sa = a.sim->spheres(), &sb = b.sim->spheres();
  ASSERT_EQ(sa.size(), sb.size());
  double total = 0;
  for (std::size_t i = 0; i < sa.size(); ++i) {
    ASSERT_EQ(sa.dissipated[i], sb.dissipated[i]) << "sphere " << i;
    total += sa.dissipated[i];
  }
  EXPECT_GT(total, 0.0);
}

TEST(EnergyBalance, MultirateBalanceCloses) {
  // The same heap on multi-rate levels (each pair its own step): dissipation is counted per pair
  // evaluation with the pair's step, so the balance closes as in single rate (measured 3.1e-3).
  Heap a = heap(343, 20, 4000, SlipRule::coulomb, true);
  const Diagnostics d = a.sim->diagnostics();
  const double e = (d.accounted() - a.E0) / d.dissipated;
  std::printf("heap multi-rate: D = %.4e J, error/D %.3e\n", d.dissipated, e);
  EXPECT_GT(d.dissipated, 0.0);
  EXPECT_LT(std::fabs(e), 1e-2);
}
