/// @file scene_setup.hpp
/// The mpm-frag scene schema and the construction of a run (grid, bodies -> particles,
/// materials -> registry styles, solver options) from a resolved scene.
///
/// Bodies are primitives filled with a regular lattice of ppc^3 particles per grid cell
/// (particle volume (h/ppc)^3, mass rho0 V, uGIMP half-width h/(2 ppc)); a lattice point is
/// kept if it lies inside the primitive. Bodies must not overlap and must lie inside the domain.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "common/schema.hpp"
#include "mpm/solver.hpp"

namespace mpmfrag {

/// Run-level options (output, progress, safety).
struct RunConfig {
  double t_end = 0;
  std::string out_dir = "out";
  std::string prefix = "mpm";
  double snapshot_interval = 0;   ///< s; 0 = initial and final only
  int series_every = 10;          ///< steps between time-series rows
  int backup_every = 20;          ///< steps between last-good-state copies
  double progress_interval = 10;  ///< s wall clock
  long long max_steps = 0;        ///< 0 = unlimited
  int threads = 0;                ///< 0 = OpenMP default
};

/// Everything needed to construct a Solver.
struct Setup {
  SolverConfig solver;
  RunConfig run;
  common::GridInfo grid;
  ParticleSet particles;
  std::vector<MaterialSlot> materials;
  BodyForce body_force;  ///< velocity drives of the bodies ([[body]] drive.*; empty: none)
};

/// The full mpm-frag schema (material styles from `reg`).
common::Schema mpm_schema(const MaterialRegistry& reg = builtin_materials());

/// Build the setup; throws common::InputError naming the key on bad input.
Setup build_setup(const common::Scene& scene, const MaterialRegistry& reg = builtin_materials());

}  // namespace mpmfrag
