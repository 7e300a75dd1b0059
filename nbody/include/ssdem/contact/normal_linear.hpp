/// @file normal_linear.hpp
/// Contact part "normal": the linear (Hooke) normal spring, the default normal law.
///   F_N = -k_n x n                                   (Schwartz, Richardson & Michel 2012 eq. 3)
/// stiffness seen by the other parts: k_n (normal), k_t = (k_t/k_n) k_n (tangential, key
/// contact.tangential.kt_over_kn, default 2/7: Schwartz+2012 §2.3, pkdgrav dKt = -1);
/// dashpots (damping part): C_n = cn_pre sqrt(mu), C_t = ct_pre sqrt(mu) with
/// cn_pre = 2|ln e_n| sqrt(k_n / (pi^2 + ln^2 e_n)) (S12 eq. 15), ct_pre the same with k_t, e_t;
/// stored energy k_n x^2 / 2.
#pragma once
#include <cmath>

#include "ssdem/contact/part.hpp"

namespace ssdem {

struct LinearNormal : PartBase {
  static constexpr const char* name = "normal";
  static constexpr unsigned flag = 0u;  // the default normal law
  static constexpr unsigned requires_parts = 0u;
  static constexpr PartSlot slot = PartSlot::normal;
  static constexpr const char* help = "linear normal spring F = -k_n x n (Schwartz+2012 eq. 3)";
  struct Params {
    double kn = 0.0;  ///< normal spring constant [N/m]
  };
  static void declare(common::Schema& s) {
    s.add_real("kn", 0.0, "N/m", 0.0, 1e30,
               "normal spring constant k_n; 0 = from the k_n rule (contact.vmax, "
               "contact.overlap_fraction; dt_rule.hpp)");
  }
  template <class P>
  static void read(const common::Scene& s, const std::string& pre, P& p) {
    p.kn = s.real(pre + "kn");
  }
  struct Coeffs {
    double kn, kt;
    template <class P>
    explicit Coeffs(const P& p) : kn(p.kn), kt(p.kt()) {}
  };
  // --- the normal-law interface used by the other parts ---
  template <class C, class R>
  static void stiffness(const C& c, const R& /*x*/, const R& /*Rbar*/, R& kn, R& kt) {
    kn = splat<R>(c.kn);
    kt = splat<R>(c.kt);
  }
  template <class C, class R>
  static R cn(const C& c, const PairCtx<R>& k) { return c.cn_pre * lsqrt(k.mu); }
  template <class C, class R>
  static R ct(const C& c, const PairCtx<R>& k) { return c.ct_pre * lsqrt(k.mu); }
  /// Edge impulses (contact_law.hpp, "Contact edges"): with x = w t after the edge,
  /// spring  k_n w [(sig + h/2)^2 / 2 - sig h] / h = k_n w (sig - h/2)^2 / (2h)  (repulsive),
  /// dashpot C_n [(sig + h/2) - h] / h = C_n (sig/h - 1/2)                       (times u_n).
  template <class C, class R>
  static R edge_spring(const C& c, const PairCtx<R>& k, const R& w, const R& sig) {
    const R e = sig - 0.5 * k.h;
    return c.kn * w * e * e / (2.0 * k.h);
  }
  template <class C, class R>
  static R edge_dashpot(const C& c, const PairCtx<R>& k, const R& /*w*/, const R& sig) {
    return cn(c, k) * (sig / k.h - 0.5);
  }
  // --- hooks ---
  template <unsigned PARTS, bool WALL, class N, class C, class R, class H>
  static void normal_phase(const C& c, PairCtx<R>& k, const H&) {
    k.kn = splat<R>(c.kn);
    k.kt = splat<R>(c.kt);
    k.FN = (-c.kn * k.x) * k.n;
  }
  template <class N, class C, class R, class H>
  static R energy(const C& c, const EnergyCtx<R>& e, const H&) { return 0.5 * c.kn * e.x * e.x; }
};

}  // namespace ssdem
