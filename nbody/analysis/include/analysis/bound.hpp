/// @file bound.hpp
/// Clump properties and the mass gravitationally bound to the largest remnant.
///
/// The largest remnant (LR) is the most massive FOF clump (fof.hpp). Every other clump k
/// (single spheres included) is tested with the two-body energy of its relative orbit about the
/// current remnant (mass M, centre of mass R, centre-of-mass velocity V):
///     E_k = 1/2 |v_k - V|^2 - G (M + m_k) / |r_k - R|                             (1)
/// (per unit reduced mass; pkdgrav `rpa`, ssdem.md §5.1: escaping if E >= 0). Clumps with
/// E_k < 0 join the remnant; M, R, V are recomputed from all members and the test is repeated
/// until no clump is added (the iterative bound-mass recipe of ssdem.md §5.1 and
/// validation-data.md §5.1 step 2). Membership only grows, so the iteration terminates.
/// Deviation from a full potential: the remnant is a point mass in (1) (as in rpa and
/// validation-data.md §5.1); a clump inside the remnant's extent is over-bound, which only
/// matters for material that FOF did not already link to the remnant.
/// Sums run in clump-index order (serial, deterministic); the energy test of a pass is
/// evaluated in parallel against fixed M, R, V (Jacobi passes), so the result does not depend on
/// the thread count.
#pragma once
#include <Eigen/Core>
#include <cstddef>
#include <vector>

#include "analysis/fof.hpp"

namespace analysis {

/// Mass, centre of mass and centre-of-mass velocity of every clump.
struct ClumpProps {
  std::vector<double> mass;
  std::vector<Eigen::Vector3d> com;
  std::vector<Eigen::Vector3d> vel;  ///< momentum / mass
};

ClumpProps clump_properties(const double* position, const double* velocity, const double* mass,
                            std::size_t n, const FofResult& fof);

struct BoundResult {
  std::vector<char> bound;         ///< per clump: member of the bound remnant (clump 0 always)
  std::size_t n_bound_clumps = 0;  ///< including the LR itself
  int iterations = 0;              ///< passes until no change
  double lr_mass = 0.0;
  Eigen::Vector3d lr_com = Eigen::Vector3d::Zero(), lr_momentum = Eigen::Vector3d::Zero();
  double bound_mass = 0.0;
  Eigen::Vector3d bound_com = Eigen::Vector3d::Zero(), bound_momentum = Eigen::Vector3d::Zero();
  double escaping_mass = 0.0;
  Eigen::Vector3d escaping_momentum = Eigen::Vector3d::Zero();
  double total_mass = 0.0;
  Eigen::Vector3d total_momentum = Eigen::Vector3d::Zero();
};

/// Two-body energy (1) of a body (m, r, v) relative to a remnant (M, R, V) [J/kg].
double two_body_energy(double M, const Eigen::Vector3d& R, const Eigen::Vector3d& V, double m,
                       const Eigen::Vector3d& r, const Eigen::Vector3d& v, double G);

/// Iterate (1) from the largest clump until no clump joins. `max_iterations` caps the passes
/// (a cap that is reached is reported through `iterations == max_iterations`).
BoundResult bound_to_largest(const ClumpProps& clumps, double G, int max_iterations = 1000);

}  // namespace analysis
