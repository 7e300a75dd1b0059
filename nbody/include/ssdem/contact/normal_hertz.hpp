/// @file normal_hertz.hpp
/// Contact part "hertz": Hertz normal law with Mindlin tangential stiffness and Tsuji damping,
/// an alternative to "normal" (exactly one normal law per scene).
///   Elastic normal force   F_N = -K x^{3/2} n,  K = (4/3) E* sqrt(R*)     (Johnson 1985, eq. 4.22)
///   E* = E / (2 (1 - nu^2))  (two spheres of one material; a wall is taken of the same material)
///   R* = Rbar = s_p s_n / (s_p + s_n) (wall: s_p)
///   normal tangent stiffness k_n(x) = dF/dx = 2 E* sqrt(R* x)        (used by rolling: k_r = k_n a^2)
///   Mindlin tangential stiffness k_t(x) = 8 G* sqrt(R* x),
///   G* = G / (2 (2 - nu)), G = E / (2 (1 + nu))   (Mindlin 1949; Tsuji, Tanaka & Ishida 1992,
///   Powder Technol. 71:239, eq. for k_t; no micro-slip, the tangential spring S of the
///   tangential part is scaled by the current k_t(x))
///   Dashpots (damping part), Tsuji et al. 1992:  C_n = alpha(e_n) sqrt(mu K) x^{1/4},
///   C_t = alpha(e_t) sqrt(mu k_t(x)).  alpha(e) is not tabulated here but computed once by
///   solving the dimensionless impact X'' = -X^{3/2} - alpha X^{1/4} X' (X(0) = 0, X'(0) = 1)
///   for the alpha whose exit speed is e (bisection, RK4); in that model e does not depend on the
///   impact speed (Tsuji et al. 1992), which the tests check.
///   Stored energy (2/5) K x^{5/2} (normal) + k_t(x) |S|^2 / 2 (tangential part).
/// Contact time and the dt rule (dt_rule.hpp): the stiffness grows with the overlap, so the
/// contact time shortens with the impact speed v (undamped; Johnson 1985 §11.4):
///   x_max = (15 mu v^2 / (16 E* sqrt(R*)))^{2/5},  t_c = 2 (x_max / v) I,
///   I = int_0^1 (1 - s^{5/2})^{-1/2} ds = (2/5) B(2/5, 1/2) = 1.4716...  (t_c = 3.218 (mu/K)^{2/5} v^{-1/5})
/// The dt rule uses v = contact.vmax (the largest expected impact speed) and the lightest pair.
#pragma once
#include <cmath>

#include "ssdem/contact/damping.hpp"
#include "ssdem/contact/part.hpp"

namespace ssdem {

inline constexpr unsigned kPartHertz = 16u;

/// alpha of the Tsuji dashpot for restitution e (0 for e >= 1), see the file comment.
double hertz_damping_alpha(double e);
/// Exit speed / impact speed of the dimensionless Tsuji-Hertz impact with dashpot alpha.
double hertz_restitution(double alpha);
/// Undamped Hertz contact time for reduced mass mu, K = (4/3) E* sqrt(R*), impact speed v.
double hertz_contact_time(double mu, double K, double v);

struct HertzNormal : PartBase {
  static constexpr const char* name = "hertz";
  static constexpr unsigned flag = kPartHertz;
  static constexpr unsigned requires_parts = 0u;
  static constexpr PartSlot slot = PartSlot::normal;
  static constexpr const char* help =
      "Hertz normal law F = (4/3) E* sqrt(R*) x^1.5 with Mindlin k_t = 8 G* sqrt(R* x) and Tsuji "
      "damping (Johnson 1985; Tsuji et al. 1992); replaces 'normal'";
  struct Params {
    double E = 0.0;     ///< Young's modulus [Pa]
    double nu = 0.25;   ///< Poisson's ratio
    double vmax = 0.0;  ///< impact speed for the dt rule [m/s] (set from contact.vmax)
  };
  static void declare(common::Schema& s) {
    s.add_real("E", 0.0, "Pa", 0.0, 1e15, "Young's modulus of the sphere material (required with 'hertz')");
    s.add_real("nu", 0.25, "1", 0.0, 0.5, "Poisson's ratio of the sphere material", true);
  }
  template <class P>
  static void read(const common::Scene& s, const std::string& pre, P& p) {
    p.E = s.real(pre + "E");
    p.nu = s.real(pre + "nu");
  }
  struct Coeffs {
    double Estar = 0, Gstar = 0, alpha_n = 0, alpha_t = 0;
    template <class P>
    explicit Coeffs(const P& p) {
      if (!(p.parts & kPartHertz)) return;
      Estar = p.E / (2.0 * (1.0 - p.nu * p.nu));
      const double G = p.E / (2.0 * (1.0 + p.nu));
      Gstar = G / (2.0 * (2.0 - p.nu));
      if (p.parts & kPartDamping) {
        alpha_n = hertz_damping_alpha(p.en);
        alpha_t = hertz_damping_alpha(p.et);
      }
    }
  };
  // --- the normal-law interface used by the other parts ---
  template <class C, class R>
  static void stiffness(const C& c, const R& x, const R& Rbar, R& kn, R& kt) {
    const R a = lsqrt(Rbar * x);  // contact radius
    kn = 2.0 * c.Estar * a;
    kt = 8.0 * c.Gstar * a;
  }
  template <class C, class R>
  static R cn(const C& c, const PairCtx<R>& k) {
    // sqrt(mu K) x^{1/4} = sqrt(mu (4/3) E* sqrt(R* x))
    return c.alpha_n * lsqrt(k.mu * (4.0 / 3.0) * c.Estar * lsqrt(k.Rbar * k.x));
  }
  template <class C, class R>
  static R ct(const C& c, const PairCtx<R>& k) { return c.alpha_t * lsqrt(k.mu * k.kt); }
  /// Edge impulses (contact_law.hpp, "Contact edges"), with x = w t after the edge, y = sig + h/2,
  /// K = (4/3) E* sqrt(R*) and C_n = C_0 x^{1/4}, C_0 = alpha_n sqrt(mu K):
  ///   spring  K w^{3/2} [y^{5/2} / (5/2) - sig^{3/2} h] / h              (repulsive)
  ///   dashpot C_0 w^{1/4} [y^{5/4} / (5/4) - sig^{1/4} h] / h            (times u_n)
  template <class C, class R>
  static R edge_spring(const C& c, const PairCtx<R>& k, const R& w, const R& sig) {
    const R K = (4.0 / 3.0) * c.Estar * lsqrt(k.Rbar), y = sig + 0.5 * k.h;
    return K * w * lsqrt(w) * (0.4 * y * y * lsqrt(y) - sig * lsqrt(sig) * k.h) / k.h;
  }
  template <class C, class R>
  static R edge_dashpot(const C& c, const PairCtx<R>& k, const R& w, const R& sig) {
    const R C0 = c.alpha_n * lsqrt(k.mu * (4.0 / 3.0) * c.Estar * lsqrt(k.Rbar)), y = sig + 0.5 * k.h;
    return C0 * lsqrt(lsqrt(w)) * (0.8 * y * lsqrt(lsqrt(y)) - lsqrt(lsqrt(sig)) * k.h) / k.h;
  }
  // --- hooks ---
  template <unsigned PARTS, bool WALL, class N, class C, class R, class H>
  static void normal_phase(const C& c, PairCtx<R>& k, const H&) {
    const R a = lsqrt(k.Rbar * k.x);
    k.kn = 2.0 * c.Estar * a;
    k.kt = 8.0 * c.Gstar * a;
    k.FN = (-(4.0 / 3.0) * c.Estar * a * k.x) * k.n;  // (4/3) E* sqrt(R*) x^{3/2}
  }
  template <class N, class C, class R, class H>
  static R energy(const C& c, const EnergyCtx<R>& e, const H&) {
    return (8.0 / 15.0) * c.Estar * lsqrt(e.Rbar * e.x) * e.x * e.x;  // (2/5) K x^{5/2}
  }
};

}  // namespace ssdem
