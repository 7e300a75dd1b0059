/// @file test_shock.cpp
/// Verification: planar symmetric Tillotson-basalt impact at 2 x 2.5 km/s vs the
/// Rankine–Hugoniot state of the Tillotson EOS (validation-data.md §2.3).
#include <gtest/gtest.h>

#include "shock_problem.hpp"

TEST(Shock, HugoniotOfTillotsonBasalt) {
  const shock::Exact ex = shock::hugoniot(mpmfrag::TillotsonParams{}, 2500.0);
  // The exact state itself (independent check of the table in validation-data.md §2.3).
  EXPECT_NEAR(ex.P / 1e9, 48.13, 0.1);
  EXPECT_NEAR(ex.rho / 2700.0, 1.5399, 0.002);
  EXPECT_NEAR(ex.Us, 7131, 15);
}

TEST(Shock, PlanarImpactMatchesRankineHugoniot) {
  const shock::Exact ex = shock::hugoniot(mpmfrag::TillotsonParams{}, 2500.0);
  const shock::Result r = shock::run(100);  // h = 1 mm, 50 cells behind the shock at the end
  const double us_lab = ex.Us - 2500.0;
  std::printf("shock (h = 1 mm): P = %.2f GPa (exact %.2f), rho/rho0 = %.4f (exact %.4f), v_behind = %.1f m/s,"
              " U_lab = %.1f m/s (exact %.1f)\n",
              r.P / 1e9, ex.P / 1e9, r.rho / 2700, ex.rho / 2700, r.v_behind, r.shock_speed_lab, us_lab);
  EXPECT_NEAR(r.P / ex.P, 1.0, 0.02);
  EXPECT_NEAR(r.rho / ex.rho, 1.0, 0.015);
  EXPECT_NEAR(r.shock_speed_lab / us_lab, 1.0, 0.015);
  EXPECT_LT(std::fabs(r.v_behind), 0.02 * 2500.0);
}

TEST(Shock, CellBinnedProfileConverges) {
  // L1 of the cell-binned pressure profile against the exact step (see shock_problem.hpp);
  // measured 0.087, 0.057, 0.035, 0.020 for 25, 50, 100, 200 cells (order 0.6-0.8).
  const shock::Result a = shock::run(50), b = shock::run(100);
  std::printf("shock L1: 50 cells %.4f, 100 cells %.4f (ratio %.2f)\n", a.l1, b.l1, a.l1 / b.l1);
  EXPECT_LT(b.l1, 0.05);
  EXPECT_GT(a.l1 / b.l1, 1.3);
}
