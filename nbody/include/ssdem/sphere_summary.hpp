/// @file sphere_summary.hpp
/// What the run's set-up needs to know of all the spheres at once (the k_n and time-step rules,
/// dt_rule.hpp; the scene's derived speeds, scene_setup.hpp; DomainSim's checks), as one record
/// that a rank holding only a block of the spheres can also get (sphere_summary_mpi.hpp: the same
/// bits from the blocks of any number of ranks). Sums are exact (common/exact_sum.hpp), so the
/// record does not depend on the order of the spheres, hence not on how they are split.
#pragma once
#include <cmath>
#include <cstddef>

#include "ssdem/spheres.hpp"

namespace ssdem {

struct SphereSummary {
  std::size_t n = 0;
  double m1 = INFINITY, m2 = INFINITY;  ///< the two smallest masses (m2 = m1 if two share it) [kg]
  double mmax = 0.0;                    ///< largest mass [kg]
  double m_median = NAN;                ///< upper median mass: the (n/2)-th smallest, 0-based [kg]
  double smin = INFINITY, smax = 0.0;   ///< smallest and largest radius [m]
  double M = 0.0;                       ///< total mass [kg] (exact sum, correctly rounded)
  Vec3 com = Vec3::Zero();              ///< centre of mass [m] (exact sums of m x over M)
  double R = 0.0;                       ///< max over spheres of |x - com| + s [m]
  double vmax = 0.0;                    ///< largest |v| [m/s]
};

/// Offer a mass to the two smallest so far (m1 <= m2; a repeat of the smallest makes m2 = m1):
/// the result does not depend on the order of the offers.
inline void offer_smallest(double m, double& m1, double& m2) {
  if (m < m1) {
    m2 = m1;
    m1 = m;
  } else if (m < m2) {
    m2 = m;
  }
}

/// The summary of `sp` (all the spheres).
SphereSummary summarise(const Spheres& sp);

}  // namespace ssdem
