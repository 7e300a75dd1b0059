#include "handoff/invariants.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <vector>

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

namespace {
constexpr std::size_t kChunk = 16384;  // fixed chunks: the sums do not depend on the thread count

struct First {
  Sum M, X[3], P[3], K;
};
struct Second {
  Sum L[3], KR, LS;
};
/// Add a chunk's compensated partial (value and correction) into the running total.
void merge(Sum& into, const Sum& part) {
  into.add(part.s);
  into.add(part.c);
}
}  // namespace

Invariants compute_invariants(std::size_t n, const double* x, const double* v, const double* m,
                              const double* spin, const double* radius) {
  Invariants r;
  r.count = n;
  const std::size_t nc = (n + kChunk - 1) / kChunk;
  std::vector<First> a(nc);
#pragma omp parallel for schedule(static)
  for (std::size_t c = 0; c < nc; ++c) {
    First& f = a[c];
    for (std::size_t i = c * kChunk; i < std::min(n, (c + 1) * kChunk); ++i) {
      f.M.add(m[i]);
      for (int d = 0; d < 3; ++d) {
        f.X[d].add(m[i] * x[3 * i + d]);
        f.P[d].add(m[i] * v[3 * i + d]);
        f.K.add(0.5 * m[i] * v[3 * i + d] * v[3 * i + d]);
      }
    }
  }
  First t;
  for (const First& f : a) {
    merge(t.M, f.M);
    merge(t.K, f.K);
    for (int d = 0; d < 3; ++d) {
      merge(t.X[d], f.X[d]);
      merge(t.P[d], f.P[d]);
    }
  }
  r.mass = t.M.value();
  if (!(r.mass > 0.0)) return r;
  for (int d = 0; d < 3; ++d) {
    r.centre_of_mass[d] = t.X[d].value() / r.mass;
    r.momentum[d] = t.P[d].value();
  }
  r.kinetic_translational = t.K.value();
  const Eigen::Vector3d V = r.momentum / r.mass, X = r.centre_of_mass;
  std::vector<Second> b(nc);
#pragma omp parallel for schedule(static)
  for (std::size_t c = 0; c < nc; ++c) {
    Second& f = b[c];
    for (std::size_t i = c * kChunk; i < std::min(n, (c + 1) * kChunk); ++i) {
      const Eigen::Vector3d dx = Eigen::Vector3d(x[3 * i], x[3 * i + 1], x[3 * i + 2]) - X;
      const Eigen::Vector3d dv = Eigen::Vector3d(v[3 * i], v[3 * i + 1], v[3 * i + 2]) - V;
      Eigen::Vector3d l = m[i] * dx.cross(dv);
      f.LS.add(m[i] * dx.norm() * dv.norm());
      if (spin && radius) {
        const double I = 0.4 * m[i] * radius[i] * radius[i];
        const Eigen::Vector3d w(spin[3 * i], spin[3 * i + 1], spin[3 * i + 2]);
        l += I * w;
        f.LS.add(I * w.norm());
        f.KR.add(0.5 * I * w.squaredNorm());
      }
      for (int d = 0; d < 3; ++d) f.L[d].add(l[d]);
    }
  }
  Second u;
  for (const Second& f : b) {
    merge(u.KR, f.KR);
    merge(u.LS, f.LS);
    for (int d = 0; d < 3; ++d) merge(u.L[d], f.L[d]);
  }
  for (int d = 0; d < 3; ++d) r.angular_momentum[d] = u.L[d].value();
  r.kinetic_rotational = u.KR.value();
  r.angular_momentum_scale = u.LS.value();
  return r;
}

}  // namespace handoff
