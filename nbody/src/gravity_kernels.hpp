/// @file gravity_kernels.hpp
/// Inner loops of the tree walk (internal to the nbody library): one sink group (a tree leaf)
/// against its interaction lists, structure-of-arrays, equations in gravity.hpp. Each loop runs
/// over the list with `omp simd` (a vector reduction per sink), and gravity_kernels.cpp builds
/// every kernel for AVX-512, AVX2+FMA and the baseline ISA, chosen at load time by the CPU
/// (GCC target_clones). The summation order depends on the vector width, i.e. on the CPU, never
/// on the thread count.
/// Precision: the cell and far lists in single precision, in coordinates relative to the group's
/// centre (as pkdgrav does for its interactions): one interaction is rounded to ~1e-7 x (group
/// extent / distance), a list sum to ~1e-6, far below the tree's force error (~1e-3). The near
/// list (overlapping, coincident and collapsed spheres, where separations may be 1e-9 of the
/// group's extent) in double. Per-kernel sums are accumulated into double.
#pragma once
#include <cstddef>
#include <cstdint>

namespace ssdem::detail {

/// Sinks of one group (tree order). Accumulators are added to (not overwritten).
struct GroupSinks {
  std::size_t n = 0;
  const float *x = nullptr, *y = nullptr, *z = nullptr;     ///< relative to the centre
  const double *xd = nullptr, *yd = nullptr, *zd = nullptr, *hd = nullptr;  ///< same, double
  const std::int32_t* tid = nullptr;                                   ///< tree index
  double *ax = nullptr, *ay = nullptr, *az = nullptr, *pot = nullptr;  ///< pot may be null
};

/// Cells used as multipoles: centre of mass, mass, traceless quadrupole (xx, yy, zz, xy, xz, yz).
struct CellList {
  std::size_t n = 0;
  const float *x, *y, *z, *m, *q0, *q1, *q2, *q3, *q4, *q5;
};

/// Source particles of far leaves: position, mass.
struct PartList {
  std::size_t n = 0;
  const float *x, *y, *z, *m;
};
/// Source particles of near leaves: position, mass, radius, tree index.
struct NearList {
  std::size_t n = 0;
  const double *x, *y, *z, *m, *h;
  const std::int32_t* tid;
};

/// Quadrupole cells (never softened: the walk accepts a cell only beyond all softening lengths).
void cell_kernel(const GroupSinks& g, const CellList& c);
/// Particles of leaves farther than every softening length: plain Newtonian pairs.
void far_kernel(const GroupSinks& g, const PartList& p);
/// Particles of leaves that may hold overlapping pairs: spline kernel branch-free, self excluded.
void near_kernel(const GroupSinks& g, const NearList& p);

}  // namespace ssdem::detail
