/// @file kernels_avx2.cpp
/// The projection's inner loops, AVX2 build, chosen at run time (run_kernels_avx2) on x86-64 CPUs
/// that have AVX2; everywhere else the portable build runs (kernels_portable.cpp).
///
/// What differs from the portable build: one particle's three axes are evaluated together in one
/// 4-lane vector (x, y, z, unused), and a grid node's four accumulators (m, px, py, pz) — or
/// (m, vx, vy, vz) in the gather — are one 32-byte vector, so the 27-node scatter is 27 vector
/// read-modify-writes instead of 108 scalar ones. The operations, their order and the rounding are
/// those of the portable build lane by lane (no FMA: the target is "avx2" without "fma", so nothing
/// is contracted), so both builds give the same bits (tested).
///
/// Target selection: `#pragma GCC target("avx2")` below applies to the functions defined after it,
/// including the OpenMP regions outlined from them. Every header is included before the pragma, so
/// inline library functions (std::, Eigen) keep the default target and cannot leak AVX2 code into
/// the rest of the program through the linker's choice among duplicate inline definitions.
#include <omp.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "common/branchless.hpp"
#include "kernel_types.hpp"

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#include <immintrin.h>  // x86 only; on other targets this file compiles to the "not available" stubs
#define HANDOFF_AVX2_KERNELS 1
#pragma GCC push_options
#pragma GCC target("avx2")

namespace handoff::detail {
namespace {

typedef double v4d __attribute__((vector_size(32)));
typedef double v4u __attribute__((vector_size(32), aligned(8)));  // unaligned loads and stores
typedef long long v4l __attribute__((vector_size(32)));

/// One particle's stencil: first node's linear index; w[node] holds that node's weight per axis
/// in lanes 0..2 (x, y, z).
template <mpmfrag::ShapeKind K>
struct StencilV {
  static constexpr int N = K == mpmfrag::ShapeKind::ugimp ? 3 : 2;
  std::size_t base;
  v4d w[N];
};

/// Per-thread constants and the half-widths of the previous particle (as HalfWidths in the
/// portable build: l = size / (2 h), 1/(4 l), recomputed only when the size changes).
struct CacheV {
  v4d origin;
  v4d stride;  // node strides (1, sy, sz, 0) as doubles
  double size[3] = {-1.0, -1.0, -1.0};
  v4d l = {1.0, 1.0, 1.0, 1.0}, inv4l = {0.25, 0.25, 0.25, 0.25};
  explicit CacheV(const Lattice& g)
      : origin{g.origin[0], g.origin[1], g.origin[2], 0.0},
        stride{1.0, static_cast<double>(g.sy), static_cast<double>(g.sz), 0.0} {}
  [[gnu::always_inline]] void update(const double* sz, double inv_h) {
    if (sz[0] == size[0] && sz[1] == size[1] && sz[2] == size[2]) return;
    size[0] = sz[0];
    size[1] = sz[1];
    size[2] = sz[2];
    const v4d s = {sz[0], sz[1], sz[2], 1.0};
    l = 0.5 * s * inv_h;
    inv4l = 0.25 / l;
  }
};

template <mpmfrag::ShapeKind K>
struct Avx2Ops {
  using Cache = CacheV;
  static constexpr int N = StencilV<K>::N;

  /// mpmfrag::axis_weights_only for the three axes at once (same expressions, lane-wise).
  [[gnu::always_inline]] static StencilV<K> stencil(const double* x, const double* size, const Lattice& g, CacheV& c) {
    c.update(size, g.inv_h);
    const v4d one = {1.0, 1.0, 1.0, 1.0}, zero = {0.0, 0.0, 0.0, 0.0};
    const v4d xv = {x[0], x[1], x[2], 0.0};
    const v4d xi = (xv - c.origin) * g.inv_h;
    const v4d fl = _mm256_floor_pd(xi);  // = floor_to_int(xi), exactly, for the validated |xi| < 2^31
    const v4d f = xi - fl;
    StencilV<K> st;
    v4d first;  // first node per axis, an integer in a double
    if constexpr (K == mpmfrag::ShapeKind::linear) {
      first = fl;
      st.w[0] = one - f;
      st.w[1] = f;
    } else {
      const v4l low = f <= 0.5;
      const v4d u = low ? f + 1.0 : f;               // distance to the first node, in cells
      first = low ? fl - one : fl;                  // i - 1 where f <= 1/2
      const v4d l = c.l, inv4l = c.inv4l;
      auto outer = [&](v4d d) {  // node at distance d in [1/2, 3/2]
        const v4d t0 = one + l - d;
        const v4d t = zero < t0 ? t0 : zero;
        const v4d q = t * t * inv4l;
        return d <= one - l ? one - d : q;
      };
      const v4d cm = (v4d)((v4l)(u - one) & (v4l){~(1ll << 63), ~(1ll << 63), ~(1ll << 63), ~(1ll << 63)});  // |u - 1|
      st.w[0] = outer(u);
      st.w[1] = cm < l ? one - (cm * cm + l * l) * (2.0 * inv4l) : one - cm;
      st.w[2] = outer(2.0 - u);
    }
    const v4d b = first * c.stride;  // node index terms, integers below 2^53: exact in doubles
    st.base = static_cast<std::size_t>(b[0] + b[1] + b[2]);
    return st;
  }

  /// node (m, px, py, pz) += (S_ip m_p) (1, vx, vy, vz); zero weights added too (no branches).
  [[gnu::always_inline]] static void scatter(const StencilV<K>& st, const Lattice& g, double m, const double* v, double* node) {
    const v4d mv = {1.0, v[0], v[1], v[2]};
    for (int c = 0; c < N; ++c)
      for (int b = 0; b < N; ++b) {
        const double myz = m * st.w[b][1] * st.w[c][2];
        double* row = node + 4 * (st.base + b * g.sy + c * g.sz);
        for (int a = 0; a < N; ++a) {
          const double mw = st.w[a][0] * myz;
          v4u* r = reinterpret_cast<v4u*>(row + 4 * a);
          *r = *r + mw * mv;
        }
      }
  }

  /// vt = sum_i S_ip v_i (node layout m, vx, vy, vz; lane 0 of the sum is unused).
  [[gnu::always_inline]] static void gather(const StencilV<K>& st, const Lattice& g, const double* node, double* vt) {
    v4d acc = {0.0, 0.0, 0.0, 0.0};
    for (int c = 0; c < N; ++c)
      for (int b = 0; b < N; ++b) {
        const double wyz = st.w[b][1] * st.w[c][2];
        const double* row = node + 4 * (st.base + b * g.sy + c * g.sz);
        for (int a = 0; a < N; ++a) {
          const double w = st.w[a][0] * wyz;
          acc = acc + w * *reinterpret_cast<const v4u*>(row + 4 * a);
        }
      }
    vt[0] = acc[1];
    vt[1] = acc[2];
    vt[2] = acc[3];
  }
};

#include "kernel_loops.hpp"

}  // namespace

// Defined under the pragma: compiled for AVX2, so called only after the CPU check below.
[[gnu::noinline]] static void run_avx2(mpmfrag::ShapeKind kind, const KernelArgs& a) { run_loops_for<Avx2Ops>(kind, a); }

}  // namespace handoff::detail

#pragma GCC pop_options
#endif

namespace handoff::detail {

bool avx2_kernels_available() {
#ifdef HANDOFF_AVX2_KERNELS
  static const bool ok = __builtin_cpu_supports("avx2");
  return ok;
#else
  return false;
#endif
}

bool run_kernels_avx2(mpmfrag::ShapeKind kind, const KernelArgs& a) {
#ifdef HANDOFF_AVX2_KERNELS
  if (!avx2_kernels_available()) return false;
  run_avx2(kind, a);
  return true;
#else
  (void)kind;
  (void)a;
  return false;
#endif
}

}  // namespace handoff::detail
