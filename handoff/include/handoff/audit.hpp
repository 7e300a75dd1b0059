/// @file audit.hpp
/// The hand-off audit: invariants before (kept particles) and after (spheres), their absolute
/// and relative differences, what the selection dropped, counts, and the closest sphere pair.
/// Stored as group /audit of the sphere file, printed, and written as JSON beside the output.
#pragma once
#include <string>

#include "handoff/invariants.hpp"
#include "handoff/projection.hpp"

namespace handoff {

struct Audit {
  std::string method;
  Invariants input;     ///< all particles of the snapshot
  Invariants before;    ///< the particles handed off (after selection)
  Invariants dropped;   ///< the particles the selection removed
  Invariants after;     ///< the spheres
  std::size_t occupied_mpm_cells = 0;
  std::size_t outflow_particles = 0;  ///< handed-off particles taken from the outflow file
  std::size_t outflow_spheres = 0;    ///< spheres created for them outside the projection's cells
  double sphere_cell = 0.0;
  double min_gap = 0.0;      ///< min over neighbouring sphere pairs of |x_a - x_b| - r_a - r_b [m]
  double max_overlap = 0.0;  ///< max(0, -min_gap) [m]
  bool exact = true;         ///< conserving method reached exact KE and L
  std::string note;

  double kinetic_loss() const { return before.kinetic() - after.kinetic(); }
  double kinetic_loss_relative() const { return before.kinetic() > 0 ? kinetic_loss() / before.kinetic() : 0.0; }
  double mass_error_relative() const;
  double momentum_error_relative() const;        ///< |dP| / (M * rms speed)
  /// |dL| / max(|L_before|, sum m |r| |u|): relative to the angular momentum the motion could
  /// carry, so that a head-on impact (L ~ 0) does not divide by round-off.
  double angular_momentum_error_relative() const;
};

/// Smallest gap between the projection's spheres whose cells neighbour each other (+inf for a
/// single sphere). Spheres appended for outflow particles sit at centres of other cells of the
/// same lattice, so they cannot overlap any sphere.
double min_sphere_gap(const ProjectionResult& r);

/// Human-readable multi-line summary.
std::string audit_text(const Audit& a);
/// JSON document.
std::string audit_json(const Audit& a);
/// Attributes of group /audit in an open HDF5 file.
void write_audit_h5(long long file, const Audit& a);

}  // namespace handoff
