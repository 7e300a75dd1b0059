/// @file finite.hpp
/// NaN/Inf guards: never let a non-finite value pass silently.
#pragma once
#include <cmath>
#include <cstddef>
#include <string>

namespace common {

/// Index of the first non-finite value in [data, data+n), or n if all are finite.
inline std::size_t first_non_finite(const double* data, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i)
    if (!std::isfinite(data[i])) return i;
  return n;
}

}  // namespace common

namespace common {
struct ParticleSnapshot;
struct SphereSet;

/// Physical bounds on inputs (scene keys and input files). They are far outside any asteroid
/// problem and chosen so that every derived quantity stays finite in double precision: with
/// |v| <= kMaxSpeed, |w| <= kMaxAngularVelocity, lengths <= kMaxLength and densities <=
/// kMaxDensity, masses stay below ~1e41 kg and kinetic, rotational and potential energies of
/// up to 1e12 bodies below ~1e90 J (DBL_MAX is 1.8e308).
namespace bounds {
inline constexpr double kMaxDensity = 1e5;           ///< kg/m^3 (osmium: 2.26e4)
inline constexpr double kMaxSpeed = 1e7;             ///< m/s (3 % of c; impacts: < 1e5)
inline constexpr double kMaxAngularVelocity = 1e4;   ///< rad/s
inline constexpr double kMaxLength = 1e12;           ///< m (positions, radii, domain; ~7 au)
inline constexpr double kMaxMass = 1e42;             ///< kg, one particle or sphere
inline constexpr double kMaxGeneratedSpheres = 1e8;  ///< spheres a generator may create
}  // namespace bounds

/// Check an input particle file against the bounds (positions, velocities, masses, volumes,
/// sizes finite and within bounds; masses and volumes > 0). Throws InputError naming `file`,
/// the dataset, the particle index, the value and the allowed range.
void check_input_particles(const ParticleSnapshot& s, const std::string& file);
/// The same for a sphere file (positions, velocities, spins, masses, radii); `group` prefixes the
/// array names in messages ("" for files without HDF5 groups, e.g. .ss).
void check_input_spheres(const SphereSet& s, const std::string& file, const std::string& group = "/spheres/",
                         std::size_t row0 = 0);

/// Check values about to be written to `path` are finite, including the kinetic energy sum
/// 1/2 m v^2 (and the rotational energy for spheres). Throws NumericalError naming the path,
/// the array and the index; the caller saves (or names) the last good state.
void check_output_particles(const ParticleSnapshot& s, const std::string& path);
void check_output_spheres(const SphereSet& s, const std::string& path);
/// Throws NumericalError("<what>: <name>[i] = <v> is not finite") for the first non-finite value.
void require_finite(const double* data, std::size_t n, const std::string& what, const std::string& name);

}  // namespace common
