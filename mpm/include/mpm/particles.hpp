/// @file particles.hpp
/// Structure-of-arrays particle storage of mpm-frag. Particles of one material occupy one
/// contiguous index range (MaterialSlot::begin..end); style state arrays are allocated per
/// material slot, only for the styles a scene uses. All loops run over index ranges, so an MPI
/// domain decomposition can later own a sub-range without touching the physics.
#pragma once
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "mpm/material.hpp"

namespace mpmfrag {

/// Per-particle arrays (item-major: vectors N x 3, matrices N x 9 row-major, stress N x 6 Voigt).
struct ParticleSet {
  std::vector<std::uint64_t> id;      ///< global id (stable across reordering)
  std::vector<std::int32_t> material; ///< material index (scene order)
  std::vector<double> x;              ///< position [m]
  std::vector<double> v;              ///< velocity [m/s]
  std::vector<double> F;              ///< deformation gradient [1]
  std::vector<double> stress;         ///< Cauchy stress Voigt xx,yy,zz,yz,xz,xy [Pa]
  std::vector<double> mass;           ///< [kg]
  std::vector<double> volume;         ///< current volume V0 det F [m^3]
  std::vector<double> volume0;        ///< initial volume [m^3]
  std::vector<double> energy;         ///< specific internal energy [J/kg]
  std::vector<double> half_width;     ///< uGIMP half-widths l_p (N x 3, fixed) [m]
  std::vector<double> q;              ///< artificial bulk viscosity [Pa] (only if enabled)

  std::size_t size() const { return id.size(); }
  /// Resize every core array (q only if `with_q`). New F entries are the identity.
  void resize(std::size_t n, bool with_q);
  /// Bytes held by the core arrays (capacity-independent: size * element size).
  std::size_t bytes() const;
};

/// One configured material and the particles (a contiguous range) that use it.
struct MaterialSlot {
  std::string name;                          ///< scene name of the material
  const StyleInfo* style = nullptr;          ///< registry entry
  std::shared_ptr<const Material> model;     ///< configured model
  std::size_t begin = 0, end = 0;            ///< particle range
  std::vector<std::vector<double>> state;    ///< style state arrays, (end-begin)*ncomp each
  /// Allocate and initialise the state arrays for the current range.
  void allocate_state();
  std::size_t bytes() const;
};

}  // namespace mpmfrag
