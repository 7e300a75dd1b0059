/// @file bound.cpp
/// Implementation of analysis/bound.hpp; the governing equations, sources and deviations are documented there.
#include "analysis/bound.hpp"

#include <cmath>
#include <limits>

namespace analysis {

ClumpProps clump_properties(const double* position, const double* velocity, const double* mass,
                            std::size_t n, const FofResult& fof) {
  const std::size_t m = fof.count();
  ClumpProps c;
  c.mass.assign(m, 0.0);
  std::vector<Eigen::Vector3d> mx(m, Eigen::Vector3d::Zero()), mv(m, Eigen::Vector3d::Zero());
  // Positions relative to each clump's first member keep the sums well conditioned far from 0.
  for (std::size_t i = 0; i < n; ++i) {
    const std::int64_t k = fof.clump_of[i];
    const Eigen::Vector3d ref(position + 3 * fof.clump_first[k]);
    c.mass[k] += mass[i];
    mx[k] += mass[i] * (Eigen::Vector3d(position + 3 * i) - ref);
    mv[k] += mass[i] * Eigen::Vector3d(velocity + 3 * i);
  }
  c.com.resize(m);
  c.vel.resize(m);
  for (std::size_t k = 0; k < m; ++k) {
    const Eigen::Vector3d ref(position + 3 * fof.clump_first[k]);
    c.com[k] = ref + mx[k] / c.mass[k];
    c.vel[k] = mv[k] / c.mass[k];
  }
  return c;
}

double two_body_energy(double M, const Eigen::Vector3d& R, const Eigen::Vector3d& V, double m,
                       const Eigen::Vector3d& r, const Eigen::Vector3d& v, double G) {
  const double d = (r - R).norm();
  if (d <= 0.0) return -std::numeric_limits<double>::infinity();
  return 0.5 * (v - V).squaredNorm() - G * (M + m) / d;
}

BoundResult bound_to_largest(const ClumpProps& c, double G, int max_iterations) {
  BoundResult out;
  const std::size_t m = c.mass.size();
  out.bound.assign(m, 0);
  for (std::size_t k = 0; k < m; ++k) {
    out.total_mass += c.mass[k];
    out.total_momentum += c.mass[k] * c.vel[k];
  }
  if (m == 0) return out;
  out.bound[0] = 1;
  out.lr_mass = c.mass[0];
  out.lr_com = c.com[0];
  out.lr_momentum = c.mass[0] * c.vel[0];

  const std::int64_t mi = static_cast<std::int64_t>(m);
  double M = 0.0;
  Eigen::Vector3d R, V;
  auto recompute = [&] {
    M = 0.0;
    Eigen::Vector3d mx = Eigen::Vector3d::Zero(), mv = Eigen::Vector3d::Zero();
    for (std::size_t k = 0; k < m; ++k) {
      if (!out.bound[k]) continue;
      M += c.mass[k];
      mx += c.mass[k] * (c.com[k] - c.com[0]);
      mv += c.mass[k] * c.vel[k];
    }
    R = c.com[0] + mx / M;
    V = mv / M;
  };
  recompute();
  std::vector<char> join(m, 0);
  int it = 0;
  while (it < max_iterations) {
    ++it;
    std::int64_t added = 0;
#pragma omp parallel for schedule(static) reduction(+ : added)
    for (std::int64_t k = 1; k < mi; ++k) {
      join[k] = 0;
      if (out.bound[k]) continue;
      if (two_body_energy(M, R, V, c.mass[k], c.com[k], c.vel[k], G) < 0.0) {
        join[k] = 1;
        ++added;
      }
    }
    if (added == 0) break;
    for (std::size_t k = 1; k < m; ++k)
      if (join[k]) out.bound[k] = 1;
    recompute();
  }
  out.iterations = it;
  recompute();
  out.bound_mass = 0.0;
  out.bound_momentum.setZero();
  out.escaping_momentum.setZero();
  out.escaping_mass = 0.0;
  for (std::size_t k = 0; k < m; ++k) {
    if (out.bound[k]) {
      ++out.n_bound_clumps;
      out.bound_mass += c.mass[k];
      out.bound_momentum += c.mass[k] * c.vel[k];
    } else {
      out.escaping_mass += c.mass[k];
      out.escaping_momentum += c.mass[k] * c.vel[k];
    }
  }
  out.bound_com = R;
  return out;
}

}  // namespace analysis
