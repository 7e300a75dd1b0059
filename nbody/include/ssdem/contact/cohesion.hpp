/// @file cohesion.hpp
/// Contact part "cohesion": a cohesive tensile strength sigma_c acting over the contact area of
/// touching spheres, and between spheres and walls.
///   F_c = sigma_c A,  A = pi a^2,  a = beta Rbar  (the contact size of the rolling and twisting
///   parts, key contact.beta; Rbar = s_p s_n/(s_p + s_n), wall: s_p)
///   force on p: +F_c n (towards n / the wall) while the spheres overlap (x > 0); n gets -F_c n.
/// Stored (potential) energy -F_c x: continuous at first touch (x = 0), so with the damping part
/// off a cohesive contact conserves energy like the springs, except that the jump of the force
/// at x = 0 makes the leapfrog energy error at first touch and at separation first order in h
/// (0.7 % of the kinetic energy at 84 steps per oscillation period, 0.07 % at 840; measured in
/// test_nbody_cohesion).
/// Consequences (tested in test_nbody_cohesion): with the linear law, a contact at rest has the
/// equilibrium overlap x_eq = F_c / k_n; pulling with a steady force F separates the spheres iff
/// F > F_c (pull-off force = F_c); from rest at x_eq a relative speed v separates them iff
///   mu v^2 / 2 > F_c^2 / (2 k_n)   (the work of F_c - k_n x from x_eq to 0);
/// a sphere under a plate in gravity g hangs iff m g < F_c = sigma_c pi (beta s)^2.
/// Sources: the cohesive strength of rubble piles as an inter-grain stress over a contact area
/// follows Sánchez & Scheeres (2014, Meteorit. Planet. Sci. 49:788; van der Waals cohesion
/// between grains gives a bulk strength sigma ~ F_c / (grain cross-section)) and the SSDEM
/// cohesion of Zhang et al. (2018, ApJ 857:15), where a contact of size beta Rbar carries a
/// tensile force up to c pi (beta Rbar)^2 [R: the exact form in Zhang et al. 2018 was recalled,
/// not re-read]. The force-times-contact-area structure is that of the simplified JKR cohesion
/// of LIGGGHTS/Aspherix ("cohesion sjkr", [V] docs), there with the overlap-dependent
/// intersection area; the fixed area pi (beta Rbar)^2 is used here so that the pull-off force is
/// a material constant independent of k_n (deviation, chosen for that reason).
/// The friction limits of the tangential, rolling and twisting parts use |F_N| of the normal
/// phase, without F_c (cohesion adds no frictional strength; a conservative choice).
/// History: none. The k_n rule (dt_rule.hpp, scene setup) includes k_n >= F_c / x_max (pkdgrav
/// demparams' cohesion criterion, ssdem.md §1.7) so that cohesion cannot pull the overlap past
/// the target.
#pragma once
#include <cmath>

#include "ssdem/contact/part.hpp"

namespace ssdem {

inline constexpr unsigned kPartCohesion = 32u;

struct Cohesion : PartBase {
  static constexpr const char* name = "cohesion";
  static constexpr unsigned flag = kPartCohesion;
  static constexpr unsigned requires_parts = 0u;
  static constexpr PartSlot slot = PartSlot::additive;
  static constexpr const char* help =
      "cohesive strength sigma_c over the contact area pi (beta Rbar)^2, spheres and walls";
  struct Params {
    double sigma_c = 0.0;         ///< cohesive strength [Pa]
    bool cohesion_walls = true;   ///< also between spheres and walls
  };
  static void declare(common::Schema& s) {
    s.add_real("sigma", 0.0, "Pa", 0.0, 1e12, "cohesive strength sigma_c (force = sigma_c pi (beta Rbar)^2)");
    s.add_bool("walls", true, "cohesion also between spheres and walls");
  }
  template <class P>
  static void read(const common::Scene& s, const std::string& pre, P& p) {
    p.sigma_c = s.real(pre + "sigma");
    p.cohesion_walls = s.boolean(pre + "walls");
  }
  struct Coeffs {
    double coh_pre = 0.0, coh_wall_pre = 0.0;  ///< F_c / Rbar^2 (pairs, walls)
    template <class P>
    explicit Coeffs(const P& p) {
      if (!(p.parts & kPartCohesion)) return;
      coh_pre = p.sigma_c * M_PI * p.beta * p.beta;
      coh_wall_pre = p.cohesion_walls ? coh_pre : 0.0;
    }
  };
  /// Cohesive force of a contact of reduced radius Rbar.
  template <bool WALL, class C, class R>
  static R force(const C& c, const R& Rbar) {
    return (WALL ? c.coh_wall_pre : c.coh_pre) * Rbar * Rbar;
  }
  template <unsigned PARTS, bool WALL, class N, class C, class R, class H>
  static void tangent_phase(const C& c, PairCtx<R>& k, const H&) {
    k.F = k.F + force<WALL>(c, k.Rbar) * k.n;
  }
  template <class N, class C, class R, class H>
  static R energy(const C& c, const EnergyCtx<R>& e, const H&) {
    return -(e.wall ? c.coh_wall_pre : c.coh_pre) * e.Rbar * e.Rbar * e.x;
  }
};

}  // namespace ssdem
