/// @file gravity_kernels.cpp
/// Vectorised inner loops of the tree walk (gravity_kernels.hpp; equations in gravity.hpp).
/// Per sink, the loop over the interaction list is an `omp simd` reduction; the spline softening
/// of the near list is evaluated branch-free (all three pieces computed, one selected) so it
/// vectorises too. Checked with -fopt-info-vec (each list loop reports "loop vectorized").
///
/// Subnormals: the single-precision cell and far loops run with flush-to-zero and
/// denormals-are-zero set (x86 MXCSR bits FTZ 0x8000, DAZ 0x0040; restored on return). On
/// lattice-like inputs (the one-sphere-per-MPM-cell hand-off, HCP piles) the quadrupole of a
/// symmetric cell cancels to round-off: components of ~1e-37 in kernel units, whose products
/// fall below FLT_MIN = 1.2e-38. Each subnormal operation costs a microcode assist (~100 cycles),
/// and one evaluation on the 8 225-sphere hand-off took 11x longer (49.9 against 4.35 us per
/// sphere, 1 thread, theta = 0.25; the 10^4 HCP pile 1.9x). Flushing them changes a force by
/// < 1e-30 of its value (they are ~1e-30 of the leading terms), far below the float rounding.
#include "gravity_kernels.hpp"

#include <cmath>
#if defined(__SSE__)
#include <xmmintrin.h>
#endif

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(__SANITIZE_ADDRESS__)
#define SSDEM_GRAVITY_CLONES __attribute__((target_clones("arch=x86-64-v4", "arch=x86-64-v3", "default")))
#else
#define SSDEM_GRAVITY_CLONES
#endif
#define SSDEM_INLINE inline __attribute__((always_inline))

namespace ssdem::detail {
namespace {

/// Sets FTZ and DAZ for the scope (x86; elsewhere a no-op: the kernels stay correct, only slower
/// on subnormal-producing inputs).
struct FlushSubnormals {
#if defined(__SSE__)
  unsigned saved = _mm_getcsr();
  FlushSubnormals() { _mm_setcsr(saved | 0x8040u); }
  ~FlushSubnormals() { _mm_setcsr(saved); }
#else
  FlushSubnormals() = default;
#endif
  FlushSubnormals(const FlushSubnormals&) = delete;
  FlushSubnormals& operator=(const FlushSubnormals&) = delete;
};

template <bool Pot>
SSDEM_INLINE void cells(const GroupSinks& g, const CellList& cl) {
  const float *__restrict cx = cl.x, *__restrict cy = cl.y, *__restrict cz = cl.z, *__restrict cm = cl.m;
  const float *__restrict q0 = cl.q0, *__restrict q1 = cl.q1, *__restrict q2 = cl.q2;
  const float *__restrict q3 = cl.q3, *__restrict q4 = cl.q4, *__restrict q5 = cl.q5;
  const std::size_t nc = cl.n;
  for (std::size_t t = 0; t < g.n; ++t) {
    const float xi = g.x[t], yi = g.y[t], zi = g.z[t];
    float ax = 0, ay = 0, az = 0, ph = 0;
#pragma omp simd reduction(+ : ax, ay, az, ph)
    for (std::size_t k = 0; k < nc; ++k) {
      const float rx = xi - cx[k], ry = yi - cy[k], rz = zi - cz[k];
      const float r2 = rx * rx + ry * ry + rz * rz;
      const float ir = 1.0f / std::sqrt(r2), ir2 = ir * ir;
      const float ir3 = ir * ir2, ir5 = ir3 * ir2, ir7 = ir5 * ir2;
      const float qx = q0[k] * rx + q3[k] * ry + q4[k] * rz;
      const float qy = q3[k] * rx + q1[k] * ry + q5[k] * rz;
      const float qz = q4[k] * rx + q5[k] * ry + q2[k] * rz;
      const float rqr = rx * qx + ry * qy + rz * qz;
      const float mono = -cm[k] * ir3 - 2.5f * rqr * ir7;
      ax += mono * rx + qx * ir5;
      ay += mono * ry + qy * ir5;
      az += mono * rz + qz * ir5;
      if constexpr (Pot) ph -= cm[k] * ir + 0.5f * rqr * ir5;
    }
    g.ax[t] += ax;
    g.ay[t] += ay;
    g.az[t] += az;
    if constexpr (Pot) g.pot[t] += ph;
  }
}

template <bool Pot>
SSDEM_INLINE void far(const GroupSinks& g, const PartList& pl) {
  const float *__restrict px = pl.x, *__restrict py = pl.y, *__restrict pz = pl.z, *__restrict pm = pl.m;
  const std::size_t np = pl.n;
  for (std::size_t t = 0; t < g.n; ++t) {
    const float xi = g.x[t], yi = g.y[t], zi = g.z[t];
    float ax = 0, ay = 0, az = 0, ph = 0;
#pragma omp simd reduction(+ : ax, ay, az, ph)
    for (std::size_t k = 0; k < np; ++k) {
      const float rx = px[k] - xi, ry = py[k] - yi, rz = pz[k] - zi;
      const float r2 = rx * rx + ry * ry + rz * rz;
      const float ir = 1.0f / std::sqrt(r2);
      const float mir = pm[k] * ir, f = mir * ir * ir;
      ax += f * rx;
      ay += f * ry;
      az += f * rz;
      if constexpr (Pot) ph -= mir;
    }
    g.ax[t] += ax;
    g.ay[t] += ay;
    g.az[t] += az;
    if constexpr (Pot) g.pot[t] += ph;
  }
}

template <bool Pot>
SSDEM_INLINE void near(const GroupSinks& g, const NearList& pl) {
  const double *__restrict px = pl.x, *__restrict py = pl.y, *__restrict pz = pl.z, *__restrict pm = pl.m;
  const double *__restrict ph_ = pl.h;
  const std::int32_t *__restrict pt = pl.tid;
  const std::size_t np = pl.n;
  for (std::size_t t = 0; t < g.n; ++t) {
    const double xi = g.xd[t], yi = g.yd[t], zi = g.zd[t], hi = g.hd[t];
    const std::int32_t ti = g.tid[t];
    double ax = 0, ay = 0, az = 0, ph = 0;
#pragma omp simd reduction(+ : ax, ay, az, ph)
    for (std::size_t k = 0; k < np; ++k) {
      const double rx = px[k] - xi, ry = py[k] - yi, rz = pz[k] - zi;
      const double r2 = rx * rx + ry * ry + rz * rz;
      const double m = pt[k] == ti ? 0.0 : pm[k];  // no self-interaction
      const double h = hi + ph_[k];
      const double r = std::sqrt(r2), ir = 1.0 / r;  // ir = inf only at r = 0 (not selected)
      const double ih = 1.0 / h, u = r * ih, u2 = u * u, ih3 = ih * ih * ih;
      const double iu = h * ir, iu3 = iu * iu * iu;
      // spline pieces (gravity.hpp): u < 1/2, 1/2 <= u < 1, u >= 1
      const double fa = ih3 * (32.0 / 3.0 - u2 * (38.4 - 32.0 * u));
      const double fb = ih3 * (64.0 / 3.0 - 48.0 * u + 38.4 * u2 - 32.0 / 3.0 * u2 * u - iu3 / 15.0);
      const double fn = ir * ir * ir;
      const double f = u < 0.5 ? fa : (u < 1.0 ? fb : fn);
      ax += m * f * rx;
      ay += m * f * ry;
      az += m * f * rz;
      if constexpr (Pot) {
        const double wa = ih * (2.8 - u2 * (16.0 / 3.0 - u2 * (9.6 - 6.4 * u)));
        const double wb =
            ih * (3.2 - iu / 15.0 - u2 * (32.0 / 3.0 - u * (16.0 - u * (9.6 - 32.0 / 15.0 * u))));
        ph -= m * (u < 0.5 ? wa : (u < 1.0 ? wb : ir));
      }
    }
    g.ax[t] += ax;
    g.ay[t] += ay;
    g.az[t] += az;
    if constexpr (Pot) g.pot[t] += ph;
  }
}
}  // namespace

SSDEM_GRAVITY_CLONES void cell_kernel(const GroupSinks& g, const CellList& c) {
  const FlushSubnormals ftz;
  if (g.pot) cells<true>(g, c);
  else cells<false>(g, c);
}
SSDEM_GRAVITY_CLONES void far_kernel(const GroupSinks& g, const PartList& p) {
  const FlushSubnormals ftz;
  if (g.pot) far<true>(g, p);
  else far<false>(g, p);
}
SSDEM_GRAVITY_CLONES void near_kernel(const GroupSinks& g, const NearList& p) {
  if (g.pot) near<true>(g, p);
  else near<false>(g, p);
}

}  // namespace ssdem::detail
