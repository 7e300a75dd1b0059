/// @file params.hpp
/// Parameters of the Tonge–Ramesh brittle-damage model (Tonge & Ramesh 2016, JMPS 86:117, as
/// implemented in Uintah's "portable Tonge–Ramesh", PTR) in the variant of El Mir, Ramesh &
/// Richardson (2019, Icarus 321:1013): Tillotson EOS, two bounded-Pareto flaw populations.
/// Parameter names follow the PTR list (ARL-SR-0344, Tonge 2015) mapped to SI values; the basalt
/// preset is El Mir et al. (2019) Table 1 plus the documented assumptions in params.cpp.
#pragma once
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "common/choice.hpp"

namespace mpmfrag::tonge_ramesh {

/// One bounded-Pareto flaw population, pdf g(s) ∝ s^(-a-1) on [s_min, s_max].
struct FlawPopulation {
  double s_min = 5e-6;     ///< smallest flaw half-size [m]
  double s_max = 1e-3;     ///< largest flaw half-size [m]
  double exponent = 3.0;   ///< Pareto exponent a [-]
  double density = 2e12;   ///< total flaw number density eta over [s_min, s_max] [1/m^3]
  int bins = 25;           ///< number of size bins
  double bin_bias = -3.0;  ///< bin spacing: 1 uniform, b>0 power, b<0 rational (PTR method 7)
  /// Specimen sizes the population applies to [m]: it is realised only in a body whose size
  /// (flaws.hpp, population_applies) lies in [min_specimen, max_specimen]; otherwise its bins
  /// stay empty. A lab specimen cut from intact rock does not hold the joints of an outcrop.
  double min_specimen = 0.0;
  double max_specimen = 1e30;
};

/// Cold/compressed Tillotson constants (Tillotson 1962; Benz & Asphaug 1999 basalt values).
struct TillotsonCold {
  double A = 26.7e9;   ///< [Pa]
  double B = 26.7e9;   ///< [Pa]
  double a = 0.5;      ///< [-]
  double b = 1.5;      ///< [-]
  double E0 = 4.87e8;  ///< [J/kg]
};

/// How a population's bins are filled for one particle (flaws.hpp).
///  * scale_aware (default): each bin is realised at its own scale: Poisson counts per particle
///    where a particle expects >= block_count flaws of the bin (and is >= block_size_factor x the
///    bin's largest flaw), else one Poisson draw per cubic block of particles of the smallest edge
///    that satisfies both, shared by the particles of the block (keyed by the block's position
///    index); the expected density where such a block is larger than the specimen.
///  * poisson: each particle draws its own flaws, n_k ~ Poisson(eta V Delta F_k), omega_k = n_k/V
///    (PTR RandomizeMethod 7; the El Mir/issue default). The largest flaw a particle can hold
///    shrinks with its volume, so the strength depends on the cell size.
///  * expected: every particle carries the expected density of every bin, omega_k = eta Delta F_k,
///    s_k = E[s^3 | bin k]^(1/3) (PTR's non-random option, RandomizeFlawDist = 0, with the same bin
///    edges): the flaw population is a property of the continuum, independent of particle volume.
enum class FlawSampling { scale_aware, poisson, expected };
/// Scene spellings of FlawSampling (tonge_ramesh key flaw_sampling).
inline constexpr std::array kFlawSamplings{common::Choice{"scale_aware", FlawSampling::scale_aware},
                                           common::Choice{"poisson", FlawSampling::poisson},
                                           common::Choice{"expected", FlawSampling::expected}};

/// All model parameters (SI). Members read from the scene carry the name of their key in the
/// tonge_ramesh style (style.cpp), e.g. `density`, `shear_modulus` (G0), `pa_P0` (P_e).
struct Params {
  double density = 2700.0;        ///< reference solid density rho0 [kg/m^3]
  double shear_modulus = 22.7e9;  ///< undamaged shear modulus G0 [Pa]
  TillotsonCold eos;           ///< matrix EOS; K0 = eos.A
  bool use_damage = true;      ///< micromechanical wing-crack damage
  bool use_granular = true;    ///< granular (Drucker–Prager) flow + P–alpha compaction
  // micromechanics
  std::vector<FlawPopulation> populations;  ///< concatenated into one bin list
  double KIc = 1.6e6;           ///< mode-I fracture toughness [Pa m^0.5]
  double flaw_friction = 0.2;   ///< crack-face friction mu [-]
  double flaw_angle = -1.0;     ///< phi [rad]; <0 means pi/2 - atan(1/mu)/2
  double growth_exponent = 1.0; ///< gamma_c [-]
  double growth_alpha = 5.0;    ///< alpha_c: v_max = C_R / alpha_c [-]
  double critical_damage = 0.125;  ///< D_c: granular flow on [-]
  double max_damage = 0.2;         ///< D_max: damage frozen [-]
  double max_damage_inc = 1e-4;    ///< Delta D per damage sub-step [-]
  int max_substeps = 2000;         ///< cap on damage sub-steps per step (cost guard)
  bool include_initial_damage = true;  ///< D = sum w (s+l)^3 (true) or sum w l^3
  bool friction_in_tension = false;  ///< PTR QUIRK 7.3 (true reproduces PTR)
  // granular flow (cone, PTR yield type 1) and P–alpha
  double dp_slope = 0.6;        ///< A_DP [-]
  double dp_cohesion = 0.3e6;   ///< B_DP [Pa]
  double granular_time = 0.0;   ///< Duvaut–Lions relaxation time (0 = rate independent) [s]
  double j_loc = 5.0;           ///< J_GP above which the point is flagged localized [-]
  double pa_P0 = 75e6;          ///< P–alpha onset pressure P_e ("P0") [Pa]
  double pa_alpha0 = 1.25;      ///< P–alpha distension alpha_e at P_e ("alpha0") [-]
  double pa_Pc = 200e6;         ///< P–alpha full-compaction pressure P_c [Pa]
  std::uint64_t flaw_seed = 0;  ///< user part of the flaw-sampling seed
  FlawSampling flaw_sampling = FlawSampling::scale_aware;  ///< how bins are realised (flaws.hpp)
  double block_count = 1.0;        ///< scale_aware: expected flaws per sampling volume, lambda_min [-]
  double block_size_factor = 4.0;  ///< scale_aware: sampling-volume edge >= this x s_h of the bin [-]
  double specimen_size = 0.0;      ///< body size for population_applies [m]; 0: not known (all apply)

  /// Total bin count over all populations.
  int total_bins() const {
    int n = 0;
    for (const auto& p : populations) n += p.bins;
    return n;
  }
  /// Throws common::InputError on inconsistent values.
  void validate() const;
};

/// Quantities derived once from Params.
struct Derived {
  double K0 = 0, nu0 = 0, E0 = 0;      ///< reference bulk/Poisson/Young
  double kK = 0, kG = 0;               ///< K/K0 = 1/(1+kK D), G/G0 = 1/(1+kG D)
  double cs = 0, cR = 0, v_max = 0;    ///< shear, Rayleigh, limiting crack speed [m/s]
  double sin_phi = 0, cos_phi = 0, sin2phi = 0;
  double pa_kappa = 0;                 ///< (P_c-P_e)/(2 P_e (alpha_e-1))
  explicit Derived(const Params& p);
};

/// El Mir, Ramesh & Richardson (2019) Table 1 basalt, two flaw populations, 25 bins each.
Params basalt_el_mir();

}  // namespace mpmfrag::tonge_ramesh
