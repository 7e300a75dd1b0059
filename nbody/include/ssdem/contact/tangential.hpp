/// @file tangential.hpp
/// Contact part "tangential": static-friction spring with history and a Coulomb cap.
///   S transported with the contact frame (kernel, contact_law.hpp), then S += u_t(half step) h
///   F_T = k_t S + C_t u_t,  |F_T| <= mu_s |F_N|                   (Schwartz+2012 eqs 6-7, 14, 17-19)
///   slip (SlipRule): coulomb = rescale F_T to mu_s |F_N| and set S so that k_t S + C_t u_t = F_T;
///   pkdgrav = zero S and apply min(mu_s |F_N|, C_t |u_t|) along u_t (pkdgrav DoDEM).
///   torque on p: l_p n x F_T, on n: l_n n x F_T                   (S12 eqs 22-23)
/// k_t and C_t come from the normal law (linear: (k_t/k_n) k_n; Hertz: Mindlin 8 G* sqrt(R x)).
/// History: S [m] (tangent vector, transported, flips with the pair order).
/// Energy: k_t |S|^2 / 2. Dissipated over a step: sticking, the dashpot's C_t |u_t|^2 h; sliding,
/// the work the relative motion did on the element minus the change of its stored energy,
/// F_T . u_t,half h - k_t (|S_new|^2 - |S_old|^2) / 2 (the spring's energy that the cap removed
/// plus the slider's and dashpot's work).
#pragma once
#include <algorithm>
#include <array>
#include <cmath>

#include "ssdem/contact/damping.hpp"
#include "ssdem/contact/part.hpp"

namespace ssdem {

inline constexpr unsigned kPartTangential = 2u;

/// How a sliding contact is capped.
enum class SlipRule {
  coulomb,  ///< rescale F_T to mu_s |F_N| and set S so that k_t S + C_t u_t = F_T (strict Coulomb)
  pkdgrav   ///< pkdgrav DoDEM: zero S and apply min(mu_s |F_N|, C_t |u_t|) along u_t
};
/// Scene spellings of SlipRule (key contact.tangential.slip).
inline constexpr std::array kSlipRules{common::Choice{"coulomb", SlipRule::coulomb},
                                       common::Choice{"pkdgrav", SlipRule::pkdgrav}};

struct Tangential : PartBase {
  static constexpr const char* name = "tangential";
  static constexpr unsigned flag = kPartTangential;
  static constexpr unsigned requires_parts = 0u;
  static constexpr PartSlot slot = PartSlot::additive;
  static constexpr const char* help =
      "tangential spring with history and Coulomb cap mu_s (Schwartz+2012 eqs 6-7, 17-19)";
  static constexpr std::array<HistoryField, 1> history{HistoryField{"S", "m", 3, true, true}};
  struct Params {
    double kt_over_kn = 2.0 / 7.0;
    double et = 1.0;    ///< tangential "restitution" setting C_t
    double mu_s = 0.0;  ///< static friction coefficient
    SlipRule slip = SlipRule::coulomb;
  };
  static void declare(common::Schema& s) {
    s.add_real("kt_over_kn", 2.0 / 7.0, "1", 0.0, 10.0, "k_t / k_n (linear normal law)", true);
    s.add_real("et", 0.55, "1", 0.0, 1.0,
               "tangential damping setting e_t (C_t from e_t with k_t; used only with the "
               "damping part)",
               true);
    s.add_real("mu_s", 1.0, "1", 0.0, 100.0, "static friction coefficient mu_s");
    s.add_choice("slip", SlipRule::coulomb, kSlipRules,
                 "slip rule: coulomb (rescale to mu_s|F_N|) or pkdgrav (zero S, "
                 "min(mu_s|F_N|, C_t|u_t|))");
  }
  template <class P>
  static void read(const common::Scene& s, const std::string& pre, P& p) {
    p.kt_over_kn = s.real(pre + "kt_over_kn");
    p.et = s.real(pre + "et");
    p.mu_s = s.real(pre + "mu_s");
    p.slip = s.choice(pre + "slip", kSlipRules);
  }
  struct Coeffs {
    double ct_pre, mu_s;
    SlipRule slip;
    template <class P>
    explicit Coeffs(const P& p) : ct_pre(p.ct_pre()), mu_s(p.mu_s), slip(p.slip) {}
  };
  template <unsigned PARTS, bool WALL, class N, class C, class R, class H>
  static void tangent_phase(const C& c, PairCtx<R>& k, const H& h) {
    const V3<R>& n = k.n;
    const V3<R> ut = k.u - k.un_s * n;
    V3<R>& S = h.vec(0);
    const R s_old2 = S.squaredNorm();
    const V3<R> uth = k.uh - k.uh.dot(n) * n;
    S = S + uth * k.h;
    R ct = splat<R>(0.0);
    if constexpr ((PARTS & kPartDamping) != 0u) ct = N::ct(c, k);
    k.ct = ct;
    V3<R> FT = k.kt * S + ct * ut;
    const R Fmax = c.mu_s * k.FNmag;
    const R ft2 = FT.squaredNorm();
    const auto slip = ft2 > Fmax * Fmax;
    R dd = ct * ut.squaredNorm() * k.h;  // sticking: the dashpot
    if (any(slip)) {
      V3<R> FTs, Ss;
      if (c.slip == SlipRule::coulomb) {
        FTs = FT * (Fmax / lsqrt(ft2));
        Ss = (FTs - ct * ut) / k.kt;
      } else {
        Ss = V3<R>::zero();
        const R utm = lsqrt(ut.squaredNorm());
        FTs = select(utm > 0.0, (lmin(Fmax, ct * utm) / utm) * ut, V3<R>::zero());
      }
      const R ds = FTs.dot(uth) * k.h - 0.5 * k.kt * (Ss.squaredNorm() - s_old2);
      FT = select(slip, FTs, FT);
      S = select(slip, Ss, S);
      dd = select(slip, ds, dd);
    }
    k.diss += dd;
    k.F = k.F + FT;
    const V3<R> nxF = n.cross(FT);
    k.Tp = k.lp * nxF;
    if constexpr (!WALL) k.Tn = k.ln * nxF;
  }
  template <class N, class C, class R, class H>
  static R energy(const C& c, const EnergyCtx<R>& e, const H& h) {
    R kn, kt;
    N::stiffness(c, e.x, e.Rbar, kn, kt);
    return 0.5 * kt * h.vec(0).squaredNorm();
  }
};

}  // namespace ssdem
