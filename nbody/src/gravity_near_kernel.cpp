/// @file gravity_near_kernel.cpp
/// The near list's loop of the tree walk (gravity_kernels.hpp; spline kernel in gravity.hpp):
/// the pairs that may overlap. Each separation is a difference of doubles (the coordinates
/// relative to the group's centre carry ~1e-16 of the group's extent, so a pair 1e-9 of the
/// extent apart keeps ~1e-7 of its separation) rounded to float once; the spline is then
/// evaluated in single precision, branch-free (all three pieces computed, one selected; 1/r is
/// infinite at r = 0 only in a piece not selected), in units of the group's largest radius (u =
/// r/h and h near 1: no float overflow of 1/h^3 unless the radii within one group differ by
/// ~1e12), with flush-to-zero as the other loops (gravity_kernels.cpp). Sinks are taken two at a
/// time (`sink_passes`, gravity_kernels.hpp).
///
/// Until 2026-12-06 the whole loop ran in double: 8 lanes of double divisions and square roots
/// against 16 of float. Rounding now: the separation to ~1e-7 of itself, the pair force to
/// ~1e-6 (a handful of float operations), a sink's near sum to ~1e-6 of its terms' size: below
/// the tree's 1e-3 by three orders (measured against direct summation in nbody/README.md).
#include <cmath>
#include <cstdint>

#include "gravity_kernels.hpp"

namespace ssdem::detail {
namespace {

// One sink-particle pair: separation r (particle - sink), source mass m, h = h_sink + h_source.
template <bool Pot>
SSDEM_INLINE void near_term(float rx, float ry, float rz, float m, float h, float& ax, float& ay, float& az,
                            float& ph) {
  const float r2 = rx * rx + ry * ry + rz * rz;
  const float r = std::sqrt(r2), ir = 1.0f / r;  // ir = inf only at r = 0 (not selected)
  const float ih = 1.0f / h, u = r * ih, u2 = u * u, ih3 = ih * ih * ih;
  const float iu = h * ir, iu3 = iu * iu * iu;
  // spline pieces (gravity.hpp): u < 1/2, 1/2 <= u < 1, u >= 1
  const float fa = ih3 * (32.0f / 3.0f - u2 * (38.4f - 32.0f * u));
  const float fb = ih3 * (64.0f / 3.0f - 48.0f * u + 38.4f * u2 - 32.0f / 3.0f * u2 * u - iu3 / 15.0f);
  const float fn = ir * ir * ir;
  const float f = u < 0.5f ? fa : (u < 1.0f ? fb : fn);
  const float mf = m * f;
  ax += mf * rx;
  ay += mf * ry;
  az += mf * rz;
  if constexpr (Pot) {
    const float wa = ih * (2.8f - u2 * (16.0f / 3.0f - u2 * (9.6f - 6.4f * u)));
    const float wb = ih * (3.2f - iu / 15.0f - u2 * (32.0f / 3.0f - u * (16.0f - u * (9.6f - 32.0f / 15.0f * u))));
    ph -= m * (u < 0.5f ? wa : (u < 1.0f ? wb : ir));
  }
}

// Sums of one sink (near-list units) added to its accumulators (kernel units).
template <bool Pot>
SSDEM_INLINE void add_scaled(const GroupSinks& g, const NearList& pl, std::size_t t, float ax, float ay, float az,
                             float ph) {
  g.ax[t] += pl.acc_scale * ax;
  g.ay[t] += pl.acc_scale * ay;
  g.az[t] += pl.acc_scale * az;
  if constexpr (Pot) g.pot[t] += pl.pot_scale * ph;
}

template <bool Pot>
SSDEM_INLINE void near(const GroupSinks& g, const NearList& pl) {
  const double *__restrict px = pl.x, *__restrict py = pl.y, *__restrict pz = pl.z;
  const float *__restrict pm = pl.m, *__restrict phs = pl.h;
  const std::int32_t* __restrict pt = pl.tid;
  const double *__restrict sx = g.xd, *__restrict sy = g.yd, *__restrict sz = g.zd;
  const float* __restrict sh = g.h;
  const std::int32_t* __restrict st = g.tid;
  sink_passes(
      g.n, pl.n,
      [=](std::size_t t, std::size_t k, float& ax, float& ay, float& az, float& ph) SSDEM_LAMBDA_INLINE {
        near_term<Pot>(static_cast<float>(px[k] - sx[t]), static_cast<float>(py[k] - sy[t]),
                       static_cast<float>(pz[k] - sz[t]), pt[k] == st[t] ? 0.0f : pm[k], sh[t] + phs[k], ax, ay, az,
                       ph);
      },
      [&](std::size_t t, float ax, float ay, float az, float ph) { add_scaled<Pot>(g, pl, t, ax, ay, az, ph); });
}
}  // namespace

SSDEM_GRAVITY_CLONES void near_kernel(const GroupSinks& g, const NearList& p) {
  const FlushSubnormals ftz;
  if (g.pot) near<true>(g, p);
  else near<false>(g, p);
}

}  // namespace ssdem::detail
