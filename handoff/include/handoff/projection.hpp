/// @file projection.hpp
/// The hand-off of El Mir, Ramesh & Richardson (2019, §4.2 and the lower row of Fig. 1): MPM
/// particles -> one soft sphere per occupied grid cell.
///
/// Governing equations (uGIMP weights S_ip from mpm-frag's shape_functions.hpp: the solver's S(d)
/// in its weights-only, branch-free form axis_weights_only, tested equal to the solver's
/// axis_weights; particle half-widths l_p = size_p / 2 from the snapshot):
///   P2G:  m_i = sum_p S_ip m_p,          p_i = sum_p S_ip m_p v_p,        v_i = p_i / m_i
///   G2P:  v~_p = sum_i S_ip v_i                                   (grid velocity at particle p)
///   cell c (of edge k*h, k = `coarsen`), particles p in c:
///         M_c = sum_{p in c} m_p,         v_c = sum_{p in c} m_p v~_p / M_c,
///         x_c = cell centre,              r_c = k h / 2,          omega_c = 0,
///         f_c = sum_{p in c} m_p f_p / M_c   for each carried scalar field f (e.g. damage).
/// Conservation by construction: sum_c M_c = sum_p m_p, and, by the partition of unity
/// sum_i S_ip = 1, sum_c M_c v_c = sum_i v_i sum_p S_ip m_p = sum_i p_i = sum_p m_p v_p.
///
/// Deviation from a literal reading of the paper ("interpolate the nodal velocities to the cell
/// centre"): interpolating v_i at the cell centre itself does not conserve momentum exactly (nodes
/// touched only by particles of empty neighbour cells would be orphaned), so the nodal velocities
/// are interpolated at the particles of the cell and mass-averaged, which is the unique
/// momentum-conserving cell average of the same grid field. For a rigid translation both agree.
///
/// Kinetic energy is not conserved: the loss is sum_p m_p |v_p|^2/2 - sum_c M_c |v_c|^2/2 >= 0
/// (grid smoothing plus intra-cell velocity spread). For a uniform rotation omega about z of a
/// body filled with n^3 particles per cell, the interior contribution is
///   dK = sum_c M_c omega^2 sigma^2,  sigma^2 = (k h)^2 (1 - 1/(k n)^2) / 12
/// (the rotational energy of each cell's particles about the cell's centre of mass); surface
/// nodes see particles on one side only, so the surface layer moves as if pulled towards the
/// axis and adds a loss of the same order, (h/R)^2 relative (derived per axis and checked in
/// tests/handoff/test_projection.cpp: 3.3 % for a 12-cell box, 0.87 % for a 24-cell box).
/// Spin is zero by default: assigning each sphere the intra-cell angular momentum as spin
/// would need a moment of inertia (2/5) M (kh/2)^2 = M (kh)^2/10 < M (kh)^2/6 (that of the
/// filled cell), so it would create kinetic energy that the particles did not have.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "common/huge_pages.hpp"
#include "common/particle_file.hpp"
#include "common/sphere_file.hpp"
#include "mpm/shape_functions.hpp"

namespace handoff {

struct ProjectionOptions {
  mpmfrag::ShapeKind shape = mpmfrag::ShapeKind::ugimp;
  int coarsen = 1;                        ///< sphere cell edge = coarsen * MPM cell edge
  std::vector<std::string> carry_fields;  ///< scalar particle fields to mass-average onto spheres
  /// Use the AVX2 build of the inner loops where the CPU has AVX2 (same bits as the portable
  /// build, ~2x faster); false forces the portable build (tests compare the two).
  bool vector_kernels = true;
};

/// CSR map sphere -> particle ids: sphere s holds particle_id[offset[s] .. offset[s+1]).
struct SphereParticleMap {
  std::vector<std::uint64_t> offset;
  common::huge_vector<std::uint64_t> particle_id;  // one per particle: on huge pages
};

struct ProjectionResult {
  common::SphereSet spheres;  ///< ids 0..N-1 in cell order (z slowest), spin 0
  SphereParticleMap map;
  std::vector<std::int64_t> cell;   ///< linear index of each sphere's cell (x fastest)
  Eigen::Vector3i cell_shape;       ///< sphere-cell counts per axis
  double sphere_cell = 0.0;         ///< sphere cell edge [m]
  std::size_t occupied_mpm_cells = 0;
  std::string kernels;              ///< build of the inner loops that ran: "avx2" or "portable"
};

/// Project a snapshot (every particle in it) onto spheres. Throws common::InputError for an
/// empty snapshot, a particle whose stencil leaves the grid, particles larger than a cell, or a
/// non-cubic grid.
ProjectionResult project_to_spheres(const common::ParticleSnapshot& s, const ProjectionOptions& opt,
                                    const std::string& file);

/// Whether this CPU runs the AVX2 build of the projection's inner loops (ProjectionOptions::vector_kernels).
bool vector_kernels_available();

}  // namespace handoff
