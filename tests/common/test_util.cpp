/// @file test_util.cpp
/// Implementation of test_util.hpp (the header states the contract, and for physics the equations and sources).
#include "test_util.hpp"

#include <random>

#include <unistd.h>

namespace testutil {

TempDir::TempDir() {
  static int counter = 0;
  path = std::filesystem::temp_directory_path() /
         ("suite_test_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
  std::filesystem::remove_all(path);
  std::filesystem::create_directories(path);
}
TempDir::~TempDir() { std::filesystem::remove_all(path); }

common::ParticleSnapshot sample_particles(std::size_t n) {
  std::mt19937_64 g(42);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  common::ParticleSnapshot s;
  s.time = 1.25e-4;
  s.step = 77;
  s.grid.origin = Eigen::Vector3d(-2, -2, -2);
  s.grid.cell_size = Eigen::Vector3d(0.1, 0.1, 0.1);
  s.grid.shape = Eigen::Vector3i(41, 41, 41);
  for (std::size_t i = 0; i < n; ++i) {
    s.id.push_back(1000 + i);
    for (int d = 0; d < 3; ++d) {
      s.position.push_back(u(g));
      s.velocity.push_back(100 * u(g));
      s.size.push_back(0.05);
    }
    s.mass.push_back(1.0 + u(g) * 0.5);
    s.volume.push_back(1.25e-4);
    s.material.push_back(static_cast<int>(i % 2));
  }
  common::Field damage{"damage", "1", 1, {}, "scalar damage"};
  common::Field stress{"stress", "Pa", 6, {}, "Cauchy stress, Voigt xx,yy,zz,yz,xz,xy"};
  for (std::size_t i = 0; i < n; ++i) {
    damage.values.push_back(0.5 + 0.5 * u(g));
    for (int c = 0; c < 6; ++c) stress.values.push_back(1e6 * u(g));
  }
  s.fields = {damage, stress};
  return s;
}

common::SphereSet sample_spheres(std::size_t n) {
  std::mt19937_64 g(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  common::SphereSet s;
  s.time = 3600.0;
  s.step = 12;
  for (std::size_t i = 0; i < n; ++i) {
    s.id.push_back(i);
    for (int d = 0; d < 3; ++d) {
      s.position.push_back(1e3 * u(g));
      s.velocity.push_back(u(g));
      s.spin.push_back(1e-3 * u(g));
    }
    s.mass.push_back(1e9 * (1.5 + u(g)));
    s.radius.push_back(100.0);
  }
  s.fields = {common::Field{"damage", "1", 1, std::vector<double>(n, 0.25), ""}};
  return s;
}

common::Provenance sample_provenance() {
  return {"test-tool", "0.0", "abc123", "test-tool --scene x.toml", "x = 1\n"};
}

}  // namespace testutil
