/// @file gravity_kernels.cpp
/// Vectorised inner loops of the tree walk (gravity_kernels.hpp; equations in gravity.hpp).
/// Per sink, the loop over the interaction list is an `omp simd` reduction (the near list's loop,
/// with the spline softening, is in gravity_near_kernel.cpp). Checked with -fopt-info-vec (each
/// list loop reports "loop vectorized").
///
/// Subnormals: the single-precision loops (cells, far and near lists) run with flush-to-zero and
/// denormals-are-zero set (x86 MXCSR bits FTZ 0x8000, DAZ 0x0040; restored on return). On
/// lattice-like inputs (the one-sphere-per-MPM-cell hand-off, HCP piles) the quadrupole of a
/// symmetric cell cancels to round-off: components of ~1e-37 in kernel units, whose products
/// fall below FLT_MIN = 1.2e-38. Each subnormal operation costs a microcode assist (~100 cycles),
/// and one evaluation on the 8 225-sphere hand-off took 11x longer (49.9 against 4.35 us per
/// sphere, 1 thread, theta = 0.25; the 10^4 HCP pile 1.9x). Flushing them changes a force by
/// < 1e-30 of its value (they are ~1e-30 of the leading terms), far below the float rounding.
#include "gravity_kernels.hpp"

#include <cmath>

namespace ssdem::detail {
namespace {

// One interaction of a sink with a quadrupole cell (separation r = sink - cell centre), added to
// the sink's sums.
template <bool Pot>
SSDEM_INLINE void cell_term(float rx, float ry, float rz, float m, float q0, float q1, float q2, float q3,
                            float q4, float q5, float& ax, float& ay, float& az, float& ph) {
  const float r2 = rx * rx + ry * ry + rz * rz;
  const float ir = 1.0f / std::sqrt(r2), ir2 = ir * ir;
  const float ir3 = ir * ir2, ir5 = ir3 * ir2, ir7 = ir5 * ir2;
  const float qx = q0 * rx + q3 * ry + q4 * rz;
  const float qy = q3 * rx + q1 * ry + q5 * rz;
  const float qz = q4 * rx + q5 * ry + q2 * rz;
  const float rqr = rx * qx + ry * qy + rz * qz;
  const float mono = -m * ir3 - 2.5f * rqr * ir7;
  ax += mono * rx + qx * ir5;
  ay += mono * ry + qy * ir5;
  az += mono * rz + qz * ir5;
  if constexpr (Pot) ph -= m * ir + 0.5f * rqr * ir5;
}
// One interaction of a sink with a particle (separation r = particle - sink).
template <bool Pot>
SSDEM_INLINE void far_term(float rx, float ry, float rz, float m, float& ax, float& ay, float& az, float& ph) {
  const float r2 = rx * rx + ry * ry + rz * rz;
  const float ir = 1.0f / std::sqrt(r2);
  const float mir = m * ir, f = mir * ir * ir;
  ax += f * rx;
  ay += f * ry;
  az += f * rz;
  if constexpr (Pot) ph -= mir;
}

// Sums of one sink, added to its accumulators.
template <bool Pot>
SSDEM_INLINE void add_sums(const GroupSinks& g, std::size_t t, float ax, float ay, float az, float ph) {
  g.ax[t] += ax;
  g.ay[t] += ay;
  g.az[t] += az;
  if constexpr (Pot) g.pot[t] += ph;
}

template <bool Pot>
SSDEM_INLINE void cells(const GroupSinks& g, const CellList& cl) {
  const float *__restrict cx = cl.x, *__restrict cy = cl.y, *__restrict cz = cl.z, *__restrict cm = cl.m;
  const float *__restrict q0 = cl.q0, *__restrict q1 = cl.q1, *__restrict q2 = cl.q2;
  const float *__restrict q3 = cl.q3, *__restrict q4 = cl.q4, *__restrict q5 = cl.q5;
  const float *__restrict sx = g.x, *__restrict sy = g.y, *__restrict sz = g.z;
  sink_passes(
      g.n, cl.n,
      [=](std::size_t t, std::size_t k, float& ax, float& ay, float& az, float& ph) SSDEM_LAMBDA_INLINE {
        cell_term<Pot>(sx[t] - cx[k], sy[t] - cy[k], sz[t] - cz[k], cm[k], q0[k], q1[k], q2[k], q3[k], q4[k], q5[k],
                       ax, ay, az, ph);
      },
      [&g](std::size_t t, float ax, float ay, float az, float ph) { add_sums<Pot>(g, t, ax, ay, az, ph); });
}

template <bool Pot>
SSDEM_INLINE void far(const GroupSinks& g, const PartList& pl) {
  const float *__restrict px = pl.x, *__restrict py = pl.y, *__restrict pz = pl.z, *__restrict pm = pl.m;
  const float *__restrict sx = g.x, *__restrict sy = g.y, *__restrict sz = g.z;
  sink_passes(
      g.n, pl.n,
      [=](std::size_t t, std::size_t k, float& ax, float& ay, float& az, float& ph) SSDEM_LAMBDA_INLINE {
        far_term<Pot>(px[k] - sx[t], py[k] - sy[t], pz[k] - sz[t], pm[k], ax, ay, az, ph);
      },
      [&g](std::size_t t, float ax, float ay, float az, float ph) { add_sums<Pot>(g, t, ax, ay, az, ph); });
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

}  // namespace ssdem::detail
