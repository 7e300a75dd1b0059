/// @file generators.hpp
/// Built-in initial conditions: lattice (FCC) rubble piles, random loose clouds, two bodies on
/// a collision course, two-body orbits and Plummer spheres. Random numbers are keyed by sphere
/// id (common::KeyedRng), so generated scenes do not depend on thread count or ordering.
/// Plummer sampling follows Aarseth, Henon & Wielen (1974, A&A 37:183): r = a (X^{-2/3} - 1)^{-1/2}
/// with X uniform, speeds by von Neumann rejection from g(q) = q^2 (1 - q^2)^{7/2}.
#pragma once
#include <cstdint>

#include "ssdem/spheres.hpp"

namespace ssdem {

/// FCC lattice of spheres of radius s (nearest-neighbour distance 2 s, so every interior sphere
/// touches 12 others) filling a ball of radius R centred at `centre`; bulk density
/// rho_grain * 0.7405. Radii are scaled by (1 - jitter * U[0,1)) per sphere (keyed RNG).
Spheres lattice_pile(double R, double s, double rho_grain, double jitter = 0.0,
                     std::uint64_t seed = 1, const Vec3& centre = Vec3::Zero(),
                     std::uint64_t first_id = 0);

/// N non-overlapping spheres of radius s placed uniformly at random in a ball of radius R
/// (rejection sampling; throws InputError if the ball is too full).
Spheres random_cloud(std::size_t n, double R, double s, double rho_grain, std::uint64_t seed = 1,
                     const Vec3& centre = Vec3::Zero(), std::uint64_t first_id = 0);

/// Append `b` to `a` with a velocity shift and position shift (ids continue from a's).
void append_body(Spheres& a, const Spheres& b, const Vec3& shift, const Vec3& velocity);

/// Plummer sphere of n equal point-like spheres (radius `s`), total mass M, scale a, G.
Spheres plummer(std::size_t n, double M, double a, double G, double s, std::uint64_t seed = 1);

/// Total mass and bulk radius helpers.
double total_mass(const Spheres& sp);

}  // namespace ssdem
