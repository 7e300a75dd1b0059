/// @file test_granular.cpp
/// Granular flow (Drucker–Prager return, dilatancy, dissipation) and P–alpha compaction
/// (tonge-ramesh spec §8–9; crush-curve hand values in §9).
#include <gtest/gtest.h>

#include <cmath>

#include <Eigen/Dense>

#include "mpm/tonge_ramesh/granular.hpp"
#include "mpm/tonge_ramesh/moduli.hpp"

using namespace mpmfrag::tonge_ramesh;

TEST(PAlpha, CrushCurvePoints) {
  const Params p = basalt_el_mir();
  const Derived d(p);
  EXPECT_NEAR(d.pa_kappa, 3.3333, 1e-4);
  EXPECT_DOUBLE_EQ(crush_alpha(p, d, 75e6), 1.25);
  EXPECT_DOUBLE_EQ(crush_alpha(p, d, 200e6), 1.0);
  EXPECT_DOUBLE_EQ(crush_alpha(p, d, 300e6), 1.0);
  const struct {
    double a, P;
  } tab[] = {{1.05, 144e6}, {1.1, 121e6}, {1.2, 88.2e6}, {1.5, 32.6e6}, {2.0, 6.16e6}, {3.0, 0.22e6}};
  for (const auto& t : tab) {
    // invert the tabulated pressure to 3 digits: alpha within the rounding of P
    const double a = crush_alpha(p, d, t.P);
    const double a_hi = crush_alpha(p, d, t.P * 0.995), a_lo = crush_alpha(p, d, t.P * 1.005);
    EXPECT_GE(a, std::min(a_lo, t.a) - 1e-3) << t.P;
    EXPECT_LE(a, std::max(a_hi, t.a) + 1e-3) << t.P;
    EXPECT_NEAR(a, t.a, 0.01 * t.a);
  }
  EXPECT_TRUE(std::isinf(crush_alpha(p, d, -1e6)));
}

// Hydrostatic compression of a fully damaged point with alpha = 1.5: the state follows the crush
// curve, alpha never < 1, alpha = 1 beyond P_c, dissipation >= 0.
TEST(PAlpha, CompactionFollowsCrushCurve) {
  const Params p = basalt_el_mir();
  const Derived d(p);
  const double D = p.max_damage;
  const double ratio = damaged_bulk(d, D) / d.K0;
  double alpha = 1.5, J = 1.5;
  double prev = alpha, Wsum = 0.0;
  bool saw_mid = false;
  for (int i = 0; i < 3000; ++i) {
    J *= 1.0 - 2e-4;
    Wsum += pa_compaction(p, d, D, J, 0.0, 1e-8, alpha);
    ASSERT_GE(alpha, 1.0);
    ASSERT_LE(alpha, prev + 1e-15);
    prev = alpha;
    const double P = -kirchhoff_mean(p, J / alpha, 0.0, ratio) / J;
    if (alpha < 1.5 - 1e-9 && alpha > 1.0) {
      EXPECT_NEAR(alpha, crush_alpha(p, d, P), 1e-9) << "P=" << P;
      if (std::abs(P - 88.2e6) < 1e6) {
        EXPECT_NEAR(alpha, 1.2, 0.005);
        saw_mid = true;
      }
    }
    if (P > 1.05 * p.pa_Pc) {
      EXPECT_DOUBLE_EQ(alpha, 1.0);
    }
  }
  EXPECT_TRUE(saw_mid);
  EXPECT_DOUBLE_EQ(alpha, 1.0);
  EXPECT_GT(Wsum, 0.0);
  // Tension never compacts.
  double a2 = 1.3;
  EXPECT_EQ(pa_compaction(p, d, D, 1.4, 0.0, 1e-8, a2), 0.0);
  EXPECT_EQ(a2, 1.3);
}

namespace {
double yield_f(const Params& p, const Derived& d, double D, double J, double JGP,
               const Eigen::Matrix3d& be) {
  const double G = damaged_shear(p, d, D), ratio = damaged_bulk(d, D) / d.K0;
  const Eigen::Matrix3d td = G * (be - be.trace() / 3.0 * Eigen::Matrix3d::Identity());
  const double pK = kirchhoff_mean(p, J / JGP, 0.0, ratio);
  return td.norm() + p.dp_slope * (std::sqrt(3.0) * pK - p.dp_cohesion);
}
}  // namespace

TEST(Granular, ReturnLandsOnConeWithDilatancyAndPositiveDissipation) {
  const Params p = basalt_el_mir();
  const Derived d(p);
  const double D = p.max_damage;
  for (double J : {0.995, 0.999, 0.9999}) {
    Eigen::Matrix3d be = Eigen::Matrix3d::Identity();
    be(0, 1) = be(1, 0) = 1e-2;  // shear
    be(0, 0) += 5e-3;
    be(1, 1) -= 5e-3;
    be /= std::cbrt(be.determinant());  // isochoric
    double JGP = 1.0, gps = 0.0;
    ASSERT_GT(yield_f(p, d, D, J, JGP, be), 0.0);
    const double W = granular_flow(p, d, D, J, 0.0, 1e-8, be, JGP, gps);
    const double G = damaged_shear(p, d, D);
    EXPECT_NEAR(yield_f(p, d, D, J, JGP, be) / G, 0.0, 1e-9) << "J=" << J;
    EXPECT_GT(JGP, 1.0);  // dilatancy
    EXPECT_GE(W, 0.0);
    EXPECT_GT(gps, 0.0);
    EXPECT_NEAR(std::cbrt(be.determinant()), 1.0, 1e-5);  // be stays ~isochoric
  }
}

TEST(Granular, ApexReturnInHydrostaticTension) {
  const Params p = basalt_el_mir();
  const Derived d(p);
  const double D = p.max_damage;
  Eigen::Matrix3d be = Eigen::Matrix3d::Identity();
  double JGP = 1.0, gps = 0.0;
  const double J = 1.001;  // ~ 21 MPa hydrostatic tension if elastic
  const double W = granular_flow(p, d, D, J, 0.0, 1e-8, be, JGP, gps);
  const double ratio = damaged_bulk(d, D) / d.K0;
  EXPECT_NEAR(kirchhoff_mean(p, J / JGP, 0.0, ratio) / (p.dp_cohesion / std::sqrt(3.0)), 1.0, 1e-6);
  EXPECT_GT(JGP, 1.0009);
  EXPECT_GE(W, 0.0);
}
