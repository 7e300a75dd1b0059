/// @file micromechanics.cpp
/// Wing-crack K_I, growth law and damage sum (equations in micromechanics.hpp; PTR
/// `calculateDamageGrowth`, ARL-SR-0344 Eqs. 10–12, Paliwal & Ramesh 2008).
#include "mpm/tonge_ramesh/micromechanics.hpp"

#include <algorithm>
#include <cmath>

namespace mpmfrag::tonge_ramesh {

double stress_intensity(const Params& p, const Derived& d, double sa, double sb, double s,
                        double l) {
  const double c2 = d.cos_phi * d.cos_phi, s2 = d.sin_phi * d.sin_phi;
  const double sn = sa * c2 + sb * s2;
  const double tr = -0.5 * (sa - sb) * d.sin2phi;
  const double snf = p.friction_in_tension ? sn : std::min(sn, 0.0);
  const double F = std::max(2.0 * s * (tr + p.flaw_friction * snf), 0.0);
  return F / std::sqrt(M_PI * (l + 0.27 * s)) + sb * std::sqrt(M_PI * (l + s * d.sin_phi));
}

double growth_speed(const Params& p, const Derived& d, double KI) {
  if (!(KI > p.KIc)) return 0.0;
  const double r = (KI - p.KIc) / (KI - 0.5 * p.KIc);
  return d.v_max * (p.growth_exponent == 1.0 ? r : std::pow(r, p.growth_exponent));
}

double damage_of(const Params& p, int n, const double* omega, const double* s, const double* l) {
  double D = 0.0;
  for (int k = 0; k < n; ++k) {
    if (omega[k] <= 0.0) continue;
    const double a = p.include_initial_damage ? s[k] + l[k] : l[k];
    D += omega[k] * a * a * a;
  }
  return std::min(D, p.max_damage);
}

double advance_cracks(const Params& p, const Derived& d, double sa, double sb, double dt, int n,
                      const double* omega, const double* s, double* l) {
  // Hoisted per-call constants of K_I (same expression as stress_intensity()).
  const double c2 = d.cos_phi * d.cos_phi, s2 = d.sin_phi * d.sin_phi;
  const double sn = sa * c2 + sb * s2;
  const double tr = -0.5 * (sa - sb) * d.sin2phi;
  const double snf = p.friction_in_tension ? sn : std::min(sn, 0.0);
  const double shear_drive = std::max(tr + p.flaw_friction * snf, 0.0);
  double D = 0.0;
  for (int k = 0; k < n; ++k) {
    const double w = omega[k];
    if (w <= 0.0) continue;
    const double sk = s[k];
    double lk = l[k];
    const double lcap = std::max(1.0 / std::cbrt(w) - sk, 0.0);
    if (lk < lcap) {
      const double KI = 2.0 * sk * shear_drive / std::sqrt(M_PI * (lk + 0.27 * sk)) +
                        sb * std::sqrt(M_PI * (lk + sk * d.sin_phi));
      if (KI > p.KIc) lk = std::min(lk + dt * growth_speed(p, d, KI), lcap);
    } else {
      lk = lcap;
    }
    l[k] = lk;
    const double a = p.include_initial_damage ? sk + lk : lk;
    D += w * a * a * a;
  }
  return std::min(D, p.max_damage);
}

}  // namespace mpmfrag::tonge_ramesh
