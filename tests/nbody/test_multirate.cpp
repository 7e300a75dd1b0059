/// @file test_multirate.cpp
/// Multi-rate block time steps (multirate.hpp): a lone sphere flying into a pile and a 5 km/s
/// fragment through a pile follow the single-rate trajectories bit for bit (their pairs are on
/// the base level and a promotion in space is exact), a heavy pair on a coarse level rebounds
/// with the restitution of its own step count, contacts create no energy, restarts (also
/// through a checkpoint file) and thread counts do not change results; a cohesive pair on level
/// 2 pulls off at the cohesive threshold like single rate at its step; a non-finite state is caught
/// by the sphere's next step.
#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

#include "common/status.hpp"
#include "ssdem/dt_rule.hpp"
#include "ssdem/generators.hpp"
#include "ssdem/io.hpp"
#include "ssdem/scene_setup.hpp"
#include "ssdem/simulation.hpp"

using namespace ssdem;

namespace {

ContactParams gravel(double kn) {
  ContactParams p = gravel_preset(kn);
  return p;
}

// A pile of radius 4 (spheres of radius 1 m, 2000 kg/m^3, at rest) and a lone sphere starting
// 6 m from its surface flying at speed v into it; no uniform field; self-gravity direct, every 16
// steps, as the block's impulses (gravity.inner_steps = "impulse": single-rate stepping applies
// self-gravity so, and the comparisons below are bit for bit; the held field is tested in
// test_multirate_gravity.cpp).
struct Scene {
  Spheres sp;
  SimConfig cfg;
};
Scene lone_into_pile(double v, bool multirate, double steps_per_contact = 30.3) {
  Scene s;
  s.sp = lattice_pile(4.0, 1.0, 2000.0, 0.05, 7);
  const double m = s.sp.m[0];
  s.sp.push(1000, Vec3(11.0, 0.3, -0.2), Vec3(-v, 0, 0), Vec3::Zero(), m, 1.0);
  const DtAdvice a = choose_kn_dt(m, 1.0, std::max(v, 1.0), 0.55, 0.01, steps_per_contact);
  s.cfg.contacts = true;
  s.cfg.contact = gravel(a.kn);
  s.cfg.dt = shortest_contact_time(s.cfg.contact, s.sp, false) / steps_per_contact;
  s.cfg.self_gravity = true;
  s.cfg.direct_gravity = true;
  s.cfg.gravity_every = 16;
  s.cfg.multirate = multirate;
  s.cfg.pair_steps_per_contact = steps_per_contact;
  s.cfg.gravity_held = false;
  return s;
}

std::size_t differing(const Spheres& a, const Spheres& b) {
  std::size_t d = 0;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (a.x[i] != b.x[i] || a.v[i] != b.v[i] || a.w[i] != b.w[i]) ++d;
  return d;
}

double coarse_share(const Simulation& sim) {  // share of sphere-time on levels >= 1
  double tot = 0, c = 0;
  const auto& t = sim.level_stats().sphere_time;
  for (std::size_t l = 0; l < t.size(); ++l) {
    tot += t[l];
    if (l > 0) c += t[l];
  }
  return tot > 0 ? c / tot : 0.0;
}

// Rebound speed ratio of spheres 2 and 3 of sp (mass M, radius s) alone, single rate at step dt
// until t_end: the reference for a pair stepping on a coarse level.
double single_rate_pair_rebound(const Spheres& sp, double M, double s, SimConfig c, double dt, double t_end) {
  Spheres two;
  two.push(2, sp.x[2], sp.v[2], Vec3::Zero(), M, s);
  two.push(3, sp.x[3], sp.v[3], Vec3::Zero(), M, s);
  c.multirate = false;
  c.dt = dt;
  c.gravity_every = 1;
  Simulation ref(two, c);
  while (ref.time() < t_end) ref.step();
  return (ref.spheres().v[1].x() - ref.spheres().v[0].x()) / 2.0;
}

}  // namespace

TEST(Multirate, LoneSphereIntoPileMatchesSingleRateBitForBit) {
  // The lone sphere waits on level 4 (one step per gravity block) until it comes within skin/2
  // of the pile; its pairs are then on level 0 (equal masses), and the promotion is exact (no
  // uniform field): the trajectory must equal single-rate stepping at the base step, bit for
  // bit (tolerance 0: the same floating-point operations in the same order).
  Scene a = lone_into_pile(3.0, false), b = lone_into_pile(3.0, true);
  Simulation s1(a.sp, a.cfg), s2(b.sp, b.cfg);
  const std::size_t lone = a.sp.size() - 1;
  const int n = 16 * 900;
  for (int k = 0; k < n; ++k) {
    s1.step();
    s2.step();
  }
  std::printf("lone sphere: v_x end %.6f m/s (start -3), coarse share %.3f, promotions %lld\n",
              s1.spheres().v[lone].x(), coarse_share(s2), static_cast<long long>(s2.level_stats().promotions));
  EXPECT_GT(s2.spheres().v[lone].x(), -1.0);  // it hit the pile (gravel contacts: it stays)
  EXPECT_GT(coarse_share(s2), 1e-3);  // levels were actually used (the lone sphere: 1/280 of all)
  EXPECT_LT(s2.level_stats().evaluations, static_cast<std::int64_t>(n) * static_cast<std::int64_t>(a.sp.size()));
  EXPECT_EQ(differing(s1.spheres(), s2.spheres()), 0u);
}

TEST(Multirate, FastFragmentThroughPileIsCaught) {
  // 5 km/s fragment aimed at a pile: k_n from 1 % overlap at 5 km/s (the dt rule's k_n for
  // this impact), 30 steps per contact; it waits on a coarse level (one step per 16) until it
  // comes within skin/2 of the pile. It is caught at the same base step as single-rate stepping
  // sees its first overlap, so the whole run is bit-identical to single rate.
  Scene a = lone_into_pile(5000.0, false, 30.0), b = lone_into_pile(5000.0, true, 30.0);
  Simulation s1(a.sp, a.cfg), s2(b.sp, b.cfg);
  const std::size_t lone = a.sp.size() - 1;
  const double h = a.cfg.dt;
  const int n = static_cast<int>(std::ceil(60.0 / 5000.0 / h / 16.0)) * 16;  // 60 m of flight
  std::printf("fragment: %.3f radii per base step, %d steps\n", 5000.0 * h, n);
  for (int k = 0; k < n; ++k) {
    s1.step();
    s2.step();
  }
  const double vx = s2.spheres().v[lone].x();
  std::printf("fragment v_x after the pile: %.3f m/s (from -5000); max overlap %.4f; promotions %lld\n", vx,
              s2.contact_stats().max_overlap_frac, static_cast<long long>(s2.level_stats().promotions));
  EXPECT_GT(vx, -4900.0);  // it hit spheres of the pile (lost > 100 m/s): no tunnelling
  EXPECT_GT(s2.level_stats().promotions, 0);  // it was on a coarse level when it came near
  EXPECT_EQ(differing(s1.spheres(), s2.spheres()), 0u);
}

TEST(Multirate, HeavyPairRestitutionAtItsOwnLevel) {
  // A light pair (mass m) sets the base step h = tau(m/2)/30; a heavy pair (mass 20.25 m: tau_c
  // 4.5x longer) steps at level 2, 4 h = tau_c/33.75 (non-integer steps per contact). Its
  // rebound must equal single-rate stepping of the heavy pair alone at dt = 4 h (same step
  // grid: level 2 starts at a multiple of 4 h) to round-off (1e-9: the drift is summed in steps
  // of h instead of 4 h), and e_n to the contact law's own error at 33.75 steps (second order with
  // the edge impulses, contact_law.hpp: measured 5.6e-4; 9.4e-3 before them: < 2e-3).
  ContactParams p;
  p.parts = kPartDamping;
  p.kn = 1e5;
  p.en = 0.55;
  const double s = 0.01, m = 2500 * 4.0 / 3.0 * M_PI * s * s * s, M = 20.25 * m;
  Spheres sp;
  sp.push(0, Vec3(-0.1, 0, 0), Vec3::Zero(), Vec3::Zero(), m, s);  // light pair at rest, far away
  sp.push(1, Vec3(-0.1, 2.01 * s, 0), Vec3::Zero(), Vec3::Zero(), m, s);
  sp.push(2, Vec3(-1.2 * s, 0.5, 0), Vec3(1, 0, 0), Vec3::Zero(), M, s);
  sp.push(3, Vec3(1.2 * s, 0.5, 0), Vec3(-1, 0, 0), Vec3::Zero(), M, s);
  SimConfig c;
  c.contacts = true;
  c.contact = p;
  c.dt = p.contact_time(0.5 * m) / 30.0;
  c.multirate = true;
  c.pair_steps_per_contact = 30.0;
  c.self_gravity = false;
  c.gravity_every = 64;  // no self-gravity: the block only bounds the levels
  Simulation sim(sp, c);
  double used = 0;
  for (int k = 0; k < 64 * 40; ++k) {
    sim.step();
    used = std::max(used, sim.level_stats().sphere_time.size() > 2 ? sim.level_stats().sphere_time[2] : 0.0);
  }
  const double e = (sim.spheres().v[3].x() - sim.spheres().v[2].x()) / 2.0;
  const double e1 = single_rate_pair_rebound(sp, M, s, c, 4.0 * c.dt, 16 * 40 * 4.0 * c.dt * (1.0 - 1e-9));
  std::printf("heavy pair at level 2: e = %.9f, single rate at 4 h: %.9f (e_n 0.55, rel err %.2e)\n", e, e1,
              std::fabs(e - 0.55) / 0.55);
  EXPECT_GT(used, 0.0);
  EXPECT_NEAR(e, e1, 1e-9);
  EXPECT_LT(std::fabs(e - 0.55) / 0.55, 2e-3);
}

TEST(Multirate, MedianAnchorGivesTheTypicalPairExactlyNStepsOnItsLevel) {
  // Debris of equal spheres plus a few light ones and a heavier one (the pipeline's hand-off: tau
  // of the equal pair 2.93x the lightest pair's). time.level_anchor = median puts the equal pair on
  // level 2 with N = 20 steps per contact instead of level 1 with 29.3 (lightest): its rebound is
  // single-rate stepping at its own step tau/20 (to round-off), the lightest pair keeps >= 20
  // steps, and the same simulated time takes 29.3/20 fewer sphere evaluations.
  const double s = 0.01, m = 2500 * 4.0 / 3.0 * M_PI * s * s * s, M = 2.93 * 2.93 * m;
  Spheres sp;
  sp.push(0, Vec3(-0.1, 0, 0), Vec3::Zero(), Vec3::Zero(), m, s);  // light pair at rest, apart
  sp.push(1, Vec3(-0.1, 3.0 * s, 0), Vec3::Zero(), Vec3::Zero(), m, s);
  sp.push(2, Vec3(-1.2 * s, 0.5, 0), Vec3(1, 0, 0), Vec3::Zero(), M, s);
  sp.push(3, Vec3(1.2 * s, 0.5, 0), Vec3(-1, 0, 0), Vec3::Zero(), M, s);
  sp.push(4, Vec3(0.3, -0.3, 0), Vec3::Zero(), Vec3::Zero(), M, s);  // at rest, apart: median mass M
  sp.push(5, Vec3(0.3, 0.3, 0.3), Vec3::Zero(), Vec3::Zero(), 3.0 * M, s);  // not the anchor
  auto config = [&](const char* anchor) {
    const common::Scene sc = common::Scene::parse(
        ssdem_schema(),
        std::string("[time]\nend = 1.0\nmultirate = true\nsteps_per_contact = 20.0\nlevel_anchor = \"") +
            anchor + "\"\n[gravity]\nself = false\nevery = 64\n[contact]\nparts = \"normal,damping\"\nnormal.kn = 1e5\n"
            "damping.en = 0.55\n",
        "anchor");
    return sim_config(sc, sp);
  };
  const SimConfig lo = config("lightest"), hi = config("median");
  const double tau_min = lo.contact.contact_time(0.5 * m), tau_ref = lo.contact.contact_time(0.5 * M);
  EXPECT_NEAR(lo.dt * 20.0 / tau_min, 1.0, 1e-14);
  EXPECT_GE(tau_ref / (4.0 * hi.dt), 20.0);  // the heavy pair: exactly 20 steps on level 2
  EXPECT_LT(tau_ref / (4.0 * hi.dt), 20.0 * (1.0 + 1e-11));
  EXPECT_GE(tau_min / hi.dt, 20.0);  // the lightest: >= 20 steps on level 0
  {  // a median pair at r = 4.14: level 2 already gives it 20.7 steps, the anchor saves < 10 %: not applied
    const Spheres keep = sp;
    sp.m[2] = sp.m[3] = sp.m[4] = 4.14 * 4.14 * m;
    EXPECT_EQ(config("median").dt, config("lightest").dt);
    sp = keep;
  }
  auto run = [&](const SimConfig& c, double t_end) {
    Simulation sim(sp, c);
    while (sim.time() < t_end) sim.step();
    return std::make_pair((sim.spheres().v[3].x() - sim.spheres().v[2].x()) / 2.0, sim.level_stats());
  };
  const double t_end = 0.02 + 3.0 * tau_ref;
  const auto [e_hi, st_hi] = run(hi, t_end);
  const auto [e_lo, st_lo] = run(lo, t_end);
  EXPECT_GT(st_hi.sphere_time[2], 0.0);
  EXPECT_GT(st_lo.sphere_time[1], 0.0);
  // the heavy pair alone, single rate at its level's step
  const double e1 = single_rate_pair_rebound(sp, M, s, hi, 4.0 * hi.dt, t_end);
  std::printf("heavy pair: e = %.9f (median anchor), %.9f (lightest), single rate at tau/20: %.9f; "
              "sphere evaluations %lld vs %lld\n", e_hi, e_lo, e1, static_cast<long long>(st_hi.evaluations),
              static_cast<long long>(st_lo.evaluations));
  EXPECT_NEAR(e_hi, e1, 1e-9);
  EXPECT_LT(std::fabs(e_hi - 0.55) / 0.55, 1.5e-2);
  // the pair in reach steps at 4 h_hi instead of 2 h_lo: 2 h_hi / h_lo = 2.93 / 2 fewer steps
  // (sphere-time on the pair's level / its step; the spheres out of reach step once per gravity
  // block either way)
  const double steps_lo = st_lo.sphere_time[1] / (2.0 * lo.dt), steps_hi = st_hi.sphere_time[2] / (4.0 * hi.dt);
  std::printf("steps of the pair in reach: %.1f (lightest) vs %.1f (median)\n", steps_lo, steps_hi);
  EXPECT_NEAR(steps_lo / steps_hi, 2.93 / 2.0, 0.1);
}

TEST(Multirate, ContactsCreateNoEnergy) {
  // Two piles of unequal spheres (radii 1 and 0.6: pairs on levels 0 and 1) collide at 2 m/s
  // with dissipative gravel contacts and no gravity; the total energy (kinetic, rotational,
  // elastic) at every block boundary may not exceed the start by more than 1e-6 (KDK's bounded
  // elastic-energy oscillation is below that at 30 steps per contact; measured max 0).
  Spheres sp = lattice_pile(3.0, 1.0, 2000.0, 0.05, 3);
  Spheres b = lattice_pile(3.0, 0.6, 2000.0, 0.05, 4);
  append_body(sp, b, Vec3(5.0, 0.5, 0), Vec3(-2.0, 0, 0));  // gap ~0.5 m
  SimConfig c;
  c.contacts = true;
  double mmax = 0;
  for (double m : sp.m) mmax = std::max(mmax, m);
  c.contact = gravel(choose_kn_dt(mmax, 0.6, 2.0, 0.55).kn);
  c.dt = shortest_contact_time(c.contact, sp, false) / 30.0;
  c.multirate = true;
  c.pair_steps_per_contact = 30.0;
  c.gravity_every = 32;
  Simulation sim(sp, c);
  const double E0 = sim.diagnostics().total();
  double worst = -1e300;
  for (int k = 0; k < 32 * 300; ++k) {
    sim.step();
    if (sim.at_gravity_boundary()) worst = std::max(worst, sim.diagnostics().total() / E0 - 1.0);
  }
  std::printf("colliding piles: max (E/E0 - 1) = %.3e, final %.3e, coarse share %.3f\n", worst,
              sim.diagnostics().total() / E0 - 1.0, coarse_share(sim));
  EXPECT_LT(worst, 1e-6);
  EXPECT_LT(sim.diagnostics().total(), 0.95 * E0);  // and contacts did dissipate
  EXPECT_GT(coarse_share(sim), 0.01);
}

TEST(Multirate, NonFiniteStateCaughtByTheSpheresNextStep) {
  // The state check of a multi-rate step covers the spheres evaluated at it (and every sphere
  // before a field evaluation): a non-finite velocity of a sphere between its steps is caught at
  // its next synchronisation, at the latest one gravity block (16 base steps) later, and named.
  for (const bool lone : {true, false}) {
    Scene a = lone_into_pile(1.0, true);
    Simulation sim(a.sp, a.cfg);
    for (int k = 0; k < 16 * 4 + 3; ++k) sim.step();  // (mid-block)
    const std::size_t i = lone ? a.sp.size() - 1 : 0;
    const int l = sim.levels()[i];
    if (lone) {
      ASSERT_GE(l, 2);  // on a coarse step, not synchronised every base step
    }
    sim.spheres_mut().v[i].y() = NAN;
    int steps = 0;
    std::string what;
    try {
      for (; steps < 64; ++steps) sim.step();
    } catch (const common::NumericalError& e) {
      what = e.what();
    }
    std::printf("non-finite velocity of sphere %zu (level %d): caught after %d base step(s): %s\n", i, l,
                steps + 1, what.c_str());
    EXPECT_LE(steps + 1, 1 << l);  // by its next synchronisation
    EXPECT_NE(what.find("sphere id " + std::to_string(a.sp.id[i])), std::string::npos) << what;
  }
}

TEST(Multirate, RestartThroughCheckpointIsBitIdentical) {
  Scene a = lone_into_pile(3.0, true);
  Simulation ref(a.sp, a.cfg);
  for (int k = 0; k < 16 * 150; ++k) ref.step();
  Simulation first(a.sp, a.cfg);
  for (int k = 0; k < 16 * 70; ++k) first.step();
  const auto path = std::filesystem::temp_directory_path() / "ssdem_multirate_ckpt.h5";
  const SimState st = first.state();
  write_checkpoint(path.string(), st, a.cfg.dt, st.gravity_block, common::Provenance{}, a.cfg.contact.kn, "");
  SimState back = read_checkpoint(path.string(), nullptr, nullptr, nullptr, nullptr);
  std::filesystem::remove(path);
  ASSERT_EQ(back.level, st.level);
  Simulation second(std::move(back), a.cfg);
  for (int k = 0; k < 16 * 80; ++k) second.step();
  EXPECT_EQ(differing(ref.spheres(), second.spheres()), 0u);
}

TEST(Multirate, IndependentOfThreadCount) {
  // 2 700 spheres (loops run in parallel above 2 048): a pile and a cloud flying into it.
  Spheres sp = lattice_pile(8.0, 1.0, 2000.0, 0.05, 11);
  Spheres b = lattice_pile(5.0, 1.0, 2000.0, 0.05, 12);
  append_body(sp, b, Vec3(16.0, 2.0, 0), Vec3(-3.0, 0, 0));
  SimConfig c;
  c.contacts = true;
  c.contact = gravel(choose_kn_dt(sp.m[0], 1.0, 3.0, 0.55).kn);
  c.dt = shortest_contact_time(c.contact, sp, false) / 30.0;
  c.self_gravity = true;
  c.gravity_every = 1;
  c.adaptive_gravity = true;
  c.multirate = true;
  c.pair_steps_per_contact = 30.0;
  Spheres out[2];
  const int threads[2] = {1, 3};
  for (int r = 0; r < 2; ++r) {
    omp_set_num_threads(threads[r]);
    Simulation sim(sp, c);
    for (int k = 0; k < 200; ++k) sim.step();
    out[r] = sim.spheres();
  }
  omp_set_num_threads(2);
  EXPECT_EQ(differing(out[0], out[1]), 0u);
}

TEST(Multirate, CohesivePullOffAtItsPairLevel) {
  // Cohesion (contact/cohesion.hpp) acts only in contact, inside the pair's level: two cohesive
  // spheres at the equilibrium overlap x_eq = F_c / k_n given relative speed f v_c apart
  // (v_c = F_c / sqrt(mu k_n)) separate iff f > 1, on level 2 as in single rate. The pair steps at
  // 4 h = tau_c / 418.7 (r = tau_c / (N h) = 4.5; 837 steps per period as in test_nbody_cohesion,
  // whose first-order error at the force jump is below 2 %); its exit speed must be the energy value
  // sqrt(f^2 - 1) v_c to 2 % and equal single-rate stepping at 4 h to 1e-3 (the same step grid
  // after the start, where the levels coarsen at their first synchronisations).
  const double s1 = 0.5, s2 = 0.8, rho = 2000, kn = 2e5, sigma = 400.0, beta = 0.5;
  const double m1 = rho * 4.0 / 3.0 * M_PI * std::pow(s1, 3), m2 = rho * 4.0 / 3.0 * M_PI * std::pow(s2, 3);
  const double mu = m1 * m2 / (m1 + m2), Rbar = s1 * s2 / (s1 + s2);
  const double Fc = sigma * M_PI * beta * beta * Rbar * Rbar, xeq = Fc / kn, vc = Fc / std::sqrt(mu * kn);
  const double tau = M_PI * std::sqrt(mu / kn), h = tau / (372.1 * 4.5);
  auto run = [&](double f, bool multirate, std::uint8_t* level) {
    const double v = f * vc;
    Spheres sp;
    sp.push(0, Vec3(0, 0, 0), Vec3(-v * m2 / (m1 + m2), 0, 0), Vec3::Zero(), m1, s1);
    sp.push(1, Vec3(s1 + s2 - xeq, 0, 0), Vec3(v * m1 / (m1 + m2), 0, 0), Vec3::Zero(), m2, s2);
    SimConfig c;
    c.contacts = true;
    c.contact.parts = kPartCohesion;
    c.contact.kn = kn;
    c.contact.sigma_c = sigma;
    c.contact.beta = beta;
    c.dt = multirate ? h : 4 * h;
    c.multirate = multirate;
    c.pair_steps_per_contact = 372.1;
    c.gravity_every = multirate ? 64 : 1;
    Simulation sim(sp, c);
    bool apart = false;
    const int n = multirate ? 64 * 200 : 16 * 200;
    for (int k = 0; k < n; ++k) {
      sim.step();
      if (level && k == 63) *level = sim.levels()[0];
      apart = apart || (sim.spheres().x[1] - sim.spheres().x[0]).norm() > s1 + s2;
    }
    return apart ? (sim.spheres().v[1] - sim.spheres().v[0]).norm() / vc : 0.0;
  };
  std::uint8_t level = 255;
  const double below = run(0.97, true, &level), above = run(1.03, true, nullptr), ref = run(1.03, false, nullptr);
  std::printf("cohesive pull-off on level %d: f = 0.97 exit %.4f, f = 1.03 exit %.5f v_c (energy %.5f, single rate "
              "at 4 h %.5f)\n", level, below, above, std::sqrt(1.03 * 1.03 - 1.0), ref);
  EXPECT_EQ(level, 2);
  EXPECT_EQ(below, 0.0);
  EXPECT_NEAR(above / std::sqrt(1.03 * 1.03 - 1.0), 1.0, 0.02);
  EXPECT_NEAR(above / ref, 1.0, 1e-3);
}
