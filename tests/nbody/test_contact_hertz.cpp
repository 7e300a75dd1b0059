/// @file test_contact_hertz.cpp
/// Verification of the Hertz-Mindlin normal law (contact/normal_hertz.hpp) against the Hertz
/// analytic impact (Johnson 1985 §11.4): contact time t_c = 2 (x_max/v) (2/5) B(2/5, 1/2) and
/// peak force (4/3) E* sqrt(R*) x_max^{3/2}, x_max = (15 mu v^2 / (16 E* sqrt(R*)))^{2/5}; Tsuji
/// damping: restitution equal to e_n and independent of the impact speed; the dt rule and the
/// scene parser.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "common/status.hpp"
#include "ssdem/contact_params.hpp"
#include "ssdem/dt_rule.hpp"
#include "ssdem/scene_setup.hpp"
#include "ssdem/simulation.hpp"

using namespace ssdem;

namespace {
struct HertzImpact {
  double tc = 0, tc_ref = 0, Fmax = 0, Fmax_ref = 0, e = 0;
};

// Two spheres of radii s1, s2 approaching head-on at relative speed v.
HertzImpact hertz_head_on(double v, double en, double steps, bool damping) {
  const double s1 = 0.01, s2 = 0.017, rho = 2500, E = 7e7, nu = 0.3;
  const double m1 = rho * 4.0 / 3.0 * M_PI * s1 * s1 * s1, m2 = rho * 4.0 / 3.0 * M_PI * s2 * s2 * s2;
  const double mu = m1 * m2 / (m1 + m2), R = s1 * s2 / (s1 + s2);
  const double Estar = E / (2.0 * (1.0 - nu * nu)), K = 4.0 / 3.0 * Estar * std::sqrt(R);
  ContactParams p;
  p.parts = kPartHertz | (damping ? kPartDamping : 0u);
  p.E = E;
  p.nu = nu;
  p.en = en;
  p.vmax = v;
  HertzImpact r;
  r.tc_ref = hertz_contact_time(mu, K, v);
  const double xmax = std::pow(15.0 * mu * v * v / (16.0 * Estar * std::sqrt(R)), 0.4);
  r.Fmax_ref = K * std::pow(xmax, 1.5);
  Spheres sp;
  sp.push(0, Vec3(-s1 - 0.01 * s1, 0, 0), Vec3(v * m2 / (m1 + m2), 0, 0), Vec3::Zero(), m1, s1);
  sp.push(1, Vec3(s2 + 0.01 * s1, 0, 0), Vec3(-v * m1 / (m1 + m2), 0, 0), Vec3::Zero(), m2, s2);
  SimConfig c;
  c.contacts = true;
  c.contact = p;
  c.dt = r.tc_ref / steps;
  c.min_steps_per_contact = 5;
  Simulation sim(sp, c);
  double t_in = -1, t_out = -1;
  double gap_prev = (sim.spheres().x[1] - sim.spheres().x[0]).norm() - s1 - s2;
  for (int k = 0; k < 100000 && t_out < 0; ++k) {
    const double t0 = sim.time();
    sim.step();
    const double gap = (sim.spheres().x[1] - sim.spheres().x[0]).norm() - s1 - s2;
    r.Fmax = std::max(r.Fmax, m1 * sim.acceleration()[0].norm());  // contact force on sphere 0
    if (t_in < 0 && gap < 0) t_in = t0 + c.dt * gap_prev / (gap_prev - gap);
    if (t_in >= 0 && gap > 0 && gap_prev <= 0) t_out = t0 + c.dt * (-gap_prev) / (gap - gap_prev);
    gap_prev = gap;
  }
  for (int k = 0; k < 3; ++k) sim.step();
  r.tc = t_out - t_in;
  r.e = (sim.spheres().v[1].x() - sim.spheres().v[0].x()) / v;
  return r;
}
}  // namespace

TEST(ContactHertz, ContactTimeAndPeakForceMatchHertz) {
  // 137.3 steps per contact (non-integer); two speeds a decade apart: t_c ~ v^{-1/5}.
  for (double v : {0.3, 3.0}) {
    const HertzImpact r = hertz_head_on(v, 1.0, 137.3, false);
    std::printf("Hertz v = %.1f m/s: t_c = %.6e s (analytic %.6e, rel %.2e), F_max = %.6e N "
                "(analytic %.6e, rel %.2e), e = %.6f\n",
                v, r.tc, r.tc_ref, r.tc / r.tc_ref - 1, r.Fmax, r.Fmax_ref, r.Fmax / r.Fmax_ref - 1, r.e);
    EXPECT_NEAR(r.tc / r.tc_ref, 1.0, 2e-3);
    EXPECT_NEAR(r.Fmax / r.Fmax_ref, 1.0, 2e-3);
    EXPECT_NEAR(r.e, 1.0, 1e-4);  // elastic: energy returned
  }
  // the constant of t_c = C (mu/K)^{2/5} v^{-1/5}, C = 2 (5/4)^{2/5} int_0^1 (1 - u^{5/2})^{-1/2} du,
  // by quadrature here (u = 1 - w^2 removes the end-point singularity) against the Beta form
  double I = 0.0;
  const int nq = 200000;
  for (int k = 0; k < nq; ++k) {
    const double w = (k + 0.5) / nq;
    I += 2.0 * w / std::sqrt(1.0 - std::pow(1.0 - w * w, 2.5)) / nq;
  }
  EXPECT_NEAR(hertz_contact_time(1.0, 1.0, 1.0), 2.0 * std::pow(1.25, 0.4) * I, 1e-6);
  EXPECT_NEAR(hertz_contact_time(1.0, 1.0, 1.0), 3.2181, 1e-4);
}

TEST(ContactHertz, TsujiDampingGivesSpeedIndependentRestitution) {
  // Tsuji et al. 1992: with C_n ~ x^{1/4} the restitution does not depend on the impact speed.
  EXPECT_NEAR(hertz_restitution(hertz_damping_alpha(0.55)), 0.55, 1e-6);
  for (double en : {0.3, 0.55, 0.9}) {
    for (double v : {0.1, 2.0}) {
      const HertzImpact r = hertz_head_on(v, en, 101.7, true);
      std::printf("Hertz+Tsuji e_n = %.2f, v = %.1f: e_meas = %.5f (rel %.2e), alpha = %.4f\n", en, v,
                  r.e, r.e / en - 1, hertz_damping_alpha(en));
      EXPECT_NEAR(r.e / en, 1.0, 5e-3);
    }
  }
}

TEST(ContactHertz, DtRuleUsesTheImpactSpeed) {
  ContactParams p;
  p.parts = kPartHertz;
  p.E = 1e8;
  p.nu = 0.25;
  Spheres sp;
  sp.push(0, Vec3(0, 0, 0), Vec3::Zero(), Vec3::Zero(), 1.0, 0.1);
  sp.push(1, Vec3(1, 0, 0), Vec3::Zero(), Vec3::Zero(), 1.0, 0.1);
  p.vmax = 1.0;
  const double t1 = shortest_contact_time(p, sp, false);
  p.vmax = 32.0;
  const double t32 = shortest_contact_time(p, sp, false);
  EXPECT_NEAR(t1 / t32, 2.0, 1e-9);  // t_c ~ v^{-1/5}: 32^{1/5} = 2
  const double Estar = p.E / (2 * (1 - p.nu * p.nu));
  EXPECT_DOUBLE_EQ(t32, hertz_contact_time(0.5, 4.0 / 3.0 * Estar * std::sqrt(0.05), 32.0));
  EXPECT_THROW(check_dt(p, sp, false, t32 / 5.0, 10.0), common::InputError);
  EXPECT_NO_THROW(check_dt(p, sp, false, t32 / 11.0, 10.0));
}

TEST(ContactHertz, SceneSelectsTheLawByName) {
  const common::Schema schema = ssdem_schema();
  auto make = [&](const std::string& extra) {
    const common::Scene sc = common::Scene::parse(
        schema, std::string("[time]\nend = 1.0\n[initial]\nbody_radius = 4.0\n[gravity]\nself = false\n") + extra, "t");
    Spheres sp = initial_spheres(sc);
    return sim_config(sc, sp);
  };
  const SimConfig c = make("[contact]\nparts = \"hertz,damping,tangential\"\nvmax = 2.0\nhertz.E = 1e8\n");
  EXPECT_EQ(c.contact.parts, kPartHertz | kPartDamping | kPartTangential);
  EXPECT_EQ(c.contact.vmax, 2.0);
  EXPECT_GT(c.dt, 0.0);
  EXPECT_THROW(make("[contact]\nparts = \"hertz\"\nvmax = 2.0\n"), common::InputError);  // no E
  EXPECT_THROW(make("[contact]\nparts = \"normal,hertz\"\nhertz.E = 1e8\n"), common::InputError);
  EXPECT_THROW(make("[contact]\nparts = \"damping\"\n"), common::InputError);  // no normal law
}
