/// @file diagnostics.hpp
/// The conserved and accounted quantities of a series row (run.hpp), and their sums.
///   E_kin = sum_i m_i |v_i|^2 / 2,  E_rot = sum_i I_i |w_i|^2 / 2 (contacts on),
///   E_self = sum_i m_i phi_i / 2 (phi_i the self-gravity potential of sphere i),
///   E_unif = -sum_i m_i g.x_i,  E_el = sum over contacts of the stored elastic energy,
///   p = sum_i m_i v_i,  L = sum_i (m_i x_i x v_i + I_i w_i)  (about the origin).
/// Every sum is exact and rounded once (common/exact_sum.hpp): each sphere's and each contact's
/// term is computed alike wherever it is held, so one rank, any number of threads and any number
/// of MPI ranks (each adding the terms of the spheres and contacts it owns, the accumulators then
/// added over the ranks) give the same bits in series.csv.
#pragma once
#include <array>
#include <cstddef>

#include "common/exact_sum.hpp"
#include "ssdem/spheres.hpp"

namespace ssdem {

struct Diagnostics {
  double kinetic = 0, rotational = 0, potential_self = 0, potential_uniform = 0, elastic = 0;
  double total() const { return kinetic + rotational + potential_self + potential_uniform + elastic; }
  double bond_elastic = 0;   ///< part of `elastic` stored in intact bonds [J]
  double bond_released = 0;  ///< stored energy of the bonds broken so far [J] (left the total)
  double dissipated = 0;     ///< energy dissipated by the contacts so far (sum of Spheres::dissipated) [J]
  /// What an exact integration keeps constant: the conservative total plus what has left it
  /// (contact dissipation, broken bonds' stored energy). accounted() - E_0 is the energy error.
  double accounted() const { return total() + dissipated + bond_released; }
  std::size_t bonds = 0, bonds_broken = 0;
  Vec3 momentum = Vec3::Zero();
  Vec3 angular_momentum = Vec3::Zero();  ///< orbital + spin, about the origin
  std::size_t contacts = 0, wall_contacts = 0;
  double max_overlap_frac = 0;
};

/// The exact sums behind Diagnostics' energies and momenta.
struct DiagnosticSums {
  static constexpr int kCount = 12;
  common::ExactSum kinetic, rotational, potential_self, potential_uniform, dissipated, elastic;
  std::array<common::ExactSum, 3> momentum, angular_momentum;

  /// Add sphere i's terms: spin energy when `rotation` (contacts on), E_self when `pot` (its
  /// potential phi_i [J/kg]) is given, E_unif in the uniform field g.
  void add_sphere(const Spheres& sp, std::size_t i, bool rotation, const double* pot, const Vec3& g);
  /// The rounded sums into d's energy and momentum fields (the others are left as they are).
  void store(Diagnostics& d) const;
  /// Each accumulator in a fixed order (for reductions over ranks).
  std::array<common::ExactSum*, kCount> all();
};

}  // namespace ssdem
