/// @file micromechanics.hpp
/// Wing-crack growth and damage of the Tonge–Ramesh model (Paliwal & Ramesh 2008, JMPS 56:896;
/// Tonge & Ramesh 2016 JMPS 86:117; ARL-SR-0344 Eqs. 10–12; PTR `calculateDamageGrowth`).
///
/// With principal stresses sigma_I >= sigma_II >= sigma_III (tension +), the 2-D wing-crack analysis
/// uses sigma_a = sigma_III (most compressive) and sigma_b = sigma_I. For a flaw of half-size s
/// whose normal makes the angle phi with the sigma_a axis and wing length l:
///   sigma_n = sigma_a cos^2 phi + sigma_b sin^2 phi,  tau_r = -(sigma_a - sigma_b) sin(2phi)/2,
///   F = max(2 s (tau_r + mu min(sigma_n, 0)), 0),
///   K_I = F/sqrt(pi (l + 0.27 s)) + sigma_b sqrt(pi (l + s sin phi)).
/// Growth (K_I >= K_IC):  l_dot = v_max ((K_I - K_IC)/(K_I - K_IC/2))^gamma_c, v_max = C_R/alpha_c,
/// C_R = c_s (0.862 + 1.14 nu0)/(1 + nu0); forward Euler, l capped at omega^(-1/3) - s, l >= 0.
/// Damage D = sum_k omega_k (s_k + l_k)^3, capped at D_max.
/// QUIRK (PTR keeps the friction term mu*sigma_n also when the flaw faces are in tension, which
/// then *adds* to the driving force): fixed by default (mu min(sigma_n,0)): open faces carry no
/// friction. Params::friction_in_tension = true reproduces PTR.
/// QUIRK (PTR feeds the Kirchhoff trial stress): the caller passes the Cauchy stress.
/// Deviation: no flaw-interaction ellipse (PTR DoFlawInteraction): far-field stress is used.
#pragma once
#include "mpm/tonge_ramesh/params.hpp"

namespace mpmfrag::tonge_ramesh {

/// Mode-I stress intensity at the wing tips of a flaw (s, l) under principal stresses
/// sigma_a (most compressive) and sigma_b (most tensile) [Pa m^0.5].
double stress_intensity(const Params& p, const Derived& d, double sa, double sb, double s, double l);

/// Wing growth speed for a given K_I [m/s] (0 below K_IC).
double growth_speed(const Params& p, const Derived& d, double KI);

/// Damage sum_k omega_k (s_k + l_k)^3 (or sum omega l^3), capped at D_max.
double damage_of(const Params& p, int n, const double* omega, const double* s, const double* l);

/// Advance all wing lengths l by dt under (sa, sb); returns the new (capped) damage.
/// Bins with omega = 0 are skipped.
double advance_cracks(const Params& p, const Derived& d, double sa, double sb, double dt, int n,
                      const double* omega, const double* s, double* l);

}  // namespace mpmfrag::tonge_ramesh
