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

struct ParticleSet;

/// Description of one per-particle array of ParticleSet (see ParticleSet::for_each_array).
struct ArrayInfo {
  const char* name;                  ///< member name
  const char* unit;                  ///< SI unit ("1" for dimensionless and integer arrays)
  int width = 1;                     ///< components per particle
  const char* dataset = nullptr;     ///< snapshot dataset name (particle_file.hpp); nullptr: not written
  double dataset_scale = 1.0;        ///< the dataset holds dataset_scale * the array (size = 2 l_p)
  const char* description = "";      ///< HDF5 `description` of a state dataset (not a core dataset)
  bool optional = false;             ///< empty unless enabled (q: artificial viscosity)
  bool identity_init = false;        ///< new entries of this 3x3 array start as the identity (F)
};

/// One ParticleSet array: its description, element type and member pointer (`ps.*member`).
template <class T>
struct ParticleArray {
  using element_type = T;
  ArrayInfo info;
  std::vector<T> ParticleSet::*member;
};

/// Per-particle arrays (item-major: vectors N x 3, matrices N x 9 row-major, stress N x 6 Voigt).
///
/// The list of arrays lives in one place, for_each_array(): resize, bytes, the solver's
/// locality reordering, the outflow copy and compaction and the snapshot datasets
/// (add_particle_datasets, output.hpp) all walk it. Adding an array = declaring the member
/// below and adding its line to for_each_array.
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
  // Energy budget (energy_budget.hpp): parts of `energy` accumulated since t = 0 [J/kg]
  std::vector<double> work_dev;       ///< deviatoric stress work int s : D dt / rho
  std::vector<double> heat_shock;     ///< artificial-viscosity (shock) heating int q |tr D| dt / rho
  std::vector<double> heat_transfer;  ///< transfer kinetic-energy fix-up (scheme "midpoint")

  /// Call f(ParticleArray<T>) for every array above, in this order (which is also the order of
  /// the state datasets stress, internal_energy in snapshots).
  template <class F>
  static constexpr void for_each_array(F&& f) {
    using u64 = ParticleArray<std::uint64_t>;
    using i32 = ParticleArray<std::int32_t>;
    using f64 = ParticleArray<double>;
    f(u64{{.name = "id", .unit = "1", .dataset = "id"}, &ParticleSet::id});
    f(i32{{.name = "material", .unit = "1", .dataset = "material"}, &ParticleSet::material});
    f(f64{{.name = "x", .unit = "m", .width = 3, .dataset = "position"}, &ParticleSet::x});
    f(f64{{.name = "v", .unit = "m/s", .width = 3, .dataset = "velocity"}, &ParticleSet::v});
    f(f64{{.name = "F", .unit = "1", .width = 9, .identity_init = true}, &ParticleSet::F});
    f(f64{{.name = "stress", .unit = "Pa", .width = 6, .dataset = "stress",
           .description = "Cauchy stress, Voigt order xx,yy,zz,yz,xz,xy, tension positive"},
          &ParticleSet::stress});
    f(f64{{.name = "mass", .unit = "kg", .dataset = "mass"}, &ParticleSet::mass});
    f(f64{{.name = "volume", .unit = "m^3", .dataset = "volume"}, &ParticleSet::volume});
    f(f64{{.name = "volume0", .unit = "m^3"}, &ParticleSet::volume0});
    f(f64{{.name = "energy", .unit = "J/kg", .dataset = "internal_energy", .description = "specific internal energy"},
          &ParticleSet::energy});
    f(f64{{.name = "half_width", .unit = "m", .width = 3, .dataset = "size", .dataset_scale = 2.0},
          &ParticleSet::half_width});
    f(f64{{.name = "q", .unit = "Pa", .optional = true}, &ParticleSet::q});
    f(f64{{.name = "work_dev", .unit = "J/kg"}, &ParticleSet::work_dev});
    f(f64{{.name = "heat_shock", .unit = "J/kg"}, &ParticleSet::heat_shock});
    f(f64{{.name = "heat_transfer", .unit = "J/kg"}, &ParticleSet::heat_transfer});
  }

  std::size_t size() const { return id.size(); }
  /// Resize every array to n particles (optional ones only if `with_q`, else they are
  /// cleared). New entries of identity_init arrays (F) are the identity, others 0.
  void resize(std::size_t n, bool with_q);
  /// Bytes held by the arrays (capacity-independent: size * element size).
  std::size_t bytes() const;
};

/// One configured material and the particles (a contiguous range) that use it.
struct MaterialSlot {
  std::string name;                          ///< scene name of the material
  const StyleInfo* style = nullptr;          ///< registry entry
  std::shared_ptr<const Material> model;     ///< configured model
  std::size_t begin = 0, end = 0;            ///< particle range
  double extent = 0.0;  ///< largest bounding-box edge of the range at initialize() + spacing [m]
  std::vector<std::vector<double>> state;    ///< style state arrays, (end-begin)*ncomp each
  /// Allocate and initialise the state arrays for the current range.
  void allocate_state();
  std::size_t bytes() const;
};

}  // namespace mpmfrag
