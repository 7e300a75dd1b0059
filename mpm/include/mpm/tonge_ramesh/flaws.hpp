/// @file flaws.hpp
/// Bounded-Pareto flaw populations and their discretisation into bins per particle
/// (PTR `initalizeFlawDist`, RandomizeMethod 7; ARL-SR-0344 §3), realised at the scale of the
/// flaws (issue 16).
///
/// Population: pdf g(s) = a s_min^a s^(-a-1) / (1-(s_min/s_max)^a) on [s_min, s_max], total
/// density eta [1/m^3]. Bin k = [s_l, s_h] (bin_edges) holds the number density
///     n_k = eta (F(s_h) - F(s_l))                                                        (1)
/// Every bin is realised in a sampling volume V_s (a particle or a block of particles): a count
/// N ~ Poisson(n_k V_s) and N sizes from g truncated to [s_l, s_h]; every particle of the sampling
/// volume gets
///     omega_k = N / V_s,   s_k = ((1/N) sum_i s_i^3)^(1/3)                               (2)
/// (exact inverse-CDF draws for N < 20, a truncated normal on the mean of s^3 for N >= 20 with
/// the standard error sqrt((E[s^6]-E[s^3]^2)/N); PTR QUIRK fixed: PTR uses sqrt(E[s^6]/N)).
///
/// Why the mean density per bin does not depend on V_s: E[omega_k] = E[N]/V_s = n_k, and by
/// Wald's identity E[omega_k s_k^3] = E[N] E[s^3 | bin k] / V_s = n_k E[s^3 | bin k], the bin's
/// share of the initial damage eta E[s^3]. Only the fluctuation depends on V_s:
/// Var[omega_k] = n_k / V_s, correlated over the sampling volume. (Expectations over blocks;
/// a block cut by the specimen surface still carries the density N/V_s inside the specimen.)
///
/// Choice of V_s per bin (Params::flaw_sampling):
///  * poisson  : V_s = the particle volume V (PTR method 7, El Mir). With V = (0.1 mm)^3 and
///    eta = 2e12 m^-3 a particle holds ~2 flaws, almost always 5-10 um; the 0.1-1 mm flaws that set
///    the lab-scale strength are absent or sit alone in one particle, where s ~ dx/2 gives
///    omega s^3 = (s/dx)^3 ~ D_c: a pre-broken one-cell hole instead of a growing crack. The
///    strength then depends on the cell size.
///  * expected : omega_k = n_k, s_k = E[s^3 | bin k]^(1/3) everywhere (no fluctuation).
///  * scale_aware (default): V_s = (m dx)^3, dx = V^(1/3) the particle spacing and m >= 1 the
///    smallest integer with
///        (m dx)^3 n_k >= lambda_min   and   m dx >= c_s s_h                                 (3)
///    (lambda_min = Params::block_count, c_s = Params::block_size_factor). The first condition
///    makes the block at least the mean spacing of the bin's flaws (lambda_min = 1: the edge is
///    n_k^(-1/3)), so a flaw is realised at its own scale and its wing crack can grow up to the
///    block edge omega^(-1/3) = m dx before it interacts; the second keeps every flaw well inside
///    its sampling volume (one flaw adds at most (s_h/(c_s s_h))^3 = 1/64 to D for c_s = 4,
///    far below D_c = 0.125, so no particle starts as a hole). m = 1 is the per-particle Poisson
///    draw of `poisson`, with the same random stream: where every bin has m = 1 (planetary cells)
///    the two samplings give bit-identical flaws. m > 1: the block is the cube
///        b = floor(x / (m dx))  (per axis, x = the particle's initial position, world frame)  (4)
///    and its draw is keyed by (seed, b, m, material, population, bin): the same for every
///    particle of the block, independent of the thread count, the particle order, the grid origin
///    and any domain decomposition. (An interval of length m dx holds exactly m points of a lattice
///    of spacing dx, so every block holds m^3 particles of a regular body.) If m dx exceeds the
///    specimen size (Params::specimen_size > 0), no block inside the specimen expects
///    lambda_min flaws; the bin then carries the expected density (1) instead, which keeps the
///    mean (a draw at that scale would make one specimen's strength hinge on one rare flaw).
///    The threshold lambda_min = 1 was chosen from the Brazilian-disk study in
///    pipelines/damage/README.md (lambda_min in {0.25, 1, 4} at 0.4 and 0.2 mm cells).
///
/// Specimen sizes (population_applies): a population declares the body sizes it applies to,
/// [min_specimen, max_specimen]; in a body outside that range its bins stay empty (omega = 0).
/// The basalt preset gives the 1 cm-80 m population min_specimen = 1 m, so a 10 mm Brazilian disk
/// carries only the 5 um-1 mm flaws, and a 1.2 km impactor or a 25 km target both populations.
/// Poisson counts use KeyedRng::poisson (exact Knuth product below mean 30, rounded normal above;
/// PTR switches at 20: immaterial).
#pragma once
#include <cstdint>
#include <vector>

#include "mpm/tonge_ramesh/params.hpp"

namespace mpmfrag::tonge_ramesh {

/// CDF of the bounded Pareto distribution.
double pareto_cdf(const FlawPopulation& f, double s);
/// n-th raw moment E[s^n] of the Pareto (exponent a) truncated to [s_l, s_h].
double pareto_moment(double a, double s_l, double s_h, int n);
/// Inverse CDF of the Pareto (exponent a) truncated to [s_l, s_h], u in [0,1].
double pareto_inverse(double a, double s_l, double s_h, double u);
/// Bin edges, largest first: edges[0] = s_max ... edges[bins] = s_min.
std::vector<double> bin_edges(const FlawPopulation& f);

/// Whether population f is realised in a body of size `specimen` [m] (0: unknown, always true).
bool population_applies(const FlawPopulation& f, double specimen);

/// Block edge in particle spacings, m of eq. (3), for a bin of density n_k [1/m^3] and largest
/// size s_h [m] with particle spacing dx [m] (1: per-particle draw).
long block_multiple(const Params& p, double n_k, double s_h, double dx);

/// Sample all populations of `p` for one particle of initial volume V [m^3] at initial position
/// x (3 values [m]; nullptr: a lone material point, whose blocks are keyed by its id) into the
/// bin arrays omega [1/m^3] and s [m] (each of size p.total_bins()), keyed by (p.flaw_seed,
/// particle_id or block, material_id). Returns the initial damage sum omega s^3.
double sample_flaws(const Params& p, double V, const double* x, std::uint64_t particle_id,
                    std::uint64_t material_id, double* omega, double* s);
/// A lone material point (x = nullptr).
inline double sample_flaws(const Params& p, double V, std::uint64_t particle_id,
                           std::uint64_t material_id, double* omega, double* s) {
  return sample_flaws(p, V, nullptr, particle_id, material_id, omega, s);
}

}  // namespace mpmfrag::tonge_ramesh
