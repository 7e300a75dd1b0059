/// @file test_invariants.cpp
/// The audit's conserved quantities (handoff/src/invariants.cpp: moments about item 0 shifted to
/// the centre of mass, block-plain / Neumaier sums, the scale in a second pass) against a direct two-pass reference
/// in long double, on a body far from the origin with a fast bulk motion (where a shift about the
/// origin would lose digits), with and without sphere spins, and on 1 and 2 threads.
#include <gtest/gtest.h>
#include <omp.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>
#include <vector>

#include "handoff/invariants.hpp"

using namespace handoff;

namespace {

struct Set {
  std::vector<double> x, v, m, spin, radius;
  std::size_t n() const { return m.size(); }
};

/// A spinning, expanding ball of radius R at `centre` moving at `bulk`, with random scatter.
Set ball(std::size_t n, const Eigen::Vector3d& centre, const Eigen::Vector3d& bulk, double R, unsigned seed) {
  Set s;
  std::mt19937_64 g(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const Eigen::Vector3d omega(0.3, -0.2, 1.1);  // rad/s
  while (s.n() < n) {
    const Eigen::Vector3d r(u(g), u(g), u(g));
    if (r.norm() > 1.0) continue;
    const Eigen::Vector3d x = centre + R * r;
    const Eigen::Vector3d v = bulk + omega.cross(R * r) + 2.0 * R * r + Eigen::Vector3d(u(g), u(g), u(g));
    for (int d = 0; d < 3; ++d) {
      s.x.push_back(x[d]);
      s.v.push_back(v[d]);
      s.spin.push_back(0.01 * u(g));
    }
    s.m.push_back(1e6 * (1.5 + u(g)));
    s.radius.push_back(0.5 + 0.1 * u(g));
  }
  return s;
}

struct Ref {
  long double M = 0, X[3] = {}, P[3] = {}, L[3] = {}, K = 0, KR = 0, cs = 0;  // cs: sum m |x-X||v-V|
};

Ref reference(const Set& s, bool spin) {
  Ref r;
  for (std::size_t i = 0; i < s.n(); ++i) {
    r.M += s.m[i];
    for (int d = 0; d < 3; ++d) {
      r.X[d] += (long double)s.m[i] * s.x[3 * i + d];
      r.P[d] += (long double)s.m[i] * s.v[3 * i + d];
      r.K += 0.5L * s.m[i] * (long double)s.v[3 * i + d] * s.v[3 * i + d];
    }
  }
  long double V[3];
  for (int d = 0; d < 3; ++d) {
    r.X[d] /= r.M;
    V[d] = r.P[d] / r.M;
  }
  for (std::size_t i = 0; i < s.n(); ++i) {
    long double dx[3], dv[3], nx = 0, nv = 0;
    for (int d = 0; d < 3; ++d) {
      dx[d] = s.x[3 * i + d] - r.X[d];
      dv[d] = s.v[3 * i + d] - V[d];
      nx += dx[d] * dx[d];
      nv += dv[d] * dv[d];
    }
    r.L[0] += s.m[i] * (dx[1] * dv[2] - dx[2] * dv[1]);
    r.L[1] += s.m[i] * (dx[2] * dv[0] - dx[0] * dv[2]);
    r.L[2] += s.m[i] * (dx[0] * dv[1] - dx[1] * dv[0]);
    r.cs += s.m[i] * std::sqrt(nx) * std::sqrt(nv);
    if (spin) {
      const long double I = 0.4L * s.m[i] * s.radius[i] * s.radius[i];
      long double w2 = 0;
      for (int d = 0; d < 3; ++d) {
        r.L[d] += I * s.spin[3 * i + d];
        w2 += (long double)s.spin[3 * i + d] * s.spin[3 * i + d];
      }
      r.KR += 0.5L * I * w2;
    }
  }
  return r;
}

}  // namespace

TEST(Invariants, OnePassMatchesATwoPassLongDoubleReference) {
  const double R = 150.0;
  const Set s = ball(70000, Eigen::Vector3d(2.0e6, -1.3e6, 4.0e5), Eigen::Vector3d(5.0e3, 1.0e3, -2.0e3), R, 4);
  for (bool spin : {false, true}) {
    const Invariants a = spin ? compute_invariants(s.n(), s.x.data(), s.v.data(), s.m.data(), s.spin.data(), s.radius.data())
                              : compute_invariants(s.n(), s.x.data(), s.v.data(), s.m.data());
    const Ref r = reference(s, spin);
    long double mv = 0;  // sum m |v|
    for (std::size_t i = 0; i < s.n(); ++i)
      mv += s.m[i] * std::sqrt((long double)s.v[3 * i] * s.v[3 * i] + (long double)s.v[3 * i + 1] * s.v[3 * i + 1] +
                               (long double)s.v[3 * i + 2] * s.v[3 * i + 2]);
    EXPECT_EQ(a.count, s.n());
    EXPECT_NEAR(a.mass, (double)r.M, 1e-14 * (double)r.M);
    for (int d = 0; d < 3; ++d) {
      EXPECT_NEAR(a.centre_of_mass[d], (double)r.X[d], 1e-14 * (2.0e6 + R));  // a few ulps of |x|
      EXPECT_NEAR(a.momentum[d], (double)r.P[d], 1e-14 * (double)mv);
    }
    EXPECT_NEAR(a.kinetic_translational, (double)r.K, 1e-14 * (double)r.K);
    EXPECT_NEAR(a.kinetic_rotational, (double)r.KR, 1e-14 * (double)r.KR + 1e-300);
    // Angular momentum about the centre of mass: to 1e-13 of the spread's scale although the
    // positions are 1e4 R from the origin and the bulk speed is ~1e1 times the spread.
    const Eigen::Vector3d Lref((double)r.L[0], (double)r.L[1], (double)r.L[2]);
    EXPECT_LT((a.angular_momentum - Lref).norm(), 1e-13 * (double)r.cs) << "spin " << spin;
    EXPECT_GT(Lref.norm(), 0.1 * (double)r.cs);  // the test set does rotate
    // Scale: sum m |x-X||v-V| (+ sum I |omega| with spins), an upper bound of |L|.
    long double ls = 0;
    if (spin)
      for (std::size_t i = 0; i < s.n(); ++i)
        ls += 0.4L * s.m[i] * s.radius[i] * s.radius[i] *
              std::sqrt((long double)s.spin[3 * i] * s.spin[3 * i] + (long double)s.spin[3 * i + 1] * s.spin[3 * i + 1] +
                        (long double)s.spin[3 * i + 2] * s.spin[3 * i + 2]);
    EXPECT_NEAR(a.angular_momentum_scale, (double)(r.cs + ls), 1e-12 * (double)(r.cs + ls));
    EXPECT_GE(a.angular_momentum_scale, Lref.norm());
  }
}

TEST(Invariants, ThreadCountDoesNotChangeTheBits) {
  const Set s = ball(100000, Eigen::Vector3d(10.0, 20.0, 30.0), Eigen::Vector3d(0.0, 0.0, 3000.0), 5.0, 9);
  const int saved = omp_get_max_threads();
  omp_set_num_threads(1);
  const Invariants a = compute_invariants(s.n(), s.x.data(), s.v.data(), s.m.data(), s.spin.data(), s.radius.data());
  omp_set_num_threads(2);
  const Invariants b = compute_invariants(s.n(), s.x.data(), s.v.data(), s.m.data(), s.spin.data(), s.radius.data());
  omp_set_num_threads(saved);
  EXPECT_EQ(a.mass, b.mass);
  EXPECT_EQ(a.centre_of_mass, b.centre_of_mass);
  EXPECT_EQ(a.momentum, b.momentum);
  EXPECT_EQ(a.angular_momentum, b.angular_momentum);
  EXPECT_EQ(a.kinetic(), b.kinetic());
  EXPECT_EQ(a.angular_momentum_scale, b.angular_momentum_scale);
}

TEST(Invariants, SingleItemAndEmptySet) {
  const double x[3] = {1e6, 2.0, 3.0}, v[3] = {4.0, 5.0, 6.0}, m[1] = {2.0};
  const Invariants one = compute_invariants(1, x, v, m);
  EXPECT_EQ(one.mass, 2.0);
  EXPECT_EQ(one.centre_of_mass, Eigen::Vector3d(1e6, 2.0, 3.0));
  EXPECT_EQ(one.momentum, Eigen::Vector3d(8.0, 10.0, 12.0));
  EXPECT_EQ(one.angular_momentum, Eigen::Vector3d::Zero());
  EXPECT_EQ(one.angular_momentum_scale, 0.0);
  EXPECT_DOUBLE_EQ(one.kinetic_translational, 0.5 * 2.0 * 77.0);
  const Invariants none = compute_invariants(0, nullptr, nullptr, nullptr);
  EXPECT_EQ(none.count, 0u);
  EXPECT_EQ(none.mass, 0.0);
}
