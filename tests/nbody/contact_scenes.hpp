/// @file contact_scenes.hpp
/// Scenes shared by the contact tests (test_contact.cpp, test_energy_balance.cpp):
/// head_on_pair: two equal spheres (radius 1 cm, 2500 kg/m^3) 0.4 radius apart, approaching
/// head-on at 2 x 1 m/s, with the linear normal law (k_n = 1e5 N/m) and, if `damping`, the dashpot
/// of restitution e_n; dt = t_c / steps_per_contact.
/// gross_sliding: Chung & Ooi (2011) test 4 geometry: an aluminium sphere (radius 5 cm, 2700
/// kg/m^3) hitting a floor at 3.9 m/s and 60 degrees from the normal, undamped linear normal law
/// (k_n = 1e9 N/m) with the tangential spring and mu_s = 0.092, so it slides throughout contact.
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

struct GrossSliding {
  Spheres sp;
  SimConfig cfg;
  double vn = 0, vt = 0;  ///< normal and tangential impact speed [m/s]
  double s = 0.05, m = 0;  ///< radius [m], mass [kg]
};

inline GrossSliding gross_sliding(double steps_per_contact, SlipRule rule = SlipRule::coulomb) {
  GrossSliding g;
  ContactParams p;
  p.parts = kPartTangential;
  p.kn = 1e9;  // overlap ~0.15 % of R, so the lever arm l_p = R - x is R to that accuracy
  p.mu_s = 0.092;
  p.slip = rule;
  g.vn = 3.9 * std::cos(60 * M_PI / 180);
  g.vt = 3.9 * std::sin(60 * M_PI / 180);
  g.m = 2700 * 4.0 / 3.0 * M_PI * g.s * g.s * g.s;
  g.sp.push(0, Vec3(0, 0, g.s * 1.01), Vec3(g.vt, 0, -g.vn), Vec3::Zero(), g.m, g.s);
  g.cfg.contacts = true;
  g.cfg.contact = p;
  g.cfg.walls.push_back(Plane{Vec3::Zero(), Vec3::UnitZ()});
  g.cfg.dt = p.contact_time(g.m) / steps_per_contact;
  return g;
}

}  // namespace ssdem::test_scenes
