/// @file dt_rule.cpp
/// k_n and dt selection; equations in dt_rule.hpp.
#include "ssdem/dt_rule.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <vector>

#include "common/status.hpp"

namespace ssdem {

DtAdvice choose_kn_dt(double m, double s, double vmax, double en, double overlap_frac,
                      double steps_per_contact, double rho_phi_ag_H) {
  if (!(m > 0 && s > 0 && vmax >= 0 && overlap_frac > 0 && steps_per_contact > 0))
    throw common::InputError("choose_kn_dt: mass, radius, overlap fraction and steps must be > 0");
  DtAdvice a;
  const double xmax = overlap_frac * s;
  a.kn_kinetic = m * vmax * vmax / (xmax * xmax);
  a.kn_static = rho_phi_ag_H * s / xmax;
  a.kn = std::max(a.kn_kinetic, a.kn_static);
  if (!(a.kn > 0)) throw common::InputError("choose_kn_dt: k_n would be zero (vmax = 0 and no static load)");
  ContactParams p;
  p.kn = a.kn;
  p.en = en;
  p.parts = en < 1.0 ? kPartDamping : 0u;
  a.tau = p.contact_time(0.5 * m);
  a.dt = a.tau / steps_per_contact;
  return a;
}

double shortest_contact_time(const ContactParams& p, const SphereSummary& s, bool walls) {
  if (s.n == 0) return INFINITY;
  // Hertz: the time falls with the reduced radius; take the largest (conservative)
  double tau = std::isfinite(s.m2) ? p.contact_time(s.m1 * s.m2 / (s.m1 + s.m2), 0.5 * s.smax) : INFINITY;
  if (walls) tau = std::min(tau, p.contact_time(s.m1, s.smax));
  return tau;
}

double shortest_contact_time(const ContactParams& p, const Spheres& sp, bool walls) {
  return shortest_contact_time(p, summarise(sp), walls);
}

double median_contact_time(const ContactParams& p, const SphereSummary& s) {
  if (s.n < 2) return INFINITY;
  return p.contact_time(0.5 * s.m_median, 0.5 * s.smax);
}

double median_contact_time(const ContactParams& p, const Spheres& sp) { return median_contact_time(p, summarise(sp)); }

int anchored_levels(double tau_ref, double tau_min) {
  if (!(tau_ref > tau_min) || !std::isfinite(tau_ref)) return -1;
  int m = 0;
  while (std::ldexp(tau_min, m) < tau_ref) ++m;  // smallest m with tau_ref / 2^m <= tau_min
  return m;
}

void check_dt(const ContactParams& p, const Spheres& sp, bool walls, double dt, double min_steps) {
  check_dt(p, summarise(sp), walls, dt, min_steps);
}

void check_dt(const ContactParams& p, const SphereSummary& s, bool walls, double dt, double min_steps) {
  const double tau = shortest_contact_time(p, s, walls);
  if (!std::isfinite(tau)) return;
  if (dt * min_steps > tau * (1.0 + 1e-9)) {  // a dt of exactly tau/min_steps is accepted
    std::ostringstream os;
    os << "time.dt = " << dt << " s resolves the shortest contact (tau = " << tau << " s for ";
    if (p.parts & kPartHertz)
      os << "contact.hertz.E = " << p.E << " Pa at contact.vmax = " << p.vmax << " m/s";
    else
      os << "k_n = " << p.kn << " N/m";
    os << ") with only " << tau / dt
       << " steps; at least " << min_steps << " are required (time.min_steps_per_contact). "
       << "Use dt <= " << tau / min_steps << " s or a softer k_n.";
    throw common::InputError(os.str());
  }
}

}  // namespace ssdem
