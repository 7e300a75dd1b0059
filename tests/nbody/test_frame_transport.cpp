// Transport of contact history with the contact frame (contact/part.hpp FrameTransport) and the
// short-angle sin/cos it uses, against independent references: libm and Eigen's AngleAxis
// rotation matrices (Schwartz et al. 2012 eqs 17-19: spin about the mean normal, then the
// rotation that takes n_old to n).
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <limits>

#include "ssdem/contact/part.hpp"

namespace {
using ssdem::Vec3;

TEST(FrameTransport, ShortAngleSinCosAgreeWithLibmToRounding) {
  const double eps = std::numeric_limits<double>::epsilon();
  double worst_s = 0.0, worst_c = 0.0;
  for (int k = -4000; k <= 4000; ++k) {
    // a dense sweep of [-1/16, 1/16] plus tiny and boundary values
    for (double x : {k * (0.0625 / 4000.0), k * 1e-9, 0.0625 - 1e-17 * k}) {
      double c, s;
      ssdem::small_sincos(x, c, s);
      if (x != 0.0) worst_s = std::max(worst_s, std::abs(s - std::sin(x)) / std::abs(std::sin(x)));
      worst_c = std::max(worst_c, std::abs(c - std::cos(x)));
    }
  }
  EXPECT_LE(worst_s, 2.0 * eps) << "sin relative error";
  EXPECT_LE(worst_c, 2.0 * eps) << "cos absolute error";
  for (double x : {0.0625, 0.3, -1.0, 3.0}) {  // libm beyond 1/16: identical
    double c, s;
    ssdem::small_sincos(x, c, s);
    EXPECT_EQ(c, std::cos(x));
    EXPECT_EQ(s, std::sin(x));
  }
}

// Reference: the same two rotations as explicit matrices.
Vec3 reference(const Vec3& no, const Vec3& n, const Vec3& wsum, double h, const Vec3& v) {
  const Vec3 nbar = (no + n).normalized();
  const Eigen::Matrix3d spin = Eigen::AngleAxisd(0.5 * h * wsum.dot(nbar), nbar).toRotationMatrix();
  const Vec3 ax = no.cross(n);
  const double ang = std::atan2(ax.norm(), no.dot(n));
  const Eigen::Matrix3d tilt = Eigen::AngleAxisd(ang, ax.normalized()).toRotationMatrix();
  return tilt * (spin * v);
}

TEST(FrameTransport, MatchesExplicitRotationsForSmallLargeAndWideTurns) {
  const Vec3 no = Vec3(0.3, -0.5, 0.81).normalized();
  const Vec3 perp = no.cross(Vec3(1.0, 0.2, -0.4)).normalized();  // turn axis
  const Vec3 wsum(0.7, -1.1, 0.4);
  for (double turn : {1e-9, 1e-4, 0.05, 0.7, 1.5, 2.2, 3.0}) {  // radians; > pi/2 takes the wide path
    const Vec3 n = Eigen::AngleAxisd(turn, perp) * no;
    for (double h : {0.0, 1e-3, 0.08, 0.5}) {  // spin angle 0, tiny, near 1/16, beyond
      const Vec3 v = no.cross(Vec3(0.1, 0.9, 0.2)) * 3.7;  // a tangent-plane history vector
      const ssdem::FrameTransport tr(no, n, wsum, h);
      const Vec3 got = tr(v);
      const Vec3 want = reference(no, n, wsum, h, v);
      EXPECT_LT((got - want).norm(), 1e-14 * v.norm()) << "turn " << turn << " h " << h;
      EXPECT_NEAR(got.norm(), v.norm(), 1e-14 * v.norm());  // a rotation
      if (h == 0.0) {  // without spin the tilt takes the old tangent plane onto the new one
        EXPECT_LT(std::abs(got.dot(n)), 1e-14 * v.norm()) << "turn " << turn;
      }
    }
  }
  // no turn, no spin: the identity, exactly
  const Vec3 v(1.0, 2.0, 3.0);
  EXPECT_EQ(ssdem::FrameTransport(no, no, Vec3::Zero(), 0.1)(v), v);
}

}  // namespace
