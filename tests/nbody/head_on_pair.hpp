/// @file head_on_pair.hpp
/// The scene of the normal-impact tests (test_contact.cpp, test_energy_balance.cpp): two equal
/// spheres (radius 1 cm, 2500 kg/m^3) 0.4 radius apart, approaching head-on at 2 x 1 m/s, with
/// the linear normal law (k_n = 1e5 N/m) and, if `damping`, the dashpot of restitution e_n;
/// dt = t_c / steps_per_contact.
#pragma once
#include <cmath>

#include "ssdem/contact_params.hpp"
#include "ssdem/simulation.hpp"

namespace ssdem::test_scenes {

struct HeadOnPair {
  Spheres sp;
  SimConfig cfg;
  double tc = 0;    ///< analytic contact time [s]
  double s = 0.01;  ///< radius [m]
  double v = 1.0;   ///< approach speed of each sphere [m/s]
};

inline HeadOnPair head_on_pair(double en, double steps_per_contact, bool damping = true, bool extrapolated = true) {
  HeadOnPair h;
  const double s = h.s, rho = 2500, v = h.v;
  const double m = rho * 4.0 / 3.0 * M_PI * s * s * s;
  ContactParams p;
  p.parts = damping ? kPartDamping : 0u;
  p.kn = 1e5;
  p.en = en;
  h.tc = p.contact_time(0.5 * m);
  h.sp.push(0, Vec3(-s - 0.2 * s, 0, 0), Vec3(v, 0, 0), Vec3::Zero(), m, s);
  h.sp.push(1, Vec3(s + 0.2 * s, 0, 0), Vec3(-v, 0, 0), Vec3::Zero(), m, s);
  h.cfg.contacts = true;
  h.cfg.contact = p;
  h.cfg.dt = h.tc / steps_per_contact;
  h.cfg.min_steps_per_contact = 5;
  h.cfg.extrapolated_predictor = extrapolated;
  return h;
}

}  // namespace ssdem::test_scenes
