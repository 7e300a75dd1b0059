/// @file sphere_configs.hpp
/// Constructed sphere configurations for the analysis tests.
#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <cstdint>

#include "common/sphere_file.hpp"

namespace analysis_test {

/// Append one sphere.
inline void add(common::SphereSet& s, const Eigen::Vector3d& x, double r, double m,
                const Eigen::Vector3d& v = Eigen::Vector3d::Zero(), double damage = -1.0) {
  s.id.push_back(s.id.size());
  for (int d = 0; d < 3; ++d) {
    s.position.push_back(x[d]);
    s.velocity.push_back(v[d]);
    s.spin.push_back(0.0);
  }
  s.mass.push_back(m);
  s.radius.push_back(r);
  if (damage >= 0) {
    if (s.fields.empty()) s.fields.push_back(common::Field{"damage", "1", 1, {}, ""});
    s.fields[0].values.push_back(damage);
  }
}

/// k^3 touching spheres (radius r, spacing 2r) with the lower corner sphere at `corner`.
inline void add_cube(common::SphereSet& s, const Eigen::Vector3d& corner, int k, double r, double m,
                     const Eigen::Vector3d& v = Eigen::Vector3d::Zero(), double damage = -1.0) {
  for (int i = 0; i < k; ++i)
    for (int j = 0; j < k; ++j)
      for (int l = 0; l < k; ++l) add(s, corner + 2.0 * r * Eigen::Vector3d(i, j, l), r, m, v, damage);
}

}  // namespace analysis_test
