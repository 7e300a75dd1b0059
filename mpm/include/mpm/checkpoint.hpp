/// @file checkpoint.hpp
/// mpm-frag checkpoints: the complete state of a run after a completed step, from which
/// `mpm-frag --restart <file>` continues bit-identically (same particles, same steps, same
/// snapshots and series as an uninterrupted run, for any thread count).
///
/// A checkpoint is a particle snapshot of that state (the file contract of particle_file.hpp, so
/// mpm2spheres reads it too) plus the group `/mpm_state` (common/FILE_FORMATS.md):
///   attrs   format = "mpm-frag.checkpoint", format_version, step, time [s], max_speed [m/s],
///           min_node_mass [kg], next_snapshot [s], first_dt, min_dt, max_dt [s], initial_totals and
///           outflow_totals (11 numbers each: mass, momentum 3, angular momentum 3, kinetic,
///           internal, removed count, removed mass), drive_loads (driven bodies only: force [N]
///           and impulse [N s] of each drive, 6 numbers per drive), run_identity, run_identity_digest,
///           series_bytes, material_count
///   particles/<array>           every ParticleSet array by member name (ParticleSet::for_each_array,
///                               so an array added there travels without a change here), raw values
///   materials/<m>  attrs name, begin, end; one dataset per style state field (by field name)
///   outflow/particles/<array>, outflow/removal_time, outflow/fields/<k> (attrs name, initial,
///                               description): the outflow record (SolverResume)
///   series                      the series CSV written so far (header and rows), bytes packed
///                               8 per uint64 word (little-endian), `series_bytes` long
#pragma once
#include <functional>
#include <string>
#include <vector>

#include "common/particle_file.hpp"
#include "common/provenance.hpp"
#include "mpm/solver.hpp"

namespace mpmfrag {

/// The driver's loop state after a step (run.cpp).
struct DriverState {
  double next_snapshot = 0;            ///< simulated time of the next snapshot [s]
  double first_dt = 0, min_dt = 0, max_dt = 0;  ///< for the run summary [s]
  Diagnostics initial;                 ///< totals at t = 0 (the energy reference)
  std::string series;                  ///< the series CSV written so far
};

/// One material of a checkpoint: its scene name, particle range and state arrays by field name
/// (the style and model come from the scene: apply_materials).
struct MaterialState {
  std::string name;
  std::size_t begin = 0, end = 0;
  std::vector<std::pair<std::string, std::vector<double>>> fields;
};

/// A checkpoint read back (whole, or one process's part: read_checkpoint_part).
struct Checkpoint {
  ParticleSet particles;                 ///< the file's particle rows [first, first + size)
  std::size_t first = 0, total = 0;      ///< the first of them, and the file's particle count
  std::vector<MaterialState> materials;  ///< ranges relative to `particles`
  SolverResume solver;
  DriverState driver;
  std::string identity;  ///< run identity text (common::RunIdentity)
};

/// Write the checkpoint of `solver`'s current state atomically (temporary + rename). Throws
/// IoError; NumericalError if a particle value is not finite (never written).
void write_checkpoint(const std::string& path, const Solver& solver, const DriverState& driver,
                      const common::Provenance& prov, const std::string& identity);
/// The same from the parts of a solver's state (`ps`, `mats` and `resume` as Solver::particles(),
/// materials() and resume_state() give them; the MPI build passes the particles gathered from
/// its ranks). `extra` writes further groups into the file (the MPI build: /mpm_state/mpi).
void write_checkpoint(const std::string& path, const ParticleSet& ps, const std::vector<MaterialSlot>& mats,
                      const common::GridInfo& grid, const SolverResume& resume, const DriverState& driver,
                      const common::Provenance& prov, const std::string& identity, const common::H5Hook& extra = {});

/// Read and validate a checkpoint. Throws InputError naming the file (and dataset). `extra`
/// reads further groups (called with the open file after /mpm_state was read).
Checkpoint read_checkpoint(const std::string& path, const common::H5Hook& extra = {});

/// The part of a checkpoint that process `index` of `count` reads (a restart on MPI ranks, each
/// rank reading its own rows independently, so no rank holds every particle): the particle rows
/// [first, first + n) with first = total * index / count, each material's state rows among
/// them, the outflow record's rows [no * index / count, no * (index + 1) / count) of its no rows
/// (the same split), the scalars, and, if `records`, the series (one process).
struct CheckpointPart {
  int index = 0;
  int count = 1;
  bool records = true;
};
/// Read `part` of a checkpoint: the same checks as read_checkpoint on /mpm_state (the data of the
/// snapshot part is not read; its row count and step must match). Throws InputError. `extra`
/// reads further groups, given the open file and the part read so far (its rows).
using PartHook = std::function<void(long long file, const Checkpoint& part)>;
Checkpoint read_checkpoint_part(const std::string& path, const CheckpointPart& part, const PartHook& extra = {});

/// The 16 numbers of a Diagnostics as a checkpoint stores them (initial_totals): mass, momentum
/// (3), angular momentum (3), kinetic, internal, removed count, removed mass, work_dev,
/// heat_shock, heat_transfer, elastic, dissipated; and back (`v` must hold 16).
std::vector<double> pack_totals(const Diagnostics& d);
Diagnostics unpack_totals(const std::vector<double>& v);

/// Give the scene's materials (`mats`, from build_setup) the checkpoint's particle ranges and
/// state arrays. Throws InputError naming `path` if names, order or state fields differ.
void apply_materials(const Checkpoint& ck, std::vector<MaterialSlot>& mats, const std::string& path);

}  // namespace mpmfrag
