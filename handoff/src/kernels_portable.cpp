/// @file kernels_portable.cpp
/// The projection's inner loops, portable build: one particle at a time in scalar double
/// arithmetic (any target). See kernel_loops.hpp for the loops and projection.hpp for the equations.
#include <omp.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "common/branchless.hpp"
#include "kernel_types.hpp"

namespace handoff::detail {
namespace {

/// One particle's stencil: the first node's linear index and the per-axis weights.
template <mpmfrag::ShapeKind K>
struct Stencil {
  static constexpr int N = K == mpmfrag::ShapeKind::ugimp ? 3 : 2;  // nodes per axis
  std::size_t base;
  double w[3][N];  // w[axis][node]
};

/// The particle half-widths in cell units, l = size / (2 h), and 1/(4 l), kept from the previous
/// particle: particles of one body share their size, so the three divisions are rarely repeated.
struct HalfWidths {
  explicit HalfWidths(const Lattice&) {}
  double size[3] = {-1.0, -1.0, -1.0};
  double l[3] = {1.0, 1.0, 1.0}, inv4l[3] = {0.25, 0.25, 0.25};
  [[gnu::always_inline]] void update(const double* sz, double inv_h) {
    if (sz[0] == size[0] && sz[1] == size[1] && sz[2] == size[2]) return;
    for (int d = 0; d < 3; ++d) {
      size[d] = sz[d];
      l[d] = 0.5 * sz[d] * inv_h;
      inv4l[d] = 0.25 / l[d];
    }
  }
};

template <mpmfrag::ShapeKind K>
struct PortableOps {
  using Cache = HalfWidths;
  static constexpr int N = Stencil<K>::N;

  [[gnu::always_inline]] static Stencil<K> stencil(const double* x, const double* size, const Lattice& g, HalfWidths& hw) {
    Stencil<K> st;
    hw.update(size, g.inv_h);
    std::size_t base = 0;
    const std::size_t stride[3] = {1, g.sy, g.sz};
    for (int d = 0; d < 3; ++d) {
      const mpmfrag::AxisWeightsOnly a = mpmfrag::axis_weights_only<K>(x[d], g.origin[d], g.inv_h, hw.l[d], hw.inv4l[d]);
      base += static_cast<std::size_t>(a.first) * stride[d];
      for (int k = 0; k < N; ++k) st.w[d][k] = a.w[k];
    }
    st.base = base;
    return st;
  }

  /// Zero weights are added too (every stencil node lies inside the grid): no branches.
  [[gnu::always_inline]] static void scatter(const Stencil<K>& st, const Lattice& g, double m, const double* v, double* node) {
    const double v0 = v[0], v1 = v[1], v2 = v[2];
    for (int c = 0; c < N; ++c)
      for (int b = 0; b < N; ++b) {
        const double myz = m * st.w[1][b] * st.w[2][c];
        double* row = node + 4 * (st.base + b * g.sy + c * g.sz);
        for (int a = 0; a < N; ++a) {
          const double mw = st.w[0][a] * myz;
          row[4 * a] += mw;
          row[4 * a + 1] += mw * v0;
          row[4 * a + 2] += mw * v1;
          row[4 * a + 3] += mw * v2;
        }
      }
  }

  /// Node layout m, vx, vy, vz.
  [[gnu::always_inline]] static void gather(const Stencil<K>& st, const Lattice& g, const double* node, double* vt) {
    double s0 = 0.0, s1 = 0.0, s2 = 0.0;
    for (int c = 0; c < N; ++c)
      for (int b = 0; b < N; ++b) {
        const double wyz = st.w[1][b] * st.w[2][c];
        const double* row = node + 4 * (st.base + b * g.sy + c * g.sz);
        for (int a = 0; a < N; ++a) {
          const double w = st.w[0][a] * wyz;
          s0 += w * row[4 * a + 1];
          s1 += w * row[4 * a + 2];
          s2 += w * row[4 * a + 3];
        }
      }
    vt[0] = s0;
    vt[1] = s1;
    vt[2] = s2;
  }
};

#include "kernel_loops.hpp"

}  // namespace

void run_kernels_portable(mpmfrag::ShapeKind kind, const KernelArgs& a) { run_loops_for<PortableOps>(kind, a); }

}  // namespace handoff::detail
