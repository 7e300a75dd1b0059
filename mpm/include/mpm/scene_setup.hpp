/// @file scene_setup.hpp
/// The mpm-frag scene schema and the construction of a run (grid, bodies -> particles,
/// materials -> registry styles, solver options) from a resolved scene.
///
/// Bodies are primitives filled with a regular lattice of ppc^3 particles per grid cell
/// (spacing dx = h/ppc, uGIMP half-width dx/2); a lattice point is kept if it lies inside the
/// primitive or within kSurfaceTolerance h of its surface (points on a face are in the body
/// whatever the rounding of their coordinates). Bodies must lie inside the domain.
///
/// Exact bodies (`body[].exact = true`, the default): the lattice gives n particles of volume dx^3,
/// whose mass n rho0 dx^3 differs from the body's mass M = rho0 V_true by O(dx/R) (a 1.21 km
/// sphere on 1 km cells, ppc 2: 8 particles, 1.078 M) and whose centre of mass is off the
/// primitive's centre by up to dx/2. Every particle's mass and volume are multiplied by
/// M/(n rho0 dx^3), so that the body's mass is exactly M while each particle keeps the density
/// rho0 (a stress-free initial state: scaling the mass alone would start the body compressed or
/// stretched by the same factor), and the body's particles are shifted together by
/// c - (1/n) sum x_p (|shift| < dx/2) so that the centre of mass is the centre c asked for. The
/// uGIMP half-width stays dx/2. Initial momentum M v0 and hence Q = m_imp U^2 / (2 M_target) are
/// then those of the nominal bodies to round-off.
///
/// Overlap and touching bodies. A lattice point belongs to the FIRST body (scene order) that
/// contains it, surface (within the tolerance) included; bodies overlap (input error) only where a lattice point lies
/// deeper than kSurfaceTolerance h inside two bodies, and two spheres overlap exactly when their
/// centre distance is below r1 + r2 - kSurfaceTolerance h. Bodies that touch at a point or along a
/// face (an impactor resting on its target) are therefore accepted at every cell size: a lattice
/// point on the contact goes to the earlier body, and the later body's mass scaling makes up for
/// it.
#pragma once
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "common/schema.hpp"
#include "mpm/solver.hpp"

namespace mpmfrag {

/// Run-level options (output, progress, safety).
struct RunConfig {
  double t_end = 0;
  std::string out_dir = "out";
  std::string prefix = "mpm";
  double snapshot_interval = 0;   ///< s; 0 = initial and final only
  int series_every = 10;          ///< steps between time-series rows
  int backup_every = 20;          ///< steps between last-good-state copies
  double progress_interval = 10;  ///< s wall clock
  long long max_steps = 0;        ///< 0 = unlimited
  int threads = 0;                ///< 0 = OpenMP default
};

/// Relative depth (in cells) below which a lattice point counts as on a body's surface.
inline constexpr double kSurfaceTolerance = 1e-9;

/// A body's primitive (sphere, box, cylinder) as the set-up uses it.
struct BodyPrimitive {
  /// Depth of x below the surface [m]: > 0 inside, 0 on the surface, < 0 outside (the distance to
  /// the surface for spheres; for boxes and cylinders the distance to the nearest face plane or
  /// mantle, which has the same sign).
  std::function<double(const Eigen::Vector3d&)> depth;
  Eigen::Vector3d lo, hi, center;  ///< bounding box and centre [m]
  double volume = 0;               ///< true volume [m^3]
  double radius = -1;              ///< sphere radius (spheres only, for the exact overlap test)
};

/// The primitive of one [[body]] element; throws common::InputError naming `where`.
BodyPrimitive make_body_primitive(const common::Scene& body, const std::string& where);

/// Which body owns lattice point x that the body `self` would generate, given the bodies before it:
/// -1 if x is outside `self` by more than `tol`, q < earlier.size() if body q (the first that
/// contains x or has it within `tol` of its surface) takes it, earlier.size() if `self` does. Throws common::InputError (naming `where`)
/// if x is deeper than `tol` inside both `self` and an earlier body (the bodies overlap).
int lattice_owner(const std::vector<BodyPrimitive>& earlier, const BodyPrimitive& self, const Eigen::Vector3d& x,
                  double tol, const std::string& where);

/// What the set-up made of one [[body]] (logged by mpm-frag and checked by the tests).
struct BodyInfo {
  std::string name;
  std::size_t particles = 0;
  bool exact = true;                 ///< body[].exact
  double nominal_mass = 0;           ///< rho0 x true volume [kg]
  double lattice_mass = 0;           ///< n rho0 (h/ppc)^3 before any scaling [kg]
  double mass = 0;                   ///< sum of the particle masses [kg]
  Eigen::Vector3d center = Eigen::Vector3d::Zero();          ///< primitive centre [m]
  Eigen::Vector3d lattice_center = Eigen::Vector3d::Zero();  ///< mean lattice point before the shift [m]
  Eigen::Vector3d mass_center = Eigen::Vector3d::Zero();     ///< centre of mass of the particles [m]
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();        ///< body[].velocity [m/s]
};

/// Specific impact energy Q = m_i |v_i - v_t|^2 / (2 M_t) of the first two bodies (the heavier is
/// the target), from the particle masses (`discretised`) or the nominal masses; 0 if < 2 bodies.
double impact_energy(const std::vector<BodyInfo>& bodies, bool discretised);

/// Log each body's particle count, mass (nominal, lattice) and centre of mass, and both Q.
void log_bodies(const std::vector<BodyInfo>& bodies);

/// Everything needed to construct a Solver.
struct Setup {
  SolverConfig solver;
  RunConfig run;
  common::GridInfo grid;
  ParticleSet particles;
  std::vector<MaterialSlot> materials;
  std::vector<BodyDrive> drives;  ///< velocity-driven bodies ([[body]] drive.*; Solver::set_drives)
  std::vector<BodyInfo> bodies;  ///< one per [[body]], scene order
};

/// The full mpm-frag schema (material styles from `reg`).
common::Schema mpm_schema(const MaterialRegistry& reg = builtin_materials());

/// Part of the particles, for a set-up distributed over MPI ranks (mpi/domain.hpp): every body's
/// lattice is generated and the bodies' totals, ids and drives are the whole scene's, but only
/// the particles whose final position x satisfies keep(x) are stored; each(x) (if set) sees
/// every particle's final position, kept or not, in id order.
struct SetupPart {
  std::function<bool(const Eigen::Vector3d&)> keep;
  std::function<void(const Eigen::Vector3d&)> each;
};

/// Build the setup (with `part`: only that part of the particles); throws common::InputError
/// naming the key on bad input.
Setup build_setup(const common::Scene& scene, const MaterialRegistry& reg = builtin_materials(),
                  const SetupPart* part = nullptr);

}  // namespace mpmfrag
