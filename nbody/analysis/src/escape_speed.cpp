/// @file escape_speed.cpp
/// Implementation of analysis/escape_speed.hpp; the governing equations are documented there.
#include "analysis/escape_speed.hpp"

#include <cmath>
#include <limits>

namespace analysis {

double uniform_sphere_potential(double M, double R, double r, double G) {
  if (r >= R) return r > 0 ? -G * M / r : -std::numeric_limits<double>::infinity();
  return -G * M * (3.0 * R * R - r * r) / (2.0 * R * R * R);
}

SpeedEscape escape_by_speed(const double* position, const double* velocity, const double* mass, std::size_t n,
                            double M, double R, const Eigen::Vector3d& C, const Eigen::Vector3d& V, double G) {
  SpeedEscape out;
  for (std::size_t i = 0; i < n; ++i) {
    const double r = (Eigen::Vector3d(position + 3 * i) - C).norm();
    const Eigen::Vector3d v(velocity + 3 * i);
    if (0.5 * (v - V).squaredNorm() + uniform_sphere_potential(M, R, r, G) >= 0.0) {
      out.escaping_mass += mass[i];
      out.escaping_momentum += mass[i] * v;
      ++out.escaping_count;
    }
  }
  return out;
}

}  // namespace analysis
