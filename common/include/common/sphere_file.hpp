/// @file sphere_file.hpp
/// Sphere-set file (written by mpm2spheres and ssdem-grav, read by ssdem-grav):
///
///   / attrs: format = "ssdem.spheres", format_version, time [s], step
///   /spheres: id (uint64 N), position (N x 3, m), velocity (N x 3, m/s),
///             spin (N x 3 angular velocity, rad/s), mass (N, kg), radius (N, m),
///             optional damage (N, 1) and other per-sphere fields
///   /provenance attrs: tool, version, git_sha, command_line, scene
/// Tools may add groups (hand-off audit and id map, contact history in checkpoints) through
/// the extra hook. Every dataset has a `unit` attribute; XDMF sidecar beside it.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "common/field.hpp"
#include "common/particle_file.hpp"
#include "common/provenance.hpp"

namespace common {

inline constexpr const char* kSphereFormat = "ssdem.spheres";
inline constexpr std::int64_t kSphereFormatVersion = 1;

struct SphereSet {
  double time = 0.0;
  std::int64_t step = 0;
  std::vector<std::uint64_t> id;
  std::vector<double> position;  ///< N*3
  std::vector<double> velocity;  ///< N*3
  std::vector<double> spin;      ///< N*3
  std::vector<double> mass;      ///< N
  std::vector<double> radius;    ///< N
  std::vector<Field> fields;     ///< optional: damage, ...

  std::size_t count() const { return id.size(); }
  const Field* field(const std::string& name) const;
};

void write_sphere_set(const std::string& path, const SphereSet& s, const Provenance& prov,
                      const H5Hook& extra = {});
/// Validates like read_particle_snapshot, plus positive radius and finite spin.
SphereSet read_sphere_set(const std::string& path, const H5Hook& extra = {});

}  // namespace common
