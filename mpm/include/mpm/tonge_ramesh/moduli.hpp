/// @file moduli.hpp
/// Damaged elastic moduli and the cold Tillotson matrix pressure used by the Tonge–Ramesh model.
///
/// Damaged moduli (Tonge & Ramesh 2016; ARL-SR-0344 Eqs. 3, 6; PTR calculate*Prefactor):
///   nu0 = (3K0-2G0)/(6K0+2G0), E0 = 9K0G0/(3K0+G0), Z_n = 16(1-nu0^2)/(3E0),
///   Z_r = Z_n/(1-nu0/2), Z_c = -Z_n/8,
///   K(D) = [1/K0 + D(Z_n+4Z_c)]^-1,  G(D) = [1/G0 + (2D/15)(3Z_r+2Z_n-4Z_c)]^-1,
/// i.e. K/K0 = 1/(1+kK D), kK = 8(1-nu0^2)/(9(1-2nu0)); G/G0 = 1/(1+kG D),
/// kG = 8(1-nu0)(22-5nu0)/(45(2-nu0)).
/// Deviation from PTR: K0 is the reference bulk modulus (Tillotson A) rather than the EOS tangent
/// at the current density; the two differ by < ~20 % below 10 % compression and the constant
/// choice keeps K(D)/K0 independent of the state, which makes the pressure-matching Newton
/// iterations of the granular return exact-derivative and cheap.
///
/// Cold/compressed Tillotson branch (Tillotson 1962, GA-3216; Benz & Asphaug 1999, Icarus
/// 142:5, Eq. A1 region rho>=rho0 or e<=E_iv, used also for cold expanded states as in El Mir 2019):
///   eta = rho_s/rho0, mu = eta-1, w = e/(E0 eta^2)+1,
///   p_T = (a + b/w) rho_s e + A mu + B mu^2,
///   K_T = eta dp_T/deta = (a+b/w) rho_s e + 2 b rho_s e^2/(E0 eta^2 w^2) + eta(A + 2 B mu).
/// The full Tillotson EOS of the solver is mpm/materials/tillotson.hpp; the model keeps this inline
/// cold branch because its return mappings need the exact tangent at fixed e and the point-wise
/// model must build without the solver. The ctest SolverDamage.LocalColdTillotsonMatchesSolverEos
/// checks that both agree (1e-9) wherever this branch applies; the hot/hybrid branches are not
/// used by the brittle model (a documented limitation for shock-heated, expanded states).
#pragma once
#include "mpm/tonge_ramesh/params.hpp"

namespace mpmfrag::tonge_ramesh {

/// Damaged bulk modulus K(D).
inline double damaged_bulk(const Derived& d, double D) { return d.K0 / (1.0 + d.kK * D); }
/// Damaged shear modulus G(D).
inline double damaged_shear(const Params& p, const Derived& d, double D) {
  return p.shear_modulus / (1.0 + d.kG * D);
}

/// Cold Tillotson pressure [Pa] (compression positive) at eta = rho_s/rho0 and specific energy e.
inline double tillotson_pressure(const TillotsonCold& t, double rho0, double eta, double e) {
  const double mu = eta - 1.0;
  const double w = e / (t.E0 * eta * eta) + 1.0;
  return (t.a + t.b / w) * rho0 * eta * e + t.A * mu + t.B * mu * mu;
}

/// Isothermal-in-e tangent bulk modulus eta dp/deta [Pa] of the cold Tillotson branch.
inline double tillotson_tangent(const TillotsonCold& t, double rho0, double eta, double e) {
  const double mu = eta - 1.0;
  const double w = e / (t.E0 * eta * eta) + 1.0;
  const double rs = rho0 * eta;
  return (t.a + t.b / w) * rs * e + 2.0 * t.b * rs * e * e / (t.E0 * eta * eta * w * w) +
         eta * (t.A + 2.0 * t.B * mu);
}

/// Kirchhoff mean stress p_K = J_EL * (-p_T(1/J_EL, e)) * ratio (tension positive), ratio = K(D)/K0.
inline double kirchhoff_mean(const Params& p, double J_el, double e, double ratio) {
  return -J_el * tillotson_pressure(p.eos, p.density, 1.0 / J_el, e) * ratio;
}
/// d p_K / d ln J_EL = ratio * J_EL * (K_T - p_T).
inline double kirchhoff_mean_slope(const Params& p, double J_el, double e, double ratio) {
  const double eta = 1.0 / J_el;
  return ratio * J_el *
         (tillotson_tangent(p.eos, p.density, eta, e) - tillotson_pressure(p.eos, p.density, eta, e));
}

}  // namespace mpmfrag::tonge_ramesh
