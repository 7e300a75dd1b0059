/// @file escape_speed.hpp
/// Sphere-by-sphere escape test, the "ejecta faster than the local escape speed" form of the
/// momentum bookkeeping (ssdem.md §5.2 last item: iSALE/SPH practice, e.g. Raducan et al. 2021),
/// usable already at hand-off time when FOF still links the whole fractured target.
///
/// The remnant is a uniform sphere of mass M, radius R, centre C, velocity V, with potential
///     Φ(r) = -G M (3 R² - r²) / (2 R³)   for r < R,      Φ(r) = -G M / r   for r >= R,   (1)
/// r = |x_i - C|. Sphere i escapes if  ½ |v_i - V|² + Φ(r_i) >= 0,  i.e. |v_i - V| >= sqrt(-2Φ).
/// Deviation: the real remnant is neither uniform nor spherical, and the escaping material's own
/// gravity is ignored; this is an estimate beside the clump-based β (momentum.hpp).
#pragma once
#include <Eigen/Core>
#include <cstddef>

namespace analysis {

/// Potential (1) of a uniform sphere [J/kg].
double uniform_sphere_potential(double M, double R, double r, double G);

struct SpeedEscape {
  double escaping_mass = 0.0;
  Eigen::Vector3d escaping_momentum = Eigen::Vector3d::Zero();  ///< simulation frame
  std::size_t escaping_count = 0;
};

/// Apply (1) to every sphere (positions N*3, velocities N*3, masses N). Serial sum (deterministic).
SpeedEscape escape_by_speed(const double* position, const double* velocity, const double* mass, std::size_t n,
                            double M, double R, const Eigen::Vector3d& C, const Eigen::Vector3d& V, double G);

}  // namespace analysis
