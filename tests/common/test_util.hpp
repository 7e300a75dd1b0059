/// @file test_util.hpp
/// Helpers shared by the common tests: temporary directories and sample data.
#pragma once
#include <filesystem>
#include <string>

#include "common/particle_file.hpp"
#include "common/sphere_file.hpp"

namespace testutil {

/// A fresh directory under the system temp dir, removed at scope exit.
struct TempDir {
  std::filesystem::path path;
  TempDir();
  ~TempDir();
  std::string file(const std::string& name) const { return (path / name).string(); }
};

common::ParticleSnapshot sample_particles(std::size_t n);
common::SphereSet sample_spheres(std::size_t n);
common::Provenance sample_provenance();

}  // namespace testutil
