#include "handoff/invariants.hpp"

#include <Eigen/Geometry>
#include <cmath>

namespace handoff {

namespace {
/// Neumaier-compensated running sum.
struct Sum {
  double s = 0.0, c = 0.0;
  void add(double x) {
    const double t = s + x;
    c += (std::fabs(s) >= std::fabs(x)) ? (s - t) + x : (x - t) + s;
    s = t;
  }
  double value() const { return s + c; }
};
}  // namespace

Invariants compute_invariants(std::size_t n, const double* x, const double* v, const double* m,
                              const double* spin, const double* radius) {
  Invariants r;
  r.count = n;
  Sum M, X[3], P[3], K;
  for (std::size_t i = 0; i < n; ++i) {
    M.add(m[i]);
    for (int d = 0; d < 3; ++d) {
      X[d].add(m[i] * x[3 * i + d]);
      P[d].add(m[i] * v[3 * i + d]);
      K.add(0.5 * m[i] * v[3 * i + d] * v[3 * i + d]);
    }
  }
  r.mass = M.value();
  if (!(r.mass > 0.0)) return r;
  for (int d = 0; d < 3; ++d) {
    r.centre_of_mass[d] = X[d].value() / r.mass;
    r.momentum[d] = P[d].value();
  }
  r.kinetic_translational = K.value();
  const Eigen::Vector3d V = r.momentum / r.mass;
  Sum L[3], KR, LS;
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d dx = Eigen::Vector3d(x[3 * i], x[3 * i + 1], x[3 * i + 2]) - r.centre_of_mass;
    const Eigen::Vector3d dv = Eigen::Vector3d(v[3 * i], v[3 * i + 1], v[3 * i + 2]) - V;
    Eigen::Vector3d l = m[i] * dx.cross(dv);
    LS.add(m[i] * dx.norm() * dv.norm());
    if (spin && radius) {
      const double I = 0.4 * m[i] * radius[i] * radius[i];
      const Eigen::Vector3d w(spin[3 * i], spin[3 * i + 1], spin[3 * i + 2]);
      l += I * w;
      LS.add(I * w.norm());
      KR.add(0.5 * I * w.squaredNorm());
    }
    for (int d = 0; d < 3; ++d) L[d].add(l[d]);
  }
  for (int d = 0; d < 3; ++d) r.angular_momentum[d] = L[d].value();
  r.kinetic_rotational = KR.value();
  r.angular_momentum_scale = LS.value();
  return r;
}

}  // namespace handoff
