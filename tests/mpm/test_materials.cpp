/// @file test_materials.cpp
/// Unit tests of the material styles and helpers.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>

#include "mpm/materials/builtin.hpp"

using namespace mpmfrag;

TEST(Materials, HughesWingetRotationMatchesCayleyMatrixForm) {
  const double L[9] = {0.3, -1.2, 0.7, 2.1, -0.4, 0.5, -0.9, 1.6, 0.2};
  const double dt = 0.37;
  double v[6] = {1.0, -2.0, 0.5, 0.3, -0.7, 1.1};
  Eigen::Matrix3d S;
  S << v[0], v[5], v[4], v[5], v[1], v[3], v[4], v[3], v[2];
  const Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> Lm(L);
  const Eigen::Matrix3d W = 0.5 * (Lm - Lm.transpose()) * dt, I = Eigen::Matrix3d::Identity();
  const Eigen::Matrix3d R = (I - 0.5 * W).inverse() * (I + 0.5 * W);
  const Eigen::Matrix3d ref = R * S * R.transpose();
  EXPECT_NEAR((R * R.transpose() - I).norm(), 0.0, 1e-14);
  rotate_stress_hughes_winget(v, L, dt);
  EXPECT_NEAR(v[0], ref(0, 0), 1e-13);
  EXPECT_NEAR(v[1], ref(1, 1), 1e-13);
  EXPECT_NEAR(v[2], ref(2, 2), 1e-13);
  EXPECT_NEAR(v[3], ref(1, 2), 1e-13);
  EXPECT_NEAR(v[4], ref(0, 2), 1e-13);
  EXPECT_NEAR(v[5], ref(0, 1), 1e-13);
  // invariants preserved
  EXPECT_NEAR(v[0] + v[1] + v[2], S.trace(), 1e-13);
}

namespace {
MaterialBatch one(const double* L, const double* F, double* s, const double* m, const double* V, double* ws,
                  const double* e, double dt) {
  static const double V0 = 1.0;
  static const std::uint64_t id = 7;
  MaterialBatch b;
  b.n = 1;
  b.dt = dt;
  b.L = L;
  b.F = F;
  b.stress = s;
  b.mass = m;
  b.volume = V;
  b.volume0 = &V0;
  b.energy = e;
  b.id = &id;
  b.wave_speed = ws;
  return b;
}
}  // namespace

TEST(Materials, NeoHookeanUniaxialStretchAndWaveSpeed) {
  const double K = 8333.33, G = 3846.15, rho = 1.0, lam = K - 2 * G / 3;
  auto m = make_neo_hookean(rho, K, G);
  const double a = 1.1;
  const double L[9] = {}, F[9] = {a, 0, 0, 0, 1, 0, 0, 0, 1};
  double s[6] = {}, ws = 0, e = 0;
  const double mass = 1.0, V = a;
  const BatchResult r = m->update(one(L, F, s, &mass, &V, &ws, &e, 1e-3));
  EXPECT_EQ(r.failed, 0u);
  EXPECT_NEAR(s[0], (lam * std::log(a) + G * (a * a - 1)) / a, 1e-9);
  EXPECT_NEAR(s[1], lam * std::log(a) / a, 1e-9);
  EXPECT_NEAR(s[5], 0.0, 1e-12);
  EXPECT_NEAR(ws, std::sqrt((K + 4 * G / 3) / (mass / V)), 1e-9);
  // inverted element is reported, not computed
  const double Fbad[9] = {-1, 0, 0, 0, 1, 0, 0, 0, 1};
  EXPECT_EQ(m->update(one(L, Fbad, s, &mass, &V, &ws, &e, 1e-3)).failed, 1u);
}

TEST(Materials, LinearElasticIncrementIsHooke) {
  const double K = 2e9, G = 1e9, lam = K - 2 * G / 3;
  auto m = make_linear_elastic(1000, K, G);
  const double L[9] = {1.0, 0.2, 0, 0.2, -0.5, 0, 0, 0, 0};  // symmetric: no rotation
  const double F[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  double s[6] = {}, ws = 0, e = 0;
  const double mass = 1000.0, V = 1.0, dt = 1e-4;
  m->update(one(L, F, s, &mass, &V, &ws, &e, dt));
  EXPECT_NEAR(s[0], dt * (lam * 0.5 + 2 * G * 1.0), 1e-3);
  EXPECT_NEAR(s[1], dt * (lam * 0.5 - 2 * G * 0.5), 1e-3);
  EXPECT_NEAR(s[2], dt * lam * 0.5, 1e-3);
  EXPECT_NEAR(s[5], dt * 2 * G * 0.2, 1e-3);
}

TEST(Materials, TillotsonStyleGivesEosPressureAndStaysFinite) {
  TillotsonParams p;
  auto m = make_tillotson(p, 22.7e9);
  const double L[9] = {}, F[9] = {1 / 1.2, 0, 0, 0, 1, 0, 0, 0, 1};
  double s[6] = {}, ws = 0, e = 0;
  const double mass = 2700.0, V = 1 / 1.2;  // rho = 1.2 rho0
  m->initialize(one(L, F, s, &mass, &V, &ws, &e, 0.0));
  EXPECT_NEAR(-(s[0] + s[1] + s[2]) / 3 / 1e9, 6.408, 1e-3);
  EXPECT_GT(ws, 3144.7);
  // registry carries the style and its schema
  const StyleInfo* st = builtin_materials().find("tillotson");
  ASSERT_NE(st, nullptr);
  EXPECT_NE(st->schema.find("E_cv"), nullptr);
  EXPECT_TRUE(st->state_fields.empty());  // no per-particle state beyond the core arrays
  EXPECT_EQ(builtin_materials().names().size(), 3u + (builtin_materials().find("tonge_ramesh") ? 1u : 0u));
}
