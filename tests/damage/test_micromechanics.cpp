/// @file test_micromechanics.cpp
/// Wing-crack micromechanics and damaged moduli (tonge-ramesh spec §5, §7; hand values there).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "mpm/tonge_ramesh/micromechanics.hpp"
#include "mpm/tonge_ramesh/moduli.hpp"

using namespace mpmfrag::tonge_ramesh;

TEST(Moduli, BasaltDerivedConstants) {
  const Params p = basalt_el_mir();
  const Derived d(p);
  EXPECT_NEAR(d.nu0, 0.1688, 5e-4);
  EXPECT_NEAR(d.E0, 53.06e9, 0.05e9);
  EXPECT_NEAR(d.kK, 1.304, 2e-3);
  EXPECT_NEAR(d.kG, 1.707, 2e-3);
  EXPECT_NEAR(d.cR, 2616.0, 3.0);
  EXPECT_NEAR(d.v_max, 523.2, 1.0);
  EXPECT_NEAR(d.sin2phi, std::sin(2 * 0.8841), 1e-3);
}

TEST(Moduli, DamagedModuliAtCriticalAndMaxDamage) {
  const Params p = basalt_el_mir();
  const Derived d(p);
  EXPECT_DOUBLE_EQ(damaged_bulk(d, 0.0), 26.7e9);
  EXPECT_NEAR(damaged_bulk(d, 0.125) / d.K0, 0.860, 1.5e-3);
  EXPECT_NEAR(damaged_shear(p, d, 0.125) / p.shear_modulus, 0.824, 1.5e-3);
  EXPECT_NEAR(damaged_bulk(d, 0.2) / d.K0, 0.793, 1.5e-3);
  EXPECT_NEAR(damaged_shear(p, d, 0.2) / p.shear_modulus, 0.745, 1.5e-3);
}

TEST(Tillotson, ColdBranchPointValues) {
  const Params p = basalt_el_mir();
  // validation-data.md §2.2 point checks (compressed / cold-expanded branch).
  EXPECT_NEAR(tillotson_pressure(p.eos, p.density, 1.0, 0.0), 0.0, 1e-6);
  EXPECT_NEAR(tillotson_pressure(p.eos, p.density, 1.1, 0.0) / 1e9, 2.937, 1e-3);
  EXPECT_NEAR(tillotson_pressure(p.eos, p.density, 1.2, 1e6) / 1e9, 12.8811, 1e-3);
  EXPECT_NEAR(tillotson_pressure(p.eos, p.density, 1.5, 5e6) / 1e9, 60.387, 1e-2);
  EXPECT_NEAR(tillotson_pressure(p.eos, p.density, 0.9, 0.0) / 1e9, -2.403, 1e-3);
  EXPECT_NEAR(tillotson_pressure(p.eos, p.density, 0.9, 1e6) / 1e9, 2.44778, 1e-4);
  EXPECT_DOUBLE_EQ(tillotson_tangent(p.eos, p.density, 1.0, 0.0), 26.7e9);
  // Tangent = eta dp/deta (finite difference).
  const double h = 1e-6, eta = 1.13, e = 2e6;
  const double fd = eta * (tillotson_pressure(p.eos, p.density, eta + h, e) -
                           tillotson_pressure(p.eos, p.density, eta - h, e)) / (2 * h);
  EXPECT_NEAR(tillotson_tangent(p.eos, p.density, eta, e) / fd, 1.0, 1e-7);
}

// Onset of growth under uniaxial compression S: K_I(S*) = K_IC with
// S* = K_IC sqrt(0.27 pi) / (2 sqrt(s) (sin(2phi)/2 - mu cos^2 phi)) (spec §7.4 hand values).
TEST(WingCrack, OnsetUnderUniaxialCompressionAndTension) {
  const Params p = basalt_el_mir();
  const Derived d(p);
  const struct {
    double s, S;
  } comp[] = {{5e-6, 804e6}, {100e-6, 180e6}, {1e-3, 56.8e6}, {1e-2, 18.0e6}};
  for (const auto& c : comp) {
    const double Sstar =
        p.KIc * std::sqrt(0.27 * M_PI) /
        (2 * std::sqrt(c.s) * (0.5 * d.sin2phi - p.flaw_friction * d.cos_phi * d.cos_phi));
    EXPECT_NEAR(Sstar / c.S, 1.0, 4e-3) << "s=" << c.s;
    EXPECT_NEAR(stress_intensity(p, d, -Sstar, 0.0, c.s, 0.0) / p.KIc, 1.0, 1e-12);
    EXPECT_EQ(growth_speed(p, d, stress_intensity(p, d, -0.999 * Sstar, 0, c.s, 0)), 0.0);
    EXPECT_GT(growth_speed(p, d, stress_intensity(p, d, -1.001 * Sstar, 0, c.s, 0)), 0.0);
  }
  // Uniaxial tension, s = 100 um: 61.0 MPa with frictionless open faces (our fix),
  // 55.5 MPa with PTR's friction-in-tension quirk.
  auto onset_t = [&](const Params& q) {
    double lo = 1e6, hi = 1e9;
    for (int i = 0; i < 100; ++i) {
      const double m = 0.5 * (lo + hi);
      (stress_intensity(q, d, 0.0, m, 100e-6, 0.0) > q.KIc ? hi : lo) = m;
    }
    return lo;
  };
  EXPECT_NEAR(onset_t(p) / 1e6, 61.0, 0.15);
  Params q = p;
  q.friction_in_tension = true;
  EXPECT_NEAR(onset_t(q) / 1e6, 55.5, 0.15);
  // Hydrostatic compression never drives growth.
  EXPECT_LT(stress_intensity(p, d, -1e9, -1e9, 1e-3, 0.0), 0.0);
}

TEST(WingCrack, CrackSpeedTendsToLimit) {
  const Params p = basalt_el_mir();
  const Derived d(p);
  EXPECT_EQ(growth_speed(p, d, p.KIc), 0.0);
  double prev = 0.0;
  for (double r : {1.01, 1.1, 2.0, 10.0, 100.0, 1e4}) {
    const double v = growth_speed(p, d, r * p.KIc);
    EXPECT_GT(v, prev);
    EXPECT_LT(v, d.v_max);
    prev = v;
  }
  EXPECT_NEAR(growth_speed(p, d, 1e4 * p.KIc) / d.v_max, 1.0, 1e-4);
  // l(t) under a huge stress advances at v_max: measured speed within 0.5 %.
  const double om = 1e9, s = 20e-6;
  double l = 0.0;
  const double dt = 1e-9;
  for (int i = 0; i < 20; ++i) advance_cracks(p, d, -5e12, 0.0, dt, 1, &om, &s, &l);
  const double l0 = l;
  for (int i = 0; i < 100; ++i) advance_cracks(p, d, -5e12, 0.0, dt, 1, &om, &s, &l);
  EXPECT_NEAR((l - l0) / (100 * dt) / d.v_max, 1.0, 1e-3);
  // At a moderate overload the measured speed equals the law, below the limit.
  double l2 = 0.0;
  advance_cracks(p, d, -5e9, 0.0, dt, 1, &om, &s, &l2);
  const double v_law = growth_speed(p, d, stress_intensity(p, d, -5e9, 0.0, s, 0.0));
  EXPECT_NEAR(l2 / dt / v_law, 1.0, 1e-12);
  EXPECT_LT(v_law, 0.99 * d.v_max);
}

TEST(WingCrack, DamageMonotoneCappedAndLengthBounded) {
  const Params p = basalt_el_mir();
  const Derived d(p);
  std::vector<double> om = {2e9, 1e10, 0.0, 5e11}, s = {60e-6, 30e-6, 1e-3, 8e-6},
                      l(4, 0.0);
  double D = damage_of(p, 4, om.data(), s.data(), l.data());
  const double D0 = D;
  for (int i = 0; i < 4000; ++i) {
    const double Dn = advance_cracks(p, d, -300e6, 80e6, 2e-9, 4, om.data(), s.data(), l.data());
    ASSERT_GE(Dn, D - 1e-15);
    ASSERT_LE(Dn, p.max_damage);
    D = Dn;
    for (int k = 0; k < 4; ++k) {
      ASSERT_GE(l[k], 0.0);
      if (om[k] > 0) {
        ASSERT_LE(l[k], 1.0 / std::cbrt(om[k]) - s[k] + 1e-15);
      }
    }
  }
  EXPECT_GT(D0, 0.0);
  EXPECT_DOUBLE_EQ(D, p.max_damage);
  EXPECT_EQ(l[2], 0.0);  // empty bin untouched
}
