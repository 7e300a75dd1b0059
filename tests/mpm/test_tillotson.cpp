/// @file test_tillotson.cpp
/// Tillotson EOS unit tests: reference point values of validation-data.md §2.2 (basalt, BA99),
/// branch continuity, positive sound speed, finiteness everywhere.
#include <gtest/gtest.h>

#include <cmath>

#include "mpm/materials/tillotson.hpp"

using namespace mpmfrag;

TEST(Tillotson, BasaltPointValues) {
  const TillotsonParams p;  // basalt defaults
  struct Row { double eta, e, P_GPa, tol; TillotsonBranch br; };
  const Row rows[] = {
      {1.00, 0, 0.0, 1e-9, TillotsonBranch::compressed},
      {1.10, 0, 2.937, 1e-3, TillotsonBranch::compressed},
      {1.20, 0, 6.408, 1e-3, TillotsonBranch::compressed},
      {1.50, 0, 20.025, 1e-3, TillotsonBranch::compressed},
      {2.00, 0, 53.40, 1e-2, TillotsonBranch::compressed},
      {1.20, 1e6, 12.8811, 1e-3, TillotsonBranch::compressed},
      {1.50, 5e6, 60.387, 1e-3, TillotsonBranch::compressed},
      {2.00, 5e7, 583.265, 1e-2, TillotsonBranch::compressed},
      {0.90, 0, -2.403, 1e-3, TillotsonBranch::compressed},
      {0.90, 1e6, 2.44778, 1e-4, TillotsonBranch::compressed},
      {0.90, 1e7, 44.8394, 1e-3, TillotsonBranch::hybrid},
      {0.90, 5e7, 211.375, 1e-2, TillotsonBranch::expanded},
      {0.50, 1e7, 14.122, 1e-2, TillotsonBranch::hybrid},
      {0.50, 3e7, 20.5778, 1e-3, TillotsonBranch::expanded},
      {0.20, 5e7, 13.50, 1e-2, TillotsonBranch::expanded},
  };
  for (const Row& r : rows) {
    const TillotsonState s = tillotson_eos(p, r.eta * p.rho0, r.e);
    EXPECT_NEAR(s.pressure / 1e9, r.P_GPa, r.tol) << "eta=" << r.eta << " e=" << r.e;
    EXPECT_EQ(s.branch, r.br) << "eta=" << r.eta << " e=" << r.e;
  }
}

TEST(Tillotson, ContinuityAcrossBranches) {
  const TillotsonParams p;
  // across rho = rho0 at hot states (compressed <-> hybrid / expanded)
  for (double e : {1e7, 3e7}) {
    const double P1 = tillotson_pressure(p, p.rho0 * (1 + 1e-9), e);
    const double P2 = tillotson_pressure(p, p.rho0 * (1 - 1e-9), e);
    EXPECT_NEAR(P1, P2, 1e-5 * std::fabs(P1) + 1e3) << e;
  }
  // across E_iv and E_cv at expanded densities
  for (double eta : {0.95, 0.7, 0.3}) {
    for (double eb : {p.Eiv, p.Ecv}) {
      const double P1 = tillotson_pressure(p, eta * p.rho0, eb * (1 - 1e-10));
      const double P2 = tillotson_pressure(p, eta * p.rho0, eb * (1 + 1e-10));
      EXPECT_NEAR(P1, P2, 1e-6 * std::fabs(P1) + 1e2) << eta << " " << eb;
    }
  }
}

TEST(Tillotson, SoundSpeedMatchesFiniteDifferenceAndIsPositive) {
  const TillotsonParams p;
  // reference: c0 = sqrt(A/rho0) = 3144.7 m/s
  EXPECT_NEAR(std::sqrt(tillotson_eos(p, p.rho0, 0).c2), 3144.7, 0.1);
  for (double eta : {1.3, 1.05, 0.95, 0.8, 0.5}) {
    for (double e : {1e5, 5e6, 1e7, 4e7}) {
      const double rho = eta * p.rho0;
      const double hr = 1e-6 * rho, he = 1e-6 * e;
      const double dPdr = (tillotson_pressure(p, rho + hr, e) - tillotson_pressure(p, rho - hr, e)) / (2 * hr);
      const double dPde = (tillotson_pressure(p, rho, e + he) - tillotson_pressure(p, rho, e - he)) / (2 * he);
      const double P = tillotson_pressure(p, rho, e);
      const double c2 = dPdr + P / (rho * rho) * dPde;
      const double c2_floor = 0.01 * p.A / p.rho0;
      const TillotsonState s = tillotson_eos(p, rho, e);
      EXPECT_GT(s.c2, 0.0);
      EXPECT_NEAR(s.c2, std::max(c2, c2_floor), 1e-4 * std::fabs(c2) + 1.0) << eta << " " << e;
    }
  }
}

TEST(Tillotson, FiniteForAnyFiniteInput) {
  const TillotsonParams p;
  for (double eta : {0.0, 1e-300, 1e-12, 1e-6, 1e-3, 0.1, 0.5, 0.9, 1.0, 1.5, 3.0, 10.0, 100.0}) {
    for (double e : {-1e12, -1e6, -1.0, 0.0, 1.0, 1e3, 1e6, 1e7, 1e8, 1e10, 1e14}) {
      const TillotsonState s = tillotson_eos(p, eta * p.rho0, e);
      EXPECT_TRUE(std::isfinite(s.pressure)) << eta << " " << e;
      EXPECT_TRUE(std::isfinite(s.c2) && s.c2 > 0) << eta << " " << e;
    }
  }
  TillotsonParams f = p;
  f.pressure_min = 0.0;
  EXPECT_EQ(tillotson_pressure(f, 0.9 * p.rho0, 0.0), 0.0);  // tensile floor
}

TEST(Tillotson, HugoniotPoint) {
  // Rankine–Hugoniot: e = P/2 (1/rho0 - 1/rho) with P = P(rho, e); at rho/rho0 = 1.5399
  // validation-data.md §2.3 gives P = 48.13 GPa, u_p = 2.5 km/s, U_s = 7.131 km/s.
  const TillotsonParams p;
  const double rho = 1.5399 * p.rho0;
  double e = 0;
  for (int it = 0; it < 200; ++it) e = 0.5 * tillotson_pressure(p, rho, e) * (1 / p.rho0 - 1 / rho);
  const double P = tillotson_pressure(p, rho, e);
  const double up = std::sqrt(P * (1 / p.rho0 - 1 / rho));
  EXPECT_NEAR(P / 1e9, 48.13, 0.1);
  EXPECT_NEAR(up, 2500, 5);
  EXPECT_NEAR(up * rho / (rho - p.rho0), 7131, 15);
}
