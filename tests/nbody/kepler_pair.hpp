/// @file kepler_pair.hpp
/// Test scene: the G = M = 1 two-body Kepler orbit (semi-major axis 1, eccentricity e, period 2 pi)
/// started at apocentre, r_a = 1 + e, relative speed v_a = sqrt((1 - e)/(1 + e)) (vis-viva), two
/// bodies of mass 1/2 at -r_a/2 and +r_a/2 moving at -v_a/2 and +v_a/2; direct self-gravity, G = 1.
#pragma once

#include <cmath>
#include <cstdint>

#include "ssdem/simulation.hpp"

inline ssdem::Spheres kepler_pair(double e, double radius = 1e-6, std::uint64_t id0 = 0, std::uint64_t id1 = 1) {
  using ssdem::Vec3;
  const double ra = 1 + e, va = std::sqrt((1 - e) / (1 + e));
  ssdem::Spheres sp;
  sp.push(id0, Vec3(-0.5 * ra, 0, 0), Vec3(0, -0.5 * va, 0), Vec3::Zero(), 0.5, radius);
  sp.push(id1, Vec3(0.5 * ra, 0, 0), Vec3(0, 0.5 * va, 0), Vec3::Zero(), 0.5, radius);
  return sp;
}

inline ssdem::SimConfig kepler_config(double steps_per_orbit) {
  ssdem::SimConfig c;
  c.self_gravity = true;
  c.direct_gravity = true;
  c.gravity.G = 1.0;
  c.dt = 2 * M_PI / steps_per_orbit;
  return c;
}
