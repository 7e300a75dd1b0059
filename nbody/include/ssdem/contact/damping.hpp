/// @file damping.hpp
/// Contact part "damping": the normal (and, with the tangential part, tangential) dashpot.
///   F_N += C_n u_n,  u_n = (u.n) n                                (Schwartz+2012 eqs 3, 13)
/// The coefficients come from the normal law in use (N::cn, N::ct):
///   linear law: C_n = 2|ln e_n| sqrt(k_n mu / (pi^2 + ln^2 e_n))   (S12 eqs 15-16), C_t the same
///               with k_t and e_t; the contact then ends with restitution e_n exactly;
///   Hertz law:  C_n = alpha(e_n) sqrt(mu K sqrt(x)) (Tsuji, Tanaka & Ishida 1992, Powder
///               Technol. 71:239, eq. for eta_n), see normal_hertz.hpp.
/// The dashpot may go tensile at the end of a contact (no clamp), as in pkdgrav.
/// Stores no history and no energy (it only dissipates): C_n (u.n)^2 h over a step of length h
/// (the power the dashpot takes from the relative motion, with the velocities it acts on).
#pragma once
#include "ssdem/contact/part.hpp"

namespace ssdem {

inline constexpr unsigned kPartDamping = 1u;

struct Damping : PartBase {
  static constexpr const char* name = "damping";
  static constexpr unsigned flag = kPartDamping;
  static constexpr unsigned requires_parts = 0u;
  static constexpr PartSlot slot = PartSlot::additive;
  static constexpr const char* help = "normal dashpot from the restitution coefficient e_n (Schwartz+2012 eq. 15)";
  struct Params {
    double en = 1.0;  ///< normal restitution coefficient
  };
  static void declare(common::Schema& s) {
    s.add_real("en", 0.55, "1", 0.0, 1.0, "normal coefficient of restitution e_n", true);
  }
  template <class P>
  static void read(const common::Scene& s, const std::string& pre, P& p) {
    p.en = s.real(pre + "en");
  }
  struct Coeffs {
    double cn_pre;  ///< linear law: C_n / sqrt(mu)
    template <class P>
    explicit Coeffs(const P& p) : cn_pre(p.cn_pre()) {}
  };
  template <unsigned PARTS, bool WALL, class N, class C, class R, class H>
  static void normal_phase(const C& c, PairCtx<R>& k, const H&) {
    k.cn = N::cn(c, k);
    k.FN = k.FN + (k.cn * k.un_s) * k.n;
    k.diss += k.cn * k.un_s * k.un_s * k.h;
  }
};

}  // namespace ssdem
