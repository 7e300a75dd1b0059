/// @file twisting.hpp
/// Contact part "twisting": spring-dashpot-slider twisting resistance (Zhang et al. 2017, Icarus
/// 294:98; pkdgrav DoDEM; ssdem.md §1.4b).
///   theta_q += (dw.n)(half step) h;  M_tw = (k_q theta_q + C_q dw.n) n,
///   k_q = 2 k_t a^2, C_q = 2 C_t a^2, |k_q theta_q| <= mu_t mu_s a |F_N| (note the mu_s, as in
///   pkdgrav); beyond it M_tw = the limit, no dashpot, increment undone.
///   Torque on p: +M_tw, on n: -M_tw.  Needs the tangential part (k_t, C_t, mu_s).
/// History: theta_q [rad] (scalar, symmetric in the pair order). Energy: k_q theta_q^2 / 2.
/// Dissipated over a step: sticking, C_q (dw.n)^2 h; slipping, M_tw (dw.n)(half step) h.
#pragma once
#include <array>
#include <cmath>

#include "ssdem/contact/damping.hpp"
#include "ssdem/contact/part.hpp"
#include "ssdem/contact/tangential.hpp"

namespace ssdem {

inline constexpr unsigned kPartTwisting = 8u;

struct Twisting : PartBase {
  static constexpr const char* name = "twisting";
  static constexpr unsigned flag = kPartTwisting;
  static constexpr unsigned requires_parts = kPartTangential;
  static constexpr PartSlot slot = PartSlot::additive;
  static constexpr const char* help =
      "twisting spring-dashpot-slider, k_q = 2 k_t a^2, limit mu_t mu_s a |F_N| (Zhang+2017)";
  static constexpr std::array<HistoryField, 1> history{HistoryField{"theta_q", "rad", 1, false, false}};
  struct Params {
    double mu_t = 0.0;  ///< twisting friction coefficient
  };
  static void declare(common::Schema& s) {
    s.add_real("mu_t", 1.3, "1", 0.0, 100.0, "twisting friction coefficient mu_t");
  }
  template <class P>
  static void read(const common::Scene& s, const std::string& pre, P& p) {
    p.mu_t = s.real(pre + "mu_t");
  }
  struct Coeffs {
    double mu_t;
    template <class P>
    explicit Coeffs(const P& p) : mu_t(p.mu_t) {}
  };
  template <unsigned PARTS, bool WALL, class N, class C, class R, class H>
  static void tangent_phase(const C& c, PairCtx<R>& k, const H& h) {
    const V3<R>& n = k.n;
    const R a = c.beta * k.Rbar;
    V3<R> dw, dwh;
    relative_spins<WALL>(k, dw, dwh);
    const R dwn = dw.dot(n), dwhn = dwh.dot(n);
    R& q = h.scal(0);
    q += dwhn * k.h;
    const R kq = 2.0 * k.kt * a * a;
    const R crit = c.mu_t * c.mu_s * a * k.FNmag;
    R Mq = kq * q;
    const auto slip = labs(Mq) > crit;
    if constexpr ((PARTS & kPartDamping) != 0u) {  // sticking: the dashpot
      const R Md = Mq + 2.0 * k.ct * a * a * dwn;
      k.diss = select(slip, k.diss, k.diss + 2.0 * k.ct * a * a * dwn * dwn * k.h);
      Mq = select(slip, Mq, Md);
    }
    if (any(slip)) {  // slipping: the limit (sign of the spring), this step's increment undone
      const R Ms = select(Mq < 0.0, -crit, crit);
      q = select(slip, q - dwhn * k.h, q);
      // the spring keeps its energy: all the work is dissipated
      k.diss = select(slip, k.diss + Ms * dwhn * k.h, k.diss);
      Mq = select(slip, Ms, Mq);
    }
    k.Tp = k.Tp + Mq * n;
    if constexpr (!WALL) k.Tn = k.Tn - Mq * n;
  }
  template <class N, class C, class R, class H>
  static R energy(const C& c, const EnergyCtx<R>& e, const H& h) {
    R kn, kt;
    N::stiffness(c, e.x, e.Rbar, kn, kt);
    const R a = c.beta * e.Rbar;
    const R q = h.scal(0);
    return 0.5 * 2.0 * kt * a * a * q * q;
  }
};

}  // namespace ssdem
