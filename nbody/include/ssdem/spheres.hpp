/// @file spheres.hpp
/// Structure-of-arrays storage of the spheres of an SSDEM run.
///
/// Each sphere carries position x, velocity v, spin (angular velocity) w, mass m, radius s and
/// a persistent 64-bit id (the key used by contact history, random numbers and outputs). The
/// moment of inertia is that of a solid sphere, I = (2/5) m s^2 (pkdgrav
/// `dem.c:demAssignParticleInertia`, Schwartz, Richardson & Michel 2012, Granular Matter 14:363).
/// Optional per-sphere fields (damage, ...) from the input file are carried through unchanged.
/// Loops run over index ranges [begin, end) so a domain decomposition can be added later.
#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "common/field.hpp"

namespace ssdem {

using Vec3 = Eigen::Vector3d;

/// SoA sphere storage. Index order is stable for the whole run (never re-sorted), so the
/// index is a valid handle between neighbour-list rebuilds; ids are the persistent key.
struct Spheres {
  std::vector<std::uint64_t> id;
  std::vector<Vec3> x;   ///< position [m]
  std::vector<Vec3> v;   ///< velocity [m/s]
  std::vector<Vec3> w;   ///< spin, angular velocity [rad/s]
  std::vector<double> m; ///< mass [kg]
  std::vector<double> s; ///< radius [m]
  /// Per-sphere fields carried from the input to every snapshot (e.g. "damage").
  std::vector<common::Field> carried;

  std::size_t size() const { return id.size(); }
  /// Resize every array (new entries zero).
  void resize(std::size_t n);
  /// Append one sphere.
  void push(std::uint64_t id_, const Vec3& x_, const Vec3& v_, const Vec3& w_, double m_,
            double s_);
  /// Moment of inertia of sphere i (solid sphere).
  double inertia(std::size_t i) const { return 0.4 * m[i] * s[i] * s[i]; }
  /// Bytes held per sphere by these arrays (excluding carried fields).
  static constexpr std::size_t bytes_per_sphere() { return 8 + 3 * 24 + 16; }
};

}  // namespace ssdem
