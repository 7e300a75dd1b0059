/// @file checkpoint_rows.hpp
/// The /mpm_state group of a checkpoint (layout in checkpoint.hpp) written from rows: by one
/// process holding every row (write_checkpoint), or on MPI ranks by each rank with its block of
/// the file's rows, all ranks together with collective parallel HDF5 (mpi/checkpoint_mpi.hpp).
/// In the collective case every rank calls write_mpm_state with the same scalars, names, material
/// ranges, field lists and row totals (HDF5's metadata operations are collective); only the rows
/// differ (the particles, each material's state, the outflow record), and the series text, which
/// one process holds whole, is written by the single writer, rank 0, the other ranks joining
/// with no rows.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "common/h5.hpp"
#include "mpm/checkpoint.hpp"

namespace mpmfrag {

/// The /mpm_state format attributes (readers refuse another format or a newer version).
inline constexpr const char* kCheckpointFormat = "mpm-frag.checkpoint";
inline constexpr std::int64_t kCheckpointVersion = 1;

/// Where this process's rows of /mpm_state go.
struct CheckpointRows {
  common::h5::RowBlock particles;           ///< the rows of `ps` in /mpm_state/particles
  std::vector<common::h5::RowBlock> slots;  ///< per material: its state arrays' rows (mats[m].state)
  std::size_t outflow_first = 0;            ///< the file row of this process's first outflow row
  std::size_t outflow_total = 0;            ///< rows of the outflow record in the file
  bool single_writer = true;                ///< this process writes the series
  hid_t xfer = H5P_DEFAULT;                 ///< transfer property list (collective on MPI ranks)
  bool optional_arrays = false;             ///< the optional ParticleSet arrays (q) are written
  bool outflow_optional = false;            ///< the same for the outflow record

  /// One process writing every row of `ps`, `mats` and `r`.
  static CheckpointRows whole(const ParticleSet& ps, const std::vector<MaterialSlot>& mats, const SolverResume& r);
};

/// True if an optional ParticleSet array of `ps` is in use (non-empty).
bool uses_optional_arrays(const ParticleSet& ps);

/// Write /mpm_state into the open file `f`. mats[m].begin and end are the material's range in the
/// file (on MPI ranks not the range in `ps`); mats[m].state holds this process's rows of it. On
/// every process `r`'s scalars, `driver` and `identity` are the same; r.outflow, outflow_time and
/// the values of outflow_fields are this process's rows of the record (rows.outflow_first on;
/// the field names, units and initial values alike everywhere).
/// Returns false if a data write failed; throws common::IoError if an object cannot be made.
bool write_mpm_state(hid_t f, const ParticleSet& ps, const std::vector<MaterialSlot>& mats, const SolverResume& r,
                     const DriverState& driver, const std::string& identity, const CheckpointRows& rows);

}  // namespace mpmfrag
