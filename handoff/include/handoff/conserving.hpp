/// @file conserving.hpp
/// Alternative hand-off ("conserving"): the paper's spheres (projection.hpp), then a global
/// correction of sphere velocities and spins that restores the particles' kinetic energy and
/// angular momentum exactly while keeping mass and linear momentum exact.
///
/// With sphere masses M_c, positions r_c relative to the sphere centre of mass X, peculiar
/// velocities u_c = v_c - V (V = P/M), the corrected state is
///     v'_c = V + lambda u_c + Omega x r_c,     omega'_c = Omega        (rigid-consistent spin)
/// Linear momentum is unchanged (sum M_c u_c = 0, sum M_c r_c = 0). With
///     A = sum M_c r_c x u_c,  B = sum M_c |u_c|^2,
///     I = sum M_c (|r_c|^2 1 - r_c r_c^T) + sum (2/5) M_c a_c^2 1     (a_c = sphere radius),
/// the angular momentum about X is L' = lambda A + I Omega and the kinetic energy in the
/// centre-of-mass frame is K'_int = lambda^2 (B - A.I^-1 A)/2 + L'.I^-1 L'/2 (derivation in
/// handoff/README.md). Setting L' = L_0 and K'_int = K_0 - M|V|^2/2 (the particles' values):
///     lambda^2 = (2 K_0,int - L_0.I^-1 L_0) / (B - A.I^-1 A),   Omega = I^-1 (L_0 - lambda A).
/// A real solution exists unless the particles' motion is so close to a rigid rotation that
/// the sphere set, whose inertia lacks each cell's own (M h^2/6 for a filled cell against
/// M h^2/10 for its sphere), cannot carry L_0 with only K_0: then no set of sphere velocities
/// and uniform spins at the cell centres can match both, the paper's spheres are kept
/// unchanged, and the result says so (`exact = false`).
///
/// Trade-off against the paper's method: exact global invariants, but the energy lost locally
/// (intra-cell motion, grid smoothing) is returned as a uniform rescaling of all peculiar
/// velocities (lambda ~ 1 + dK/(2K)) and a small rigid rotation, not where it was lost.
/// This is in the spirit of the energy- and momentum-conserving particle merging of Vranic
/// et al. (2015, Comput. Phys. Commun. 191:65), applied globally rather than per cell.
#pragma once
#include <Eigen/Core>
#include <string>

#include "common/sphere_file.hpp"
#include "handoff/invariants.hpp"

namespace handoff {

struct ConservingResult {
  bool exact = false;
  double lambda = 1.0;
  Eigen::Vector3d omega = Eigen::Vector3d::Zero();
  std::string note;
};

/// Correct `spheres` in place towards `target` (the particles' invariants).
ConservingResult apply_conserving(common::SphereSet& spheres, const Invariants& target);

}  // namespace handoff
