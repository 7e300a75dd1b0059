/// @file test_stability.cpp
/// Stiff/extreme cases of the Tonge–Ramesh model (issue 4): strain rates up to 1e6 1/s, a fully
/// damaged point pulled to J = 2, compaction beyond P_c, and a sub-step-capped update: each must
/// stay finite and physically bounded (or be rejected cleanly as bad input).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "mpm/tonge_ramesh/element_driver.hpp"
#include "mpm/tonge_ramesh/flaws.hpp"
#include "mpm/tonge_ramesh/granular.hpp"
#include "mpm/tonge_ramesh/moduli.hpp"
#include "mpm/tonge_ramesh/point_update.hpp"

using namespace mpmfrag::tonge_ramesh;
using M3 = Eigen::Matrix3d;

TEST(Stability, UniaxialStressAtOneMillionPerSecond) {
  const Params p = basalt_el_mir();
  for (double r : {1e6, -1e6}) {
    const ElementResult res = run_uniaxial_stress(p, 1e-9, 1000, r, 2e-5, 0.3);
    ASSERT_TRUE(res.ok) << r;
    EXPECT_TRUE(std::isfinite(res.peak_stress));
    EXPECT_GT(res.peak_stress, 1e9) << r;  // crack-speed-limited: GPa-level dynamic strength
    EXPECT_LT(res.peak_stress, 2e10) << r;
  }
}

TEST(Stability, FullyDamagedPointUnderLargeTriaxialTension) {
  const Params p = basalt_el_mir();
  const Derived d(p);
  PointState st;
  st.D = p.max_damage;
  st.flags = 1;
  M3 sig = M3::Zero();
  double J = 1.0;
  const double rate = 1e5, dt = 1e-8;
  for (int i = 0; i < 2400; ++i) {  // J: 1 -> ~2.05
    StepInput in;
    in.L.diagonal().setConstant(rate / 3.0 * (1 + (i % 3 == 0 ? 0.2 : 0.0)));
    in.dt = dt;
    in.Jn = J;
    in.Jnp1 = J * std::exp(in.L.trace() * dt);
    J = in.Jnp1;
    ASSERT_EQ(update_point(p, d, in, sig, st, 0, nullptr, nullptr, nullptr), UpdateStatus::ok) << i;
    ASSERT_TRUE(sig.allFinite());
    // mean Kirchhoff stress never exceeds the apex B/sqrt3
    ASSERT_LE(sig.trace() / 3 * J, p.dp_cohesion / std::sqrt(3.0) * (1 + 1e-6)) << i;
  }
  EXPECT_GT(J, 2.0);
  EXPECT_NEAR(st.JGP / J, 1.0, 0.01);  // the opening is all granular dilatancy (porosity)
  EXPECT_GE(st.gp_energy, 0.0);
}

TEST(Stability, CompactionBeyondCrushPressure) {
  const Params p = basalt_el_mir();
  const Derived d(p);
  PointState st;
  st.D = p.max_damage;
  st.flags = 1;
  st.JGP = 1.4;  // distended rubble
  M3 sig = M3::Zero();
  double J = 1.4;
  const double dt = 1e-8;
  for (int i = 0; i < 6000; ++i) {  // compress to J ~ 0.77 (matrix ~ -23 %)
    StepInput in;
    in.L.diagonal().setConstant(-1e4 / 3.0);
    in.dt = dt;
    in.Jn = J;
    in.Jnp1 = J * std::exp(in.L.trace() * dt);
    J = in.Jnp1;
    ASSERT_EQ(update_point(p, d, in, sig, st, 0, nullptr, nullptr, nullptr), UpdateStatus::ok) << i;
    ASSERT_TRUE(sig.allFinite());
    ASSERT_GE(st.JGP, 1.0);
  }
  const double P = -sig.trace() / 3;
  EXPECT_GT(P, 2 * p.pa_Pc);        // well beyond P_c ...
  EXPECT_DOUBLE_EQ(st.JGP, 1.0);    // ... fully compacted
  EXPECT_GT(st.gp_energy, 0.0);
}

TEST(Stability, SubstepCapKeepsUpdateBounded) {
  Params p = basalt_el_mir();
  p.max_substeps = 5;  // force the cap
  const Derived d(p);
  const int n = p.total_bins();
  std::vector<double> om(n), s(n), l(n, 0.0);
  sample_flaws(p, 1e-9, 5, 0, om.data(), s.data());
  PointState st = initial_state(p, n, om.data(), s.data());
  M3 sig = M3::Zero();
  double J = 1.0;
  bool capped = false;
  for (int i = 0; i < 400; ++i) {
    StepInput in;
    in.L(0, 0) = 1e5;
    in.dt = 1e-7;  // very coarse step: huge damage increments
    in.Jn = J;
    in.Jnp1 = J * std::exp(1e5 * 1e-7);
    J = in.Jnp1;
    StepDiag dg;
    ASSERT_EQ(update_point(p, d, in, sig, st, n, om.data(), s.data(), l.data(), &dg), UpdateStatus::ok);
    capped |= dg.capped;
    ASSERT_TRUE(sig.allFinite());
    ASSERT_LE(st.D, p.max_damage);
  }
  EXPECT_TRUE(capped);
  EXPECT_GE(st.D, p.critical_damage);
}
