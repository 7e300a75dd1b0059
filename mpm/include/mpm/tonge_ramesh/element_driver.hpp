/// @file element_driver.hpp
/// Single-material-point (homogeneous deformation) driver for the Tonge–Ramesh model, the
/// analogue of the mixed-BC driver `runUMATTR_MixedBC` of ARL-SR-0344 §5–7: constant axial
/// strain rate (logarithmic) with zero lateral stress (uniaxial stress), lateral stretch rate found
/// each step by secant iteration on sigma_22 = sigma_33 = 0 (lateral symmetry).
#pragma once
#include <cstdint>
#include <vector>

#include "mpm/tonge_ramesh/params.hpp"
#include "mpm/tonge_ramesh/point_update.hpp"

namespace mpmfrag::tonge_ramesh {

/// One sample of a single-element history.
struct ElementSample {
  double t, strain, stress, lateral_stress, D, JGP;
};

/// Result of a uniaxial-stress run.
struct ElementResult {
  double peak_stress = 0.0;     ///< max |sigma_11| [Pa]
  double strain_at_peak = 0.0;  ///< axial log strain at the peak
  double final_D = 0.0;
  double max_lateral_residual = 0.0;  ///< max |sigma_22|/|sigma_11| on the loading branch
  long steps = 0;
  bool ok = true;               ///< false: the point update rejected an input
  std::vector<ElementSample> history;  ///< every `record_every`-th step (if > 0)
};

/// Uniaxial stress at axial strain rate `rate` [1/s] (> 0 tension, < 0 compression) on one point
/// of initial volume V (flaws sampled with particle id `id`), until the stress has dropped below
/// `drop` x peak after the peak, or |strain| reaches `max_strain`. Axial strain increment per step
/// `dstrain`.
ElementResult run_uniaxial_stress(const Params& p, double V, std::uint64_t id, double rate,
                                  double dstrain = 2e-6, double max_strain = 0.03,
                                  double drop = 0.5, int record_every = 0);

}  // namespace mpmfrag::tonge_ramesh
