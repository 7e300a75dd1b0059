/// @file params.cpp
/// Basalt preset and derived constants of the Tonge–Ramesh model.
///
/// Basalt preset = El Mir, Ramesh & Richardson (2019) Table 1: rho0 = 2700 kg/m^3; Tillotson
/// A = B = 26.7 GPa, a = 0.5, b = 1.5, E0 = 487 MJ/kg; K_IC = 1.6 MPa m^0.5; crack-speed limit
/// 0.2 C_R (alpha_c = 5); gamma_c = 1; A_DP = 0.6, B_DP = 0.3 MPa; D_c = 0.125, D_max = 0.2;
/// P0 = 75 MPa, alpha0 = 1.25, P_c = 200 MPa; small flaws 5 um..1 mm, a = 3, eta = 2e12 m^-3,
/// 25 bins; large flaws 1 cm..80 m, eta = 250 m^-3, 25 bins.
/// Not in Table 1 (stated sources / assumptions):
///  * G0 = 22.7 GPa: Benz & Asphaug (1999) basalt, also in miluphcuda basalt configs.
///  * large-population exponent a = 3 (assumed equal to the small one).
///  * flaw friction mu = 0.2 and flaw angle phi = pi/2 - atan(1/mu)/2 = 0.884 rad: defaults of
///    the 2014 Uintah TongeRamesh model (most-unstable orientation for mu).
///  * MaxDamageInc = 1e-4 (Uintah default), bin bias -3 (rational spacing, PTR method 7; El Mir's
///    value is unknown, -3 resolves an a = 3 tail far better than uniform bins).
///  * rate-independent granular flow (GPTimeConst = 0), JLoc = 5 (a flag only).
///  * the large population applies to bodies of 1 m and more (min_specimen; issue 16): it stands
///    for joints and fractures 2 cm-160 m long that a laboratory specimen, cut from intact rock,
///    does not contain; 1 m = 100 x its smallest half-size (an assumption: the sources
///    consulted do not say which populations El Mir et al. used in their lab-scale runs).
///  * scale-aware flaw sampling with lambda_min = 1 and c_s = 4 (flaws.hpp; issue 16 study).
///  * flaw interaction (PTR DoFlawInteraction) is NOT implemented: the wing-crack driving stress is
///    the far-field principal stress (ARL-SR-0344 lists this as the cheaper switch-off option).
#include "mpm/tonge_ramesh/params.hpp"

#include <cmath>

#include "common/status.hpp"

namespace mpmfrag::tonge_ramesh {

Params basalt_el_mir() {
  Params p;
  p.populations = {FlawPopulation{5e-6, 1e-3, 3.0, 2e12, 25, -3.0},
                   FlawPopulation{1e-2, 80.0, 3.0, 250.0, 25, -3.0}};
  p.populations[1].min_specimen = 1.0;
  return p;
}

void Params::validate() const {
  auto bad = [](const std::string& k, const std::string& why) {
    throw common::InputError("", "tonge_ramesh." + k, why);
  };
  if (!(density > 0)) bad("density", "must be > 0");
  if (!(shear_modulus > 0)) bad("shear_modulus", "must be > 0");
  if (!(eos.A > 0)) bad("A", "must be > 0");
  if (!(KIc > 0)) bad("KIc", "must be > 0");
  if (!(growth_alpha >= 1)) bad("growth_alpha", "must be >= 1");
  if (!(critical_damage > 0 && critical_damage <= max_damage))
    bad("critical_damage", "must be in (0, max_damage]");
  if (!(max_damage > 0 && max_damage < 1)) bad("max_damage", "must be in (0,1)");
  if (!(pa_P0 > 0 && pa_Pc > pa_P0)) bad("pa_Pc", "need 0 < pa_P0 < pa_Pc");
  if (!(pa_alpha0 > 1)) bad("pa_alpha0", "must be > 1");
  if (!(max_damage_inc > 0)) bad("max_damage_inc", "must be > 0");
  if (!(block_count > 0)) bad("flaw_block_count", "must be > 0");
  if (!(block_size_factor >= 0)) bad("flaw_block_size_factor", "must be >= 0");
  if (!(specimen_size >= 0)) bad("specimen_size", "must be >= 0");
  for (const auto& f : populations) {
    if (!(f.s_min > 0 && f.s_max > f.s_min)) bad("flaw s_min/s_max", "need 0 < s_min < s_max");
    if (!(f.exponent > 0)) bad("flaw exponent", "must be > 0");
    if (!(f.density >= 0)) bad("flaw density", "must be >= 0");
    if (f.bins < 1) bad("flaw bins", "must be >= 1");
    if (f.bin_bias == 0) bad("flaw bin_bias", "must be nonzero");
    if (!(f.min_specimen >= 0 && f.max_specimen >= f.min_specimen))
      bad("flaw min_specimen/max_specimen", "need 0 <= min_specimen <= max_specimen");
  }
}

Derived::Derived(const Params& p) {
  K0 = p.eos.A;
  const double G = p.shear_modulus;
  nu0 = (3 * K0 - 2 * G) / (6 * K0 + 2 * G);
  E0 = 9 * K0 * G / (3 * K0 + G);
  const double Zn = 16 * (1 - nu0 * nu0) / (3 * E0);
  const double Zr = Zn / (1 - 0.5 * nu0);
  const double Zc = -Zn / 8;
  kK = K0 * (Zn + 4 * Zc);
  kG = G * (2.0 / 15.0) * (3 * Zr + 2 * Zn - 4 * Zc);
  cs = std::sqrt(G / p.density);
  cR = cs * (0.862 + 1.14 * nu0) / (1 + nu0);
  v_max = cR / p.growth_alpha;
  const double mu = p.flaw_friction;
  const double phi = p.flaw_angle >= 0 ? p.flaw_angle : 0.5 * M_PI - 0.5 * std::atan(1.0 / mu);
  sin_phi = std::sin(phi);
  cos_phi = std::cos(phi);
  sin2phi = std::sin(2 * phi);
  pa_kappa = (p.pa_Pc - p.pa_P0) / (2 * p.pa_P0 * (p.pa_alpha0 - 1));
}

}  // namespace mpmfrag::tonge_ramesh
