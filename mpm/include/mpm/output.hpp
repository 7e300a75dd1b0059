/// @file output.hpp
/// Particle snapshots (common::write_particle_snapshot, the file contract in particle_file.hpp)
/// and the time-series CSV of mpm-frag.
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "common/atomic_file.hpp"
#include "common/particle_file.hpp"
#include "common/series_csv.hpp"
#include "mpm/solver.hpp"

namespace mpmfrag {

/// The snapshot datasets of the particle arrays, the one mapping of ParticleSet to the file
/// contract (ParticleSet::for_each_array, ArrayInfo::dataset): sets the core datasets (id,
/// position, velocity, mass, volume, size = 2 l_p, material) and appends the state datasets
/// `stress` and `internal_energy` to s.fields, in table order. Used by make_snapshot and by the
/// outflow record (Solver::outflow_snapshot).
void add_particle_datasets(common::ParticleSnapshot& s, const ParticleSet& ps);

/// Snapshot of the given state: core datasets, `stress` (N x 6 Voigt, Pa),
/// `internal_energy` (J/kg) and every style state field flagged for output (for particles of
/// materials without that field the field's initial value is written).
/// The outflow file's content (Solver::outflow_snapshot) from an outflow record: the removed
/// particles' core arrays at removal, their removal times and output state fields; positions
/// moved ballistically to `time`. The MPI build passes the record gathered from its ranks.
common::ParticleSnapshot make_outflow_snapshot(const ParticleSet& out, const std::vector<double>& removal_time,
                                               const std::vector<common::Field>& fields, const common::GridInfo& grid,
                                               double time, std::int64_t step);

common::ParticleSnapshot make_snapshot(const ParticleSet& ps, const std::vector<MaterialSlot>& mats,
                                       const common::GridInfo& grid, double time, std::int64_t step);

/// Time series: one CSV row per call (a common::SeriesFile; columns declared in output.cpp, 12
/// significant digits). With driven bodies, six more columns per drive: body<b>_F{x,y,z}_N (the
/// force on the rest of the system in the last step) and body<b>_J{x,y,z}_Ns (its impulse since
/// t = 0), b = the body's scene index (body_drive.hpp).
/// Rows go to `<path>.partial`; commit() renames it onto `path` (end of the run, or a numerical
/// failure after the last good state was saved), so a run that fails otherwise never replaces
/// an earlier series (common::PartialFile).
class SeriesWriter {
 public:
  /// Creates `<path>.partial` and writes the header, or `continued` (the header and rows a
  /// checkpoint kept: a restarted run). Throws common::IoError.
  /// `drive_bodies`: scene index of each driven body (Solver::drives order).
  SeriesWriter(const std::string& path, const std::vector<std::size_t>& drive_bodies,
               std::optional<std::string> continued = std::nullopt);
  /// Header and rows written so far (kept in checkpoints).
  const std::string& text() const { return file_.text(); }
  /// Append a row and flush.
  void write(std::int64_t step, double t, double dt, const Diagnostics& d, const std::vector<DriveLoad>& loads);
  /// Rename the series into place under `path`. Throws common::IoError.
  void commit() { file_.commit(); }

 private:
  common::SeriesFile file_;
};

}  // namespace mpmfrag
