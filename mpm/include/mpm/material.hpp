/// @file material.hpp
/// Material (constitutive model) interface of mpm-frag and the registry that selects a style by
/// its string key ("elastic", "neo_hookean", "tillotson", and plug-ins such as "tonge_ramesh").
///
/// ## Contract between the solver and a material style (read this if you write one)
///
/// Storage. Particles are stored structure-of-arrays (ParticleSet, particles.hpp). Particles of
/// one material occupy one contiguous index range; the solver calls a style on sub-ranges
/// ("batches", typically a few hundred particles, from several OpenMP threads at once — so
/// `update` must be const/thread-safe and must only touch the particles of its batch).
///
/// Every pointer in a MaterialBatch is already offset to the first particle of the batch:
/// particle k (0 <= k < n) of the batch reads `L + 9*k`, `F + 9*k`, `stress + 6*k`, `volume[k]`,
/// `state[f] + ncomp_f*k`, ...  Matrices are row-major 3x3 (`M(i,j) = m[3*i+j]`); use
/// `Eigen::Map<const Eigen::Matrix<double,3,3,Eigen::RowMajor>>`.
///
/// Per particle the style receives (time level n -> n+1, dt = t_{n+1} - t_n):
///   - L        velocity gradient L_ij = dv_i/dx_j at the step's grid velocity [1/s]
///   - F        deformation gradient at n+1, already updated by F_{n+1} = (I + L dt) F_n;
///              J_{n+1} = det F; J_n = J_{n+1} / det(I + L dt) (helper `jacobian_old`)
///   - stress   Cauchy stress, 6 Voigt components (xx, yy, zz, yz, xz, xy) [Pa], tension
///              positive; IN: sigma_n, OUT: sigma_{n+1} (the style overwrites it)
///   - mass [kg], volume (current, V0*J_{n+1}) [m^3], volume0 [m^3]; density = mass/volume
///   - energy   specific internal energy e_n [J/kg] (read-only; see Energy below)
///   - id       global particle id (use common::KeyedRng(seed, id, stream) for random numbers,
///              never a shared generator, so results do not depend on the thread count)
///   - state    the style's own per-particle arrays, in the order of StyleInfo::state_fields,
///              allocated (and initialised to StateField::initial) only when a scene uses the
///              style; the style updates them in place
///   - cell_size the grid spacing [m] (for regularisation lengths), time t_n [s], seed
/// and must write, per particle:
///   - stress   sigma_{n+1}
///   - wave_speed[k]  the dilatational (longitudinal) wave speed at the new state [m/s], used for
///                    the CFL condition dt = C h / max(c + |v|)
///   - bulk_speed[k]  the bulk sound speed sqrt(K_eff/rho) [m/s] for the artificial viscosity,
///                    only if `bulk_speed != nullptr`
/// and returns a BatchResult: the number of particles it could not update (non-finite input,
/// J <= 0, model-specific failure) and the first such index, with a short reason. The solver turns
/// a non-zero count into a NumericalError (exit 3, last good state saved).
///
/// Energy. The solver integrates the specific internal energy itself after the call:
///   e_{n+1} = e_n + dt/(2 rho_{n+1}) (sigma_n + sigma_{n+1}) : D  +  q |tr D| dt / rho_{n+1}
/// (trapezoidal stress power plus the artificial-viscosity heating), so a style never writes
/// `energy`; an EOS that needs e_{n+1} (Tillotson) makes its own predictor from e_n.
///
/// Artificial viscosity q is computed by the solver from `bulk_speed`; it is not part of `stress`.
///
/// Life cycle. `StyleInfo::create(params)` builds a Material from the [[material]] element of the
/// scene (its keys are those of `StyleInfo::schema` plus the common keys `name`, `model`,
/// `density`). `initialize(batch)` is called once after the particles are created (F = I or the
/// initial F, L = 0, dt = 0): it sets the initial stress and the wave speeds.
///
/// ## What a new material takes: one source file and one registry line
///
/// 1. One file, e.g. mpm/src/materials/<style>.cpp (every .cpp under mpm/src/ is compiled; no
///    CMake edit), holding
///    - a class derived from Material that implements the three pure virtual methods
///      `density()`, `reference_wave_speed()` and `update(batch)` (and `initialize(batch)` only
///      if the initial state differs from update() with dt = 0, L = 0), and
///    - `void register_<style>(MaterialRegistry& reg)`, which calls `reg.add(StyleInfo{...})`
///      with the key, a one-line description, the style's parameter Schema, its StateField list
///      (per-particle arrays; written to snapshots when `output`) and the `create` factory.
/// 2. One line `register_<style>(reg);` in `register_builtin_materials`
///    (mpm/src/material_registry.cpp), beside the declaration of `register_<style>` (in
///    mpm/materials/builtin.hpp, or the style's own header for a plug-in such as tonge_ramesh).
///
/// Nothing else: snapshots, the outflow record and reordering pick up the state fields from
/// StateField, the scene schema from StyleInfo::schema (tests/mpm/test_scene_setup.cpp has a
/// minimal style, `WithState`).
#pragma once
#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "common/schema.hpp"

namespace mpmfrag {

/// One per-particle state array declared by a material style.
struct StateField {
  std::string name;         ///< dataset name in snapshots, e.g. "damage", "plastic_strain"
  int ncomp = 1;            ///< components per particle
  std::string unit;         ///< SI unit ("1" for dimensionless)
  double initial = 0.0;     ///< initial value of every component
  bool output = true;       ///< written to particle snapshots
  std::string description;  ///< one line for the HDF5 `description` attribute
  /// > 0: a cost weight, not physics. The field (one component) holds a count from the last
  /// update, each unit of which costs `work` times a plain particle-step (the grid transfers of
  /// one particle, P2G + G2P); the MPI decomposition balances sum_p (1 + work s_p) per rank
  /// (mpm/mpi/domain.hpp). A checkpoint without it (written before the field existed) restarts
  /// with `initial`.
  double work = 0.0;
};

/// A view of `n` consecutive particles of one material (all pointers offset to the first).
struct MaterialBatch {
  std::size_t n = 0;                   ///< particles in the batch
  std::size_t first = 0;               ///< global index of particle 0 of the batch (diagnostics)
  double dt = 0.0;                     ///< time step [s] (0 in initialize)
  double time = 0.0;                   ///< t_n [s]
  double cell_size = 0.0;              ///< grid spacing h [m] (min over axes)
  std::uint64_t seed = 0;              ///< scene random seed (for common::KeyedRng)
  const double* L = nullptr;           ///< 9n, velocity gradient [1/s], row-major
  const double* F = nullptr;           ///< 9n, deformation gradient at n+1, row-major
  double* stress = nullptr;            ///< 6n, Cauchy stress Voigt xx,yy,zz,yz,xz,xy [Pa], in/out
  const double* mass = nullptr;        ///< n [kg]
  const double* volume = nullptr;      ///< n, current volume [m^3]
  const double* volume0 = nullptr;     ///< n, initial volume [m^3]
  const double* energy = nullptr;      ///< n, specific internal energy e_n [J/kg]
  const std::uint64_t* id = nullptr;   ///< n, global particle ids
  const double* x = nullptr;           ///< 3n, particle positions [m] (initial ones in initialize)
  double specimen_size = 0.0;          ///< largest extent of this material's particles at t = 0 [m]
  double* const* state = nullptr;      ///< the style's state arrays (StyleInfo::state_fields order)
  double* wave_speed = nullptr;        ///< n, OUT: dilatational wave speed [m/s]
  double* bulk_speed = nullptr;        ///< n, OUT (if not null): bulk sound speed [m/s]
};

/// Outcome of a batch update.
struct BatchResult {
  std::size_t failed = 0;        ///< particles that could not be updated
  std::size_t first_failed = 0;  ///< batch-local index of the first one
  const char* reason = "";       ///< static string, e.g. "J <= 0"
};

/// A configured material (one [[material]] entry of a scene).
class Material {
 public:
  virtual ~Material() = default;
  /// Reference density rho_0 [kg/m^3] (particle masses of the scene set-up).
  virtual double density() const = 0;
  /// Dilatational wave speed at the reference state [m/s] (for the first time step).
  virtual double reference_wave_speed() const = 0;
  /// Energy budget (energy_budget.hpp), per particle k of the batch: the recoverable DEVIATORIC
  /// elastic strain energy the style stores, elastic[k] [J] (its volumetric energy is part of the
  /// EOS work), and the energy dissipated so far by plastic or granular flow, dissipated[k] [J],
  /// from the current stress and state (read-only; dt, L unused). Default: both 0 (a fluid).
  virtual void stored_energies(const MaterialBatch& b, double* elastic, double* dissipated) const {
    for (std::size_t k = 0; k < b.n; ++k) elastic[k] = dissipated[k] = 0.0;
  }
  /// Set the initial stress and wave speeds (dt = 0, L = 0, F = initial F). Default: update().
  virtual void initialize(const MaterialBatch& b) const { update(b); }
  /// Advance the stress (and the style's state) of the batch from t_n to t_{n+1}.
  virtual BatchResult update(const MaterialBatch& b) const = 0;
};

/// What a style declares: key, parameters, per-particle state, factory.
struct StyleInfo {
  std::string name;                       ///< registry key, the scene's `model = "..."`
  std::string description;                ///< one line for --help-params
  common::Schema schema;                  ///< style-specific keys of a [[material]] element
  std::vector<StateField> state_fields;   ///< per-particle arrays the style needs
  /// Build from the resolved [[material]] element (keys relative to the element).
  std::function<std::unique_ptr<Material>(const common::Scene& element)> create;
};

/// Registry of material styles, filled explicitly (no static self-registration).
class MaterialRegistry {
 public:
  /// Add a style; throws std::invalid_argument if the name is taken.
  void add(StyleInfo info);
  /// The style `name`, or nullptr.
  const StyleInfo* find(const std::string& name) const;
  /// All style names, sorted.
  std::vector<std::string> names() const;
  /// Map name -> style schema (for common::Schema::add_style_switch).
  std::map<std::string, common::Schema> schemas() const;

 private:
  std::map<std::string, StyleInfo> styles_;
};

/// Register elastic, neo_hookean, tillotson (and plug-in styles, one line each).
void register_builtin_materials(MaterialRegistry& reg);

/// A registry with all builtin styles.
const MaterialRegistry& builtin_materials();

/// J_n from J_{n+1} and the step's velocity gradient: J_{n+1} / det(I + L dt).
inline double jacobian_old(double J_new, const double* L, double dt) {
  const double a = 1 + L[0] * dt, b = L[1] * dt, c = L[2] * dt;
  const double d = L[3] * dt, e = 1 + L[4] * dt, f = L[5] * dt;
  const double g = L[6] * dt, h = L[7] * dt, i = 1 + L[8] * dt;
  const double det = a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g);
  return J_new / det;
}

/// Determinant of a row-major 3x3 matrix.
inline double det3(const double* m) {
  return m[0] * (m[4] * m[8] - m[5] * m[7]) - m[1] * (m[3] * m[8] - m[5] * m[6]) +
         m[2] * (m[3] * m[7] - m[4] * m[6]);
}

/// Rotate a Voigt stress by the Hughes–Winget incremental rotation of the spin W = skew(L):
/// sigma <- R sigma R^T, R = (I - W dt/2)^{-1} (I + W dt/2) (objective, exactly orthogonal).
void rotate_stress_hughes_winget(double* voigt, const double* L, double dt);

}  // namespace mpmfrag
