/// @file test_momentum.cpp
/// Momentum enhancement factor (analysis/momentum.hpp) on synthetic momentum bookkeeping with
/// known answers: head-on (beta = 1.69 exactly by construction), a moving target frame, and an
/// oblique case for the Cheng et al. (2023) vector form.
#include <gtest/gtest.h>

#include <cmath>

#include "analysis/analyse_scene.hpp"
#include "analysis/run_analysis.hpp"
#include "sphere_configs.hpp"

using namespace analysis;
using analysis_test::add;
using analysis_test::add_cube;

namespace {
// Remnant cube (27 spheres of 1e12 kg) + 3 fast ejecta. Total momentum = m U by construction,
// and the ejecta carry P_esc = -(beta - 1) m U (back toward the impactor) plus transverse parts
// that cancel.
common::SphereSet impact_outcome(double beta, double m, const Eigen::Vector3d& U, const Eigen::Vector3d& vt) {
  const Eigen::Vector3d uhat = U.normalized();
  const Eigen::Vector3d t1 = uhat.unitOrthogonal(), t2 = uhat.cross(t1);
  const double pimp = m * U.norm();
  const double me = 1e6;  // each ejecta sphere
  const Eigen::Vector3d pe_total = -(beta - 1.0) * pimp * uhat;
  // three ejecta: transverse momenta +a t1, -a t1 + b t2, -b t2 (sum zero)
  const double a = 0.3 * pimp, b = 0.2 * pimp;
  const Eigen::Vector3d pe[3] = {pe_total / 3 + a * t1, pe_total / 3 - a * t1 + b * t2, pe_total / 3 - b * t2};
  const Eigen::Vector3d p_remnant = m * U - pe_total;
  const double Mr = 27 * 1e12;
  common::SphereSet s;
  add_cube(s, {0, 0, 0}, 3, 200.0, 1e12, vt + p_remnant / Mr);
  for (int k = 0; k < 3; ++k) add(s, Eigen::Vector3d(5e5 * (k + 1), -3e5, 1e5 * k), 10.0, me, vt + pe[k] / me);
  return s;
}
}  // namespace

TEST(Beta, HeadOnSyntheticBookkeepingGivesExactBeta) {
  AnalyseConfig cfg;
  cfg.impact.impactor_mass = 2.0e9;
  cfg.impact.impactor_velocity = {0, 0, -5000};
  const common::SphereSet s = impact_outcome(1.69, 2.0e9, {0, 0, -5000}, Eigen::Vector3d::Zero());
  const SnapshotResult r = analyse_snapshot(s, cfg, 40.0);
  ASSERT_TRUE(r.beta);
  EXPECT_EQ(r.n_clumps, 4u);
  EXPECT_EQ(r.bound.n_bound_clumps, 1u);  // the ejecta move at ~1e3 m/s >> v_esc ~ 0.5 m/s
  EXPECT_NEAR(r.beta->beta, 1.69, 1e-12);
  EXPECT_NEAR(r.beta->beta_lr, 1.69, 1e-12);
  EXPECT_NEAR(r.beta->beta_ejecta, 1.69, 1e-12);
  ASSERT_TRUE(r.beta->beta_vector);
  EXPECT_NEAR(*r.beta->beta_vector, 1.69, 1e-9);
  EXPECT_LT(r.beta->momentum_error, 1e-13);
  EXPECT_NEAR(r.beta->beta_total, 1.69, 1e-12);
  EXPECT_NEAR(r.beta->escaping_momentum_along, -0.69 * 1e13, 1e-3);  // back toward the impactor
  EXPECT_DOUBLE_EQ(r.bound.escaping_mass, 3e6);
}

TEST(Beta, MovingTargetFrameGivesTheSameBeta) {
  AnalyseConfig cfg;
  const Eigen::Vector3d vt(120.0, -40.0, 75.0), U(1000.0, -2000.0, -4000.0);
  cfg.impact.impactor_mass = 2.0e9;
  cfg.impact.target_velocity = vt;
  cfg.impact.impactor_velocity = vt + U;
  const common::SphereSet s = impact_outcome(2.2, 2.0e9, U, vt);
  const SnapshotResult r = analyse_snapshot(s, cfg, 40.0);
  ASSERT_TRUE(r.beta);
  EXPECT_NEAR(r.beta->beta, 2.2, 1e-10);
  EXPECT_NEAR(r.beta->beta_ejecta, 2.2, 1e-10);
  EXPECT_LT(r.beta->momentum_error, 1e-12);
  // Ignoring the frame (target velocity 0) would be wrong by far more than the tolerance.
  AnalyseConfig wrong = cfg;
  wrong.impact.target_velocity.setZero();
  wrong.impact.impactor_velocity = U;
  EXPECT_GT(std::abs(analyse_snapshot(s, wrong, 40.0).beta->beta - 2.2), 0.1);
}

TEST(Beta, ObliqueVectorFormRecoversCheng2023Beta) {
  // Construct M dv = m U + m (beta - 1)(E.U) E with E at 30 degrees from U, beta = 3.61.
  BoundResult b;
  const double m = 579.4, beta = 3.61;
  const Eigen::Vector3d U(0, 0, -6144.9);
  const Eigen::Vector3d E = Eigen::Vector3d(std::sin(M_PI / 6), 0, std::cos(M_PI / 6));
  const Eigen::Vector3d p_target = m * U + m * (beta - 1) * E.dot(U) * E;
  b.bound_mass = b.lr_mass = 4.3e9;
  b.bound_momentum = b.lr_momentum = p_target;
  b.escaping_mass = 1e6;
  b.escaping_momentum = m * U - p_target;
  b.total_mass = b.bound_mass + b.escaping_mass;
  b.total_momentum = m * U;
  ImpactSpec spec;
  spec.impactor_mass = m;
  spec.impactor_velocity = U;
  const BetaResult r = momentum_enhancement(b, spec);
  ASSERT_TRUE(r.beta_vector);
  EXPECT_NEAR(*r.beta_vector, beta, 1e-12);
  // Along U only: beta_U = 1 + (beta - 1) cos^2(30 deg) = 1 + 2.61 * 0.75
  EXPECT_NEAR(r.beta, 1 + (beta - 1) * 0.75, 1e-12);
  EXPECT_NEAR(r.beta_ejecta, r.beta, 1e-12);
}

TEST(Beta, NoMomentumTransferredGivesBetaOne) {
  BoundResult b;
  b.bound_mass = b.lr_mass = b.total_mass = 10.0;
  b.bound_momentum = b.lr_momentum = b.total_momentum = Eigen::Vector3d(0, 0, -50);
  ImpactSpec spec;
  spec.impactor_mass = 0.01;
  spec.impactor_velocity = {0, 0, -5000};
  const BetaResult r = momentum_enhancement(b, spec);
  EXPECT_DOUBLE_EQ(r.beta, 1.0);
  ASSERT_TRUE(r.beta_vector);
  EXPECT_DOUBLE_EQ(*r.beta_vector, 1.0);
}

TEST(Beta, TotalMomentumReferenceCorrectsADiscretisedImpactor) {
  // The simulation's impactor carries 4 % less momentum than the scene's m U (discretisation):
  // beta against m U is low by 4 %, beta_total against the snapshot's own momentum is exact.
  AnalyseConfig cfg;
  cfg.impact.impactor_mass = 2.0e9;
  cfg.impact.impactor_velocity = {0, 0, -5000};
  const common::SphereSet s = impact_outcome(1.69, 0.96 * 2.0e9, {0, 0, -5000}, Eigen::Vector3d::Zero());
  const SnapshotResult r = analyse_snapshot(s, cfg, 40.0);
  ASSERT_TRUE(r.beta);
  EXPECT_NEAR(r.beta->beta, 0.96 * 1.69, 1e-12);
  EXPECT_NEAR(r.beta->beta_total, 1.69, 1e-12);
  EXPECT_NEAR(r.beta->momentum_error, 0.04, 1e-12);
}
