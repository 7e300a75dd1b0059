/// @file granular.cpp
/// Drucker–Prager granular return with dilatancy and P–alpha compaction (equations and the
/// deviations from PTR are in granular.hpp; Tonge & Ramesh 2016, ARL-SR-0344 Eqs. 13–15).
#include "mpm/tonge_ramesh/granular.hpp"

#include <cmath>
#include <limits>

#include "mpm/tonge_ramesh/moduli.hpp"

namespace mpmfrag::tonge_ramesh {

namespace {
constexpr double kSqrt3 = 1.7320508075688772;

/// Solve p_K(x) = target for x = ln J_EL by Newton from x0 (exact slope, monotone function).
double solve_lnJel(const Params& p, double x0, double e, double ratio, double target, double Kref) {
  double x = x0;
  for (int it = 0; it < 60; ++it) {
    const double Jel = std::exp(x);
    const double r = kirchhoff_mean(p, Jel, e, ratio) - target;
    if (std::abs(r) <= 1e-12 * Kref) break;
    double slope = kirchhoff_mean_slope(p, Jel, e, ratio);
    if (!(slope > 1e-6 * Kref)) slope = Kref;
    double dx = -r / slope;
    if (std::abs(dx) > 0.05) dx = std::copysign(0.05, dx);
    x += dx;
  }
  return x;
}
}  // namespace

double crush_alpha(const Params& p, const Derived& d, double P) {
  if (P <= 0.0) return std::numeric_limits<double>::infinity();
  if (P >= p.pa_Pc) return 1.0;
  if (P >= p.pa_P0) {
    const double r = (p.pa_Pc - P) / (p.pa_Pc - p.pa_P0);
    return 1.0 + (p.pa_alpha0 - 1.0) * r * r;
  }
  return p.pa_alpha0 + std::log(p.pa_P0 / P) / d.pa_kappa;
}

double granular_flow(const Params& p, const Derived& d, double D, double J, double e, double dt,
                     Eigen::Matrix3d& be, double& JGP, double& gp_strain) {
  const double K = damaged_bulk(d, D), G = damaged_shear(p, d, D);
  const double ratio = K / d.K0;
  const double Itr = be.trace() / 3.0;
  const Eigen::Matrix3d tau_tr = G * (be - Itr * Eigen::Matrix3d::Identity());
  const double x_tr = std::log(J / JGP);
  const double p_tr = kirchhoff_mean(p, std::exp(x_tr), e, ratio);
  double Kt = kirchhoff_mean_slope(p, std::exp(x_tr), e, ratio);
  if (!(Kt > 1e-3 * K)) Kt = K;
  const double A = p.dp_slope, B = p.dp_cohesion;
  const double ss = tau_tr.norm(), sp = kSqrt3 * p_tr;
  const double f = ss + A * (sp - B);
  if (f <= 1e-12 * K) return 0.0;

  const double etaG = 2.0 * G / (3.0 * Kt);
  double sp_bar, ss_bar;
  const double Delta = f / (A * A + etaG);
  sp_bar = sp - A * Delta;
  ss_bar = ss - etaG * Delta;
  if (ss_bar < 0.0 || ss <= 1e-12 * K) {
    sp_bar = B;
    ss_bar = 0.0;
  }
  const double p_bar = sp_bar / kSqrt3;
  Eigen::Matrix3d tau_bar = ss > 0.0 ? Eigen::Matrix3d(tau_tr * (ss_bar / ss))
                                     : Eigen::Matrix3d(Eigen::Matrix3d::Zero());
  Eigen::Matrix3d tau_dev = tau_bar;
  double p_star = p_bar;
  if (p.granular_time > 0.0) {  // Duvaut–Lions overstress relaxation
    const double r = dt / p.granular_time;
    tau_dev = (tau_tr + r * tau_bar) / (1.0 + r);
    p_star = (p_tr + r * p_bar) / (1.0 + r);
  }

  // Dilatancy: ln J_EL such that p_K = p*.
  double x_new = solve_lnJel(p, x_tr - (p_tr - p_star) / Kt, e, ratio, p_star, K);
  double dlnJgp = x_tr - x_new;
  if (dlnJgp < 0.0) dlnJgp = 0.0;  // associative cone never compacts; guard round-off

  // Deviatoric update.
  double Iel = Itr;
  const double ntr2 = ss * ss, ndev2 = tau_dev.squaredNorm();
  if (ntr2 > ndev2) Iel = 1.0 + (Itr - 1.0) * ndev2 / ntr2;
  const double dW_dev = 1.5 * G * (Itr - Iel);

  // Stored-energy check with backtracking of the dilatancy (PTR).
  auto p_at = [&](double dl) { return kirchhoff_mean(p, std::exp(x_tr - dl), e, ratio); };
  double p_new = p_at(dlnJgp);
  double dU = 0.5 * (p_tr + p_new) * dlnJgp;
  for (int it = 0; dU + dW_dev < 0.0 && dU < 0.0 && it < 110; ++it) {
    dlnJgp *= 0.9;
    p_new = p_at(dlnJgp);
    dU = 0.5 * (p_tr + p_new) * dlnJgp;
  }
  if (dU + dW_dev < 0.0 && dU < 0.0) {
    dlnJgp = 0.0;
    p_new = p_tr;
  }

  JGP *= std::exp(dlnJgp);
  be = tau_dev / G + Iel * Eigen::Matrix3d::Identity();
  gp_strain += (tau_tr - tau_dev).norm() / (2.0 * G);
  return p_new * dlnJgp + (tau_dev.cwiseProduct(tau_tr - tau_dev)).sum() / (2.0 * G);
}

double pa_compaction(const Params& p, const Derived& d, double D, double J, double e, double dt,
                     double& JGP) {
  const double alpha0 = JGP;
  if (alpha0 <= 1.0) {
    JGP = 1.0;
    return 0.0;
  }
  const double ratio = damaged_bulk(d, D) / d.K0;
  auto pK = [&](double a) { return kirchhoff_mean(p, J / a, e, ratio); };
  auto g = [&](double a) { return a - crush_alpha(p, d, -pK(a) / J); };
  const double g0 = g(alpha0);
  if (!(g0 > 1e-12)) return 0.0;
  // Root of the increasing function g on [1, alpha0]: g(1) <= 0 < g(alpha0).
  double lo = 1.0, hi = alpha0, glo = g(1.0), ghi = g0;
  double a = hi;
  if (glo >= 0.0) {
    a = 1.0;
  } else {
    for (int it = 0; it < 200 && hi - lo > 1e-13 * hi; ++it) {
      double m = hi - ghi * (hi - lo) / (ghi - glo);  // secant (regula falsi)
      if (!(m > lo && m < hi) || it % 3 == 2) m = 0.5 * (lo + hi);  // safeguard: bisect
      const double gm = g(m);  // may be -inf (tensile P: no compaction)
      if (gm > 0.0) {
        hi = m;
        ghi = gm;
      } else {
        lo = m;
        glo = gm;
      }
      a = 0.5 * (lo + hi);
      if (std::abs(gm) < 1e-13) {
        a = m;
        break;
      }
    }
  }
  if (p.granular_time > 0.0) {
    const double r = dt / p.granular_time;
    a = (alpha0 + r * a) / (1.0 + r);
  }
  a = std::max(a, 1.0);
  JGP = a;
  return 0.5 * (pK(alpha0) + pK(a)) * std::log(a / alpha0);
}

}  // namespace mpmfrag::tonge_ramesh
