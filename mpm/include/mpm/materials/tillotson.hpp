/// @file tillotson.hpp
/// Tillotson equation of state (Tillotson 1962, GA-3216; form of Melosh 1989 "Impact Cratering"
/// §3 and Benz & Asphaug 1999, Icarus 142:5, with their basalt constants), as in
/// shared/reference/validation-data.md §2.2:
///
///   eta = rho/rho0, mu = eta - 1, nu = 1/eta - 1, w = e/(E0 eta^2) + 1
///   compressed or cold (rho >= rho0 or e <= E_iv):
///       P_c = (a + b/w) rho e + A mu + B mu^2
///   expanded hot (rho < rho0 and e >= E_cv):
///       P_e = a rho e + [ b rho e / w + A mu exp(-beta nu) ] exp(-alpha nu^2)
///   hybrid (rho < rho0 and E_iv < e < E_cv):
///       P = [ (e - E_iv) P_e + (E_cv - e) P_c ] / (E_cv - E_iv)
///
/// Sound speed: c^2 = dP/drho|_e + (P/rho^2) dP/de|_rho, with the analytic partial derivatives
/// of each branch (dP_c/de = rho (a + b/w^2), dP_e/de = a rho + b rho exp(-alpha nu^2)/w^2).
/// Deviations (documented): e is clamped at >= 0 inside the EOS (the Tillotson form is singular
/// for e <= -E0 eta^2 and negative e only arises from round-off of tensile work); c^2 is floored
/// at (c_min_fraction * c0)^2 with c0 = sqrt(A/rho0), because c^2 < 0 in strong tension on the
/// cold branch; an optional pressure floor (`pressure_min`, default none) models tensile cut-off.
/// For rho -> 0 (eta < 1e-12) P = 0 and c = c_min.
#pragma once
#include <cmath>
#include <limits>

namespace mpmfrag {

/// Tillotson constants (SI). Defaults: basalt, Benz & Asphaug 1999.
struct TillotsonParams {
  double rho0 = 2700.0;  ///< kg/m^3
  double A = 26.7e9;     ///< Pa
  double B = 26.7e9;     ///< Pa
  double a = 0.5, b = 1.5, alpha = 5.0, beta = 5.0;
  double E0 = 4.87e8;    ///< J/kg
  double Eiv = 4.72e6;   ///< J/kg
  double Ecv = 1.82e7;   ///< J/kg
  double pressure_min = -std::numeric_limits<double>::infinity();  ///< Pa, tensile floor
  double c_min_fraction = 0.1;  ///< floor of c as a fraction of c0 = sqrt(A/rho0)
};

/// Which branch of the EOS a state falls in.
enum class TillotsonBranch { compressed, hybrid, expanded };

/// Pressure P(rho, e) [Pa] and, optionally, the squared sound speed [m^2/s^2].
struct TillotsonState {
  double pressure = 0.0;
  double c2 = 0.0;  ///< sound speed squared (after the floor)
  TillotsonBranch branch = TillotsonBranch::compressed;
};

/// Evaluate the EOS at density rho [kg/m^3] and specific internal energy e [J/kg].
/// Always finite for finite inputs.
TillotsonState tillotson_eos(const TillotsonParams& p, double rho, double e);

/// Pressure only.
inline double tillotson_pressure(const TillotsonParams& p, double rho, double e) {
  return tillotson_eos(p, rho, e).pressure;
}

}  // namespace mpmfrag
