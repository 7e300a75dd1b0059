/// @file particle_sets.hpp
/// Synthetic particle snapshots for the hand-off tests and benchmark.
#pragma once
#include <Eigen/Core>
#include <cmath>
#include <random>

#include "common/particle_file.hpp"

namespace testsets {

/// Grid of `cells` cells per axis, edge h, origin at 0.
inline common::GridInfo grid(int cells, double h) {
  common::GridInfo g;
  g.origin = Eigen::Vector3d::Zero();
  g.cell_size = Eigen::Vector3d::Constant(h);
  g.shape = Eigen::Vector3i::Constant(cells + 1);
  return g;
}

inline void add(common::ParticleSnapshot& s, std::uint64_t id, const Eigen::Vector3d& x, const Eigen::Vector3d& v,
                double m, double size) {
  s.id.push_back(id);
  for (int d = 0; d < 3; ++d) {
    s.position.push_back(x[d]);
    s.velocity.push_back(v[d]);
    s.size.push_back(size);
  }
  s.mass.push_back(m);
  s.volume.push_back(size * size * size);
  s.material.push_back(0);
}

/// `n` particles uniformly in the box [lo, hi]^3 with random masses and velocities.
inline common::ParticleSnapshot uniform(std::size_t n, int cells, double h, double lo, double hi, double size,
                                        unsigned seed = 1) {
  common::ParticleSnapshot s;
  s.grid = grid(cells, h);
  std::mt19937_64 g(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d x(lo + (hi - lo) * u(g), lo + (hi - lo) * u(g), lo + (hi - lo) * u(g));
    const Eigen::Vector3d v(1000 * (u(g) - 0.5), 1000 * (u(g) - 0.5), 1000 * (u(g) - 0.5) + 3000);
    add(s, 10 * i + 7, x, v, 0.5 + u(g), size);
  }
  return s;
}

/// A box of `nc` cells per axis starting at cell `c0`, filled with n^3 particles per cell at the
/// regular offsets (k + 1/2) h / n, equal masses, velocity from `vel(x)`.
template <class F>
common::ParticleSnapshot filled_box(int cells, double h, int c0, int nc, int n, double m, F vel) {
  common::ParticleSnapshot s;
  s.grid = grid(cells, h);
  std::uint64_t id = 0;
  const int np = nc * n;
  for (int k = 0; k < np; ++k)
    for (int j = 0; j < np; ++j)
      for (int i = 0; i < np; ++i) {
        const Eigen::Vector3d x = (Eigen::Vector3d(i, j, k).array() + 0.5).matrix() * (h / n) +
                                  Eigen::Vector3d::Constant(c0 * h);
        add(s, id++, x, vel(x), m, h / n);
      }
  return s;
}

}  // namespace testsets
