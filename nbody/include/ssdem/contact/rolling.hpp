/// @file rolling.hpp
/// Contact part "rolling": spring-dashpot-slider rolling resistance (Zhang et al. 2017, Icarus
/// 294:98, after Jiang, Shen & Wang 2015; pkdgrav DEM_ROTATION_DASHPOT; ssdem.md §1.4b).
///   a = beta Rbar (key contact.beta), dw = w_n - w_p
///   v_roll = dw - (dw.n) n + ((l_n - l_p)/(2 l_p l_n)) (n x u)   (wall: correction 1/(2 l_p))
///   theta_r transported with the contact frame, then theta_r += v_roll(half step) h
///   M_roll = k_r theta_r + C_r v_roll,  k_r = k_n a^2, C_r = C_n a^2
///   |k_r theta_r| <= mu_r a |F_N|; beyond it M_roll = the limit along theta_r, no dashpot, and
///   this step's increment is undone.   Torque on p: +M_roll, on n: -M_roll.
/// k_n and C_n are those of the normal law (Hertz: the tangent stiffness 2 E* sqrt(R x)).
/// History: theta_r [rad] (transported, flips). Energy: k_r |theta_r|^2 / 2. Dissipated over a
/// step: rolling, the dashpot's C_r |v_roll|^2 h; slipping, M_roll . v_roll,half h (the spring is
/// left as it was, so the work done on the element is all lost).
#pragma once
#include <array>
#include <cmath>

#include "ssdem/contact/damping.hpp"
#include "ssdem/contact/part.hpp"

namespace ssdem {

inline constexpr unsigned kPartRolling = 4u;

struct Rolling : PartBase {
  static constexpr const char* name = "rolling";
  static constexpr unsigned flag = kPartRolling;
  static constexpr unsigned requires_parts = 0u;
  static constexpr PartSlot slot = PartSlot::additive;
  static constexpr const char* help =
      "rolling spring-dashpot-slider, k_r = k_n a^2, limit mu_r a |F_N| (Zhang+2017)";
  static constexpr std::array<HistoryField, 1> history{HistoryField{"theta_r", "rad", 3, true, true}};
  struct Params {
    double mu_r = 0.0;  ///< rolling friction coefficient
  };
  static void declare(common::Schema& s) {
    s.add_real("mu_r", 1.05, "1", 0.0, 100.0, "rolling friction coefficient mu_r");
  }
  template <class P>
  static void read(const common::Scene& s, const std::string& pre, P& p) {
    p.mu_r = s.real(pre + "mu_r");
  }
  struct Coeffs {
    double mu_r;
    template <class P>
    explicit Coeffs(const P& p) : mu_r(p.mu_r) {}
  };
  template <unsigned PARTS, bool WALL, class N, class C, class R, class H>
  static void tangent_phase(const C& c, PairCtx<R>& k, const H& h) {
    const V3<R>& n = k.n;
    const R a = c.beta * k.Rbar;
    V3<R> dw, dwh;
    relative_spins<WALL>(k, dw, dwh);
    const R dwn = dw.dot(n), dwhn = dwh.dot(n);
    R corr;
    if constexpr (WALL)
      corr = 0.5 / k.lp;
    else
      corr = (k.ln - k.lp) / (2.0 * k.lp * k.ln);
    const V3<R> vroll = dw - dwn * n + corr * n.cross(k.u);
    const V3<R> vroll_h = dwh - dwhn * n + corr * n.cross(k.uh);
    V3<R>& th = h.vec(0);
    th = th + vroll_h * k.h;
    const R kr = k.kn * a * a;
    const V3<R> spring = kr * th;
    const R crit = c.mu_r * a * k.FNmag;
    const R sp2 = spring.squaredNorm();
    const auto slip = sp2 > crit * crit;
    V3<R> M = spring;  // rolling
    if constexpr ((PARTS & kPartDamping) != 0u) {
      M = M + (k.cn * a * a) * vroll;
      k.diss = select(slip, k.diss, k.diss + k.cn * a * a * vroll.squaredNorm() * k.h);
    }
    if (any(slip)) {  // slipping: the limit along the spring, this step's increment undone
      const V3<R> Ms = spring * (crit / lsqrt(sp2));
      th = select(slip, th - vroll_h * k.h, th);
      // the spring keeps its energy: all the work is dissipated
      k.diss = select(slip, k.diss + Ms.dot(vroll_h) * k.h, k.diss);
      M = select(slip, Ms, M);
    }
    k.Tp = k.Tp + M;
    if constexpr (!WALL) k.Tn = k.Tn - M;
  }
  template <class N, class C, class R, class H>
  static R energy(const C& c, const EnergyCtx<R>& e, const H& h) {
    R kn, kt;
    N::stiffness(c, e.x, e.Rbar, kn, kt);
    const R a = c.beta * e.Rbar;
    return 0.5 * kn * a * a * h.vec(0).squaredNorm();
  }
};

}  // namespace ssdem
