/// @file outflow.hpp
/// Particles that left the MPM grid (mpm-frag `grid.outflow = "remove"`, file
/// `<prefix>_outflow.h5`) handed off with the same rule as the grid particles: one sphere per
/// occupied sphere cell of the same lattice (origin = grid origin, edge = coarsen * h), extended
/// beyond the grid.
///
/// They move ballistically after leaving the grid, so their positions are first carried to the
/// snapshot time t: x = x_file + v (t - t_file). There is no grid field outside the grid, so the
/// sphere of a lattice cell c takes the particles' own mass-weighted velocity,
///   M_c = sum_{p in c} m_p,  v_c = sum_{p in c} m_p v_p / M_c,  f_c = sum m_p f_p / M_c,
/// which conserves mass and momentum exactly (the kinetic-energy loss is the intra-cell velocity
/// spread). A particle whose cell already holds a sphere of the projection is merged into that
/// sphere with the same mass-weighted rule, so no two spheres share a cell and spheres never
/// overlap. Sphere ids continue after the projection's; the particle map is extended.
#pragma once
#include "common/particle_file.hpp"
#include "handoff/projection.hpp"

namespace handoff {

/// Append (or merge) the particles of `out` (every one of them) to the projection result `r`
/// made from a snapshot on grid `grid` at time `t`. Carries the fields that `r.spheres` carries
/// (each must be present in `out`). Returns the number of spheres added.
/// Throws common::InputError (naming `file`) when the outflow file's grid differs from `grid`
/// or a carried field is missing.
std::size_t append_outflow(const common::ParticleSnapshot& out, const common::GridInfo& grid, double t,
                           ProjectionResult& r, const std::string& file);

}  // namespace handoff
