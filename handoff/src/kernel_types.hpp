/// @file kernel_types.hpp
/// Types shared by the projection (projection.cpp: validation, binning, output allocation) and its
/// inner loops, which are compiled twice: portable (kernels_portable.cpp) and for CPUs with AVX2
/// (kernels_avx2.cpp, chosen at run time). Internal to the handoff library.
#pragma once
#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "common/huge_pages.hpp"
#include "common/particle_file.hpp"
#include "handoff/projection.hpp"
#include "mpm/shape_functions.hpp"

namespace handoff::detail {

struct CoarseGrid {
  Eigen::Vector3i shape;  // sphere cells per axis
  double edge;            // sphere cell edge
  Eigen::Vector3d origin;
  std::int64_t cells() const { return std::int64_t(shape[0]) * shape[1] * shape[2]; }
};

/// Grid constants of the kernels.
struct Lattice {
  Eigen::Vector3d origin;
  double inv_h;
  std::size_t sy, sz;           // node strides in y and z
  std::size_t size_stride = 3;  // 0 when every particle has the first one's size: the kernels then
                                // read one cached triple instead of streaming 24 B per particle
};

/// Everything the inner loops read and write. Particles are visited in `order` (sorted by sphere
/// cell; cell c holds order[start[c] .. start[c+1])); `cells` lists the occupied cells ascending;
/// `node` (4 doubles per grid node, zeroed) receives m and momentum, then m and velocity.
struct KernelArgs {
  const common::ParticleSnapshot& s;
  Lattice L;
  CoarseGrid cg;
  int k;  // coarsen
  const std::vector<std::size_t>& start;
  const common::huge_buffer<std::uint32_t>& order;
  const std::vector<const common::Field*>& carry;
  const std::vector<std::int64_t>& cells;
  common::huge_buffer<double>& node;
  ProjectionResult& r;  // spheres and map allocated; filled here
};

/// P2G, nodal velocities, G2P at each cell's particles and the cell averages (projection.hpp).
/// The two builds give bit-identical results: same operations in the same order, no FMA
/// contraction (tests/handoff/test_projection.cpp, Projection.VectorKernelsEqualPortableBitForBit).
void run_kernels_portable(mpmfrag::ShapeKind kind, const KernelArgs& a);
/// False (and nothing done) where the AVX2 build is not compiled in or the CPU lacks AVX2.
bool run_kernels_avx2(mpmfrag::ShapeKind kind, const KernelArgs& a);
/// Whether run_kernels_avx2 would run.
bool avx2_kernels_available();

}  // namespace handoff::detail
