/// @file gravity_cadence.hpp
/// The error-controlled gravity cadence (equations in simulation.hpp): the length of the next
/// gravity block from the measured force change of the block that just ended. Shared by
/// Simulation and the MPI DomainSim, which differ only in how they sum over the spheres:
///   g2 = sum_i |g_i|^2, d2 = sum_i |g_i - g_i'|^2, cmax = max_i |g_i - g_i'| / max(|g_i|, 0.1 g_rms)
///   c = sqrt(d2 / g2), k_next = floor(k / max(c / eta, cmax / 0.1)) in [1, min(2 k, k_max)].
#pragma once
#include "ssdem/simulation.hpp"

namespace ssdem {

/// Largest relative force change of one sphere per block (above the tree's own per-sphere error
/// jumps when the tree changes, up to ~2e-2).
inline constexpr double kCadenceMaxChange = 0.1;

/// Next block length after a block of k steps; records the block in `stats`.
int next_gravity_block(int k, double g2, double d2, double cmax, const SimConfig& cfg, CadenceStats& stats);

/// The measures' sums over the spheres `idx` (every sphere if null), exact
/// (common/exact_sum.hpp) so that the block length does not depend on the thread count, nor on
/// the MPI rank count once the ranks' sums are added: sum_i |g_i|^2, and
/// sum_i |g_i - g_i'|^2 with max_i |g_i - g_i'| / max(|g_i|, floor).
common::ExactSum cadence_g2(const std::vector<Vec3>& g, const std::vector<std::uint32_t>* idx);
void cadence_change(const std::vector<Vec3>& g, const std::vector<Vec3>& g_old, double floor,
                    const std::vector<std::uint32_t>* idx, common::ExactSum& d2, double& cmax);

}  // namespace ssdem
