/// @file memory_bounds.hpp
/// The memory a scene will need, estimated from its keys before anything is allocated, so that a
/// grid or a body too large for the machine ends in exit 2 naming the keys and the computed size
/// (not std::bad_alloc, or the kernel's out-of-memory killer once the zero-filled grid is touched).
///
///   grid:      nodes = prod_d (ceil((max_d - min_d) / h) + 1 + 2 ghost), 88 bytes each
///              (the 64-byte node record plus MUSL's re-projected momentum)
///   particles: per body, volume * (ppc / h)^3 (sphere 4/3 pi r^3, box, cylinder pi r^2 L), each
///              2 x (the ParticleSet arrays + its material's state fields) + 96 bytes (the
///              last-good-state copy, binning keys, the generator's record)
/// The total must not exceed the memory available: physical memory, or RLIMIT_AS / the cgroup's
/// memory.max when smaller. Particle counts must stay below 2^32 (32-bit particle indices).
/// On P MPI ranks (mpi/domain.hpp: ORB boxes of the grid and their particles, the set-up
/// distributed) a rank needs about total / P; the L ranks sharing a node need L total / P of the
/// node's memory. That first check runs before the cuts are known; once they are (the boxes
/// balance particles, so a rank beside empty space may hold far more than 1/P of the grid, and
/// every box has 2 ghost nodes a side), each rank checks its own box and particles
/// (process_bytes, DomainSolver: mpi/domain.hpp) against its process limit and the node's ranks
/// together against the node's memory.
#pragma once
#include <cstddef>
#include <vector>

#include "common/schema.hpp"
#include "mpm/material.hpp"
#include "mpm/particles.hpp"

namespace mpmfrag {

struct MemoryEstimate {
  double grid_nodes = 0;
  double grid_bytes = 0;
  double particles = 0;
  double particle_bytes = 0;
  double total() const { return grid_bytes + particle_bytes; }
};

/// Estimate from a validated scene (keys as in mpm_schema()).
MemoryEstimate estimate_memory(const common::Scene& sc, const MaterialRegistry& reg = builtin_materials());

/// Bytes a process needs for a grid box of `nodes` nodes and the particles of `mats` (each
/// material's count x (2 x (the ParticleSet arrays + its style's state fields) + 96)), by the
/// same rules as estimate_memory.
double process_bytes(double nodes, const std::vector<MaterialSlot>& mats);

/// Bytes this process may use: min(node_memory(), process_memory_limit()).
double available_memory();
/// Bytes the node (or the job's cgroup) offers its processes together: min(physical memory,
/// cgroup memory.max).
double node_memory();
/// Bytes one process may map: RLIMIT_AS (infinity when unlimited).
double process_memory_limit();

/// Throws common::InputError (exit 2) naming grid.cell_size, grid.domain_min/max and the sizes
/// when the estimate exceeds `available`, or the particle estimate reaches 2^32. `ranks`: the MPI
/// ranks of the run, `ranks_here`: those on this node (sharing `available`).
void check_memory(const common::Scene& sc, double available = available_memory(),
                  const MaterialRegistry& reg = builtin_materials(), int ranks = 1, int ranks_here = 1);

}  // namespace mpmfrag
