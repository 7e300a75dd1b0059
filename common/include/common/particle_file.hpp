/// @file particle_file.hpp
/// Particle snapshot file (written by mpm-frag, read by mpm2spheres): the pipeline's public
/// interface, documented in common/FILE_FORMATS.md.
///
///   / attrs: format = "mpm-frag.particles", format_version, time [s], step
///   /grid attrs: origin (3) [m], cell_size (3) [m], shape (3 node counts)
///   /particles: id (uint64 N), position (N x 3, m), velocity (N x 3, m/s), mass (N, kg),
///               volume (N, m^3), size (N x 3, undeformed particle-domain edges, m),
///               material (int32 N), optional state datasets (damage, stress N x 6 Voigt
///               xx,yy,zz,yz,xz,xy in Pa, distension, ...)
///   /provenance attrs: tool, version, git_sha, command_line, scene
/// Every dataset has a `unit` attribute. An XDMF sidecar (same stem, .xmf) is written beside it.
#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "common/field.hpp"
#include "common/grid.hpp"
#include "common/h5.hpp"
#include "common/provenance.hpp"

namespace common {

inline constexpr const char* kParticleFormat = "mpm-frag.particles";
inline constexpr std::int64_t kParticleFormatVersion = 1;

struct ParticleSnapshot {
  double time = 0.0;
  std::int64_t step = 0;
  GridInfo grid;
  std::vector<std::uint64_t> id;
  std::vector<double> position;  ///< N*3
  std::vector<double> velocity;  ///< N*3
  std::vector<double> mass;      ///< N
  std::vector<double> volume;    ///< N
  std::vector<double> size;      ///< N*3
  std::vector<std::int32_t> material;
  std::vector<Field> fields;     ///< optional state datasets

  std::size_t count() const { return id.size(); }
  const Field* field(const std::string& name) const;
};

/// Hook to write extra groups into the same file before it is committed, or read them.
using H5Hook = std::function<void(long long /*hid_t file*/)>;

/// Write atomically (temp + rename) with the XDMF sidecar. Throws IoError; throws
/// InputError if the snapshot is internally inconsistent (array sizes).
void write_particle_snapshot(const std::string& path, const ParticleSnapshot& s,
                             const Provenance& prov, const H5Hook& extra = {});

/// The content of a particle file, written into the open HDF5 file `file`: root attributes, /grid,
/// this process's rows `block` of every /particles dataset, /provenance. write_particle_snapshot
/// writes the whole set; the MPI writer (common/mpi/particle_file_mpi.hpp) gives each rank its
/// block of the sorted rows (every rank calls it, with the same fields). False if a data write
/// failed; throws IoError if a group or dataset cannot be created.
bool write_particle_content(long long file, const ParticleSnapshot& s, const Provenance& prov,
                            const h5::RowBlock& block);
/// The XDMF sidecar of the particle file `path` of `n` particles (the fields of `s`).
void write_particle_xdmf(const std::string& path, const ParticleSnapshot& s, std::size_t n);

/// Read and validate: format tag, version (newer -> error), required datasets, shapes, dtypes,
/// finite positions/velocities/masses, positive mass and volume. Throws InputError naming the
/// file and dataset.
ParticleSnapshot read_particle_snapshot(const std::string& path, const H5Hook& extra = {});

}  // namespace common
