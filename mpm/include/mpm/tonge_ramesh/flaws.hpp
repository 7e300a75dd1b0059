/// @file flaws.hpp
/// Bounded-Pareto flaw populations and their per-particle discretisation into bins
/// (PTR `initalizeFlawDist`, RandomizeMethod 7; ARL-SR-0344 §3). For a population with
/// pdf g(s) = a s_min^a s^(-a-1)/(1-(s_min/s_max)^a) and total density eta, the expected count
/// in a particle of volume V and size interval [s_l, s_h] is lambda = eta V (F(s_h)-F(s_l)).
/// Each bin draws n ~ Poisson(lambda) from a KeyedRng stream keyed by (scene seed, global particle
/// id, population), sets omega = n/V and the representative size s_k = (mean s^3)^(1/3) of the
/// n flaws (exact inverse-CDF draws for n < 20, a truncated normal on s^3 for n >= 20).
/// QUIRK (PTR uses sqrt(E[s^6]/n) as the spread of mean s^3): fixed, we use the variance
/// sqrt((E[s^6]-E[s^3]^2)/n), which is the statistically correct standard error.
/// With Params::flaw_sampling == expected every particle instead gets omega_k = eta (F(s_h)-F(s_l)) and
/// s_k = E[s^3 | s_l..s_h]^(1/3), independent of V and of the random stream (exact sum omega s^3 =
/// eta E[s^3]).
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

/// Sample all populations of `p` for one particle of initial volume V [m^3] into the bin arrays
/// omega [1/m^3] and s [m] (each of size p.total_bins()), keyed by (p.flaw_seed, particle_id,
/// material_id). Returns the initial damage sum omega s^3.
double sample_flaws(const Params& p, double V, std::uint64_t particle_id, std::uint64_t material_id,
                    double* omega, double* s);

}  // namespace mpmfrag::tonge_ramesh
