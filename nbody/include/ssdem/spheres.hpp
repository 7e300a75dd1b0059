/// @file spheres.hpp
/// Structure-of-arrays storage of the spheres of an SSDEM run.
///
/// Each sphere carries position x, velocity v, spin (angular velocity) w, mass m, radius s and
/// a persistent 64-bit id (the key used by contact history, random numbers and outputs). The
/// moment of inertia is that of a solid sphere, I = (2/5) m s^2 (pkdgrav
/// `dem.c:demAssignParticleInertia`, Schwartz, Richardson & Michel 2012, Granular Matter 14:363).
/// Optional per-sphere fields (damage, ...) from the input file are carried through unchanged.
/// `dissipated` accumulates the energy the sphere's contacts have dissipated (half of each
/// sphere-sphere contact's, all of its wall contacts'; contact_law.hpp, "Dissipation"): it moves
/// with the sphere (reordering, MPI ranks, checkpoints), so the run's total is a sum over spheres
/// that does not depend on the thread or rank count.
/// Loops run over index ranges [begin, end) so a domain decomposition can be added later.
///
/// The arrays are enumerated in one place, Spheres::zip_arrays (with their file descriptors:
/// dataset name, unit, type, width); resizing, appending, size checks, memory accounting and the
/// conversion to and from sphere files (snapshots, checkpoints) go through it. Adding a sphere
/// array is one member plus one line there: an array that is not a core array of the sphere
/// file (common::SphereSet) is written as a per-sphere field of that name and read back from it.
#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <type_traits>
#include <vector>

#include "common/field.hpp"
#include "common/sphere_file.hpp"

namespace ssdem {

using Vec3 = Eigen::Vector3d;

/// Not a core array of sphere files: written as the per-sphere field "dissipated" (zero when an
/// input lacks it).
inline constexpr common::SphereArray kSphereDissipated{"dissipated", "J", common::SphereScalar::Float64, 1};

/// SoA sphere storage. Within a Simulation the index order never changes, so the index is a
/// valid handle between neighbour-list rebuilds; the serial driver renumbers the spheres in
/// memory by restarting a Simulation from a permuted state (sphere_order.hpp), and files keep
/// the input's order. Ids are the persistent key.
struct Spheres {
  std::vector<std::uint64_t> id;
  std::vector<Vec3> x;   ///< position [m]
  std::vector<Vec3> v;   ///< velocity [m/s]
  std::vector<Vec3> w;   ///< spin, angular velocity [rad/s]
  std::vector<double> m; ///< mass [kg]
  std::vector<double> s; ///< radius [m]
  std::vector<double> dissipated;  ///< energy dissipated in this sphere's contacts so far [J]
  /// Per-sphere fields carried from the input to every snapshot (e.g. "damage").
  std::vector<common::Field> carried;

  /// The one list of the sphere arrays: f(const common::SphereArray&, the array of each set...),
  /// for any number of sets (zero: descriptors only), in file order.
  template <class F, class... S>
  static constexpr void zip_arrays(F&& f, S&... sets) {
    f(common::kSphereId, sets.id...);
    f(common::kSpherePosition, sets.x...);
    f(common::kSphereVelocity, sets.v...);
    f(common::kSphereSpin, sets.w...);
    f(common::kSphereMass, sets.m...);
    f(common::kSphereRadius, sets.s...);
    f(kSphereDissipated, sets.dissipated...);
  }
  /// f(const common::SphereArray&, array) for each array (carried fields excluded).
  template <class F>
  void for_each_array(F&& f) { zip_arrays(f, *this); }
  template <class F>
  void for_each_array(F&& f) const { zip_arrays(f, *this); }

  /// The value new entries get: zero.
  template <class T>
  static T zero() {
    if constexpr (std::is_arithmetic_v<T>)
      return T{0};
    else
      return T::Zero();
  }

  std::size_t size() const { return id.size(); }
  /// Whether every array holds size() entries.
  bool consistent() const;
  /// Resize every array (new entries zero).
  void resize(std::size_t n);
  /// Append one sphere (arrays not named here zero).
  void push(std::uint64_t id_, const Vec3& x_, const Vec3& v_, const Vec3& w_, double m_,
            double s_);
  /// Append all spheres of `o` (every array; carried fields are left as they are).
  void append(const Spheres& o);
  /// Moment of inertia of sphere i (solid sphere).
  double inertia(std::size_t i) const { return 0.4 * m[i] * s[i] * s[i]; }
  /// Bytes held per sphere by these arrays (excluding carried fields).
  static constexpr std::size_t bytes_per_sphere() {
    std::size_t b = 0;
    zip_arrays([&](const common::SphereArray& a) { b += a.bytes(); });
    return b;
  }
};

}  // namespace ssdem
