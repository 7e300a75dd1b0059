/// @file gravity_kernels.hpp
/// Inner loops of the tree walk (internal to the nbody library): one sink group (a subtree of at
/// most `gravity.group` spheres) against its interaction lists, structure-of-arrays, equations in gravity.hpp. Each loop runs
/// over the list with `omp simd` (a vector reduction per sink), and gravity_kernels.cpp (cells,
/// far particles) and gravity_near_kernel.cpp (near particles) build every kernel for AVX-512,
/// AVX2+FMA and the baseline ISA, chosen at load time by the CPU (GCC target_clones). The
/// summation order depends on the vector width, i.e. on the CPU, never on the thread count.
/// Precision: the cell and far lists in single precision, in coordinates relative to the group's
/// centre (as pkdgrav does for its interactions): one interaction is rounded to ~1e-7 x (group
/// extent / distance), a list sum to ~1e-6, far below the tree's force error (~1e-3). The near
/// list (overlapping, coincident and collapsed spheres, where separations may be 1e-9 of the
/// group's extent) takes each pair's separation as a difference of doubles (which carry ~1e-16
/// of the group's extent), rounded to float once, and evaluates the spline in single precision,
/// in units of the group's largest radius (details in gravity_near_kernel.cpp); the walk keeps
/// on it every source within 1e-3 of the group's extent of the group's box, so that the float
/// lists' separations stay good to ~1e-4. Per-kernel sums are accumulated into double.
#pragma once
#include <cstddef>
#include <cstdint>
#if defined(__SSE__)
#include <xmmintrin.h>
#endif

// Each kernel is built for AVX-512, AVX2+FMA and the baseline ISA, chosen at load time.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(__SANITIZE_ADDRESS__)
#define SSDEM_GRAVITY_CLONES __attribute__((target_clones("arch=x86-64-v4", "arch=x86-64-v3", "default")))
#else
#define SSDEM_GRAVITY_CLONES
#endif
#define SSDEM_INLINE inline __attribute__((always_inline))
#define SSDEM_LAMBDA_INLINE __attribute__((always_inline))

namespace ssdem::detail {

/// Sinks of one group (tree order). Accumulators are added to (not overwritten).
struct GroupSinks {
  std::size_t n = 0;
  const float *x = nullptr, *y = nullptr, *z = nullptr;  ///< relative to the centre
  const double *xd = nullptr, *yd = nullptr, *zd = nullptr;  ///< same, in near-list units, double
  const float* h = nullptr;                                   ///< radius, near-list units
  const std::int32_t* tid = nullptr;                                   ///< tree index
  double *ax = nullptr, *ay = nullptr, *az = nullptr, *pot = nullptr;  ///< pot may be null
};

/// Cells used as multipoles: centre of mass, mass, traceless quadrupole (xx, yy, zz, xy, xz, yz).
struct CellList {
  std::size_t n = 0;
  const float *x, *y, *z, *m, *q0, *q1, *q2, *q3, *q4, *q5;
};

/// Source particles that cannot overlap any sink (far leaves, and the particles of near leaves
/// that the walk splits off): position, mass.
struct PartList {
  std::size_t n = 0;
  const float *x, *y, *z, *m;
};
/// Source particles that may overlap a sink: position (double), mass, radius, tree index, in
/// near-list units: lengths relative to the group's centre in units of its largest radius, so
/// the sums are converted to kernel units by `acc_scale` = (L / that radius)^2 and `pot_scale`
/// = L / that radius.
struct NearList {
  std::size_t n = 0;
  const double *x, *y, *z;
  const float *m, *h;
  const std::int32_t* tid;
  double acc_scale = 1, pot_scale = 1;
};

/// Sets FTZ and DAZ for the scope (x86; elsewhere a no-op: the kernels stay correct, only slower
/// on subnormal-producing inputs). Why: gravity_kernels.cpp.
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

/// Quadrupole cells (never softened: the walk accepts a cell only beyond all softening lengths).
void cell_kernel(const GroupSinks& g, const CellList& c);
/// Particles farther than every softening length: plain Newtonian pairs.
void far_kernel(const GroupSinks& g, const PartList& p);
/// Particles that may overlap a sink: spline kernel branch-free, self excluded.
void near_kernel(const GroupSinks& g, const NearList& p);

/// Every sink of a group against a list of `n` entries, two sinks per pass: each entry is loaded
/// once for the pair and the two sinks' independent chains overlap (one sink per pass is bound by
/// the latency of 1/sqrt and the powers of 1/r). `term(t, k, ax, ay, az, ph)` adds entry k's
/// interaction with sink t to the sums; `add(t, ax, ay, az, ph)` stores sink t's sums. An odd
/// last sink takes a pass alone. Whether a sink's sum comes out the same in a paired pass and in
/// a pass of its own depends on how the compiler splits the reduction into lanes (with GCC: one
/// vector accumulator per sum and the same width in both loops); nothing relies on it, since the
/// pairing of a group's sinks is fixed by the group (the same on any thread and rank count).
template <class Term, class Add>
SSDEM_INLINE void sink_passes(std::size_t ns, std::size_t n, Term term, Add add) {
  std::size_t t = 0;
  for (; t + 2 <= ns; t += 2) {
    float axa = 0, aya = 0, aza = 0, pha = 0, axb = 0, ayb = 0, azb = 0, phb = 0;
#pragma omp simd reduction(+ : axa, aya, aza, pha, axb, ayb, azb, phb)
    for (std::size_t k = 0; k < n; ++k) {
      term(t, k, axa, aya, aza, pha);
      term(t + 1, k, axb, ayb, azb, phb);
    }
    add(t, axa, aya, aza, pha);
    add(t + 1, axb, ayb, azb, phb);
  }
  if (t < ns) {
    float ax = 0, ay = 0, az = 0, ph = 0;
#pragma omp simd reduction(+ : ax, ay, az, ph)
    for (std::size_t k = 0; k < n; ++k) term(t, k, ax, ay, az, ph);
    add(t, ax, ay, az, ph);
  }
}

}  // namespace ssdem::detail
