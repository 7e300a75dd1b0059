/// @file contact_hertz.cpp
/// Tsuji damping constant and Hertz contact time (equations in contact/normal_hertz.hpp).
#include <cmath>

#include "ssdem/contact/normal_hertz.hpp"

namespace ssdem {

double hertz_restitution(double alpha) {
  // X'' = -X^{3/2} - alpha X^{1/4} X', X(0) = 0, X'(0) = 1 (units: mu = K = v = 1), RK4 until
  // X returns to 0; the exit speed interpolated linearly at the crossing.
  auto acc = [alpha](double x, double v) {
    const double xp = x > 0.0 ? x : 0.0;
    return -xp * std::sqrt(xp) - alpha * std::sqrt(std::sqrt(xp)) * v;
  };
  const double h = 2e-4;
  double x = 0.0, v = 1.0;
  for (int i = 0; i < 1000000; ++i) {
    const double k1x = v, k1v = acc(x, v);
    const double k2x = v + 0.5 * h * k1v, k2v = acc(x + 0.5 * h * k1x, v + 0.5 * h * k1v);
    const double k3x = v + 0.5 * h * k2v, k3v = acc(x + 0.5 * h * k2x, v + 0.5 * h * k2v);
    const double k4x = v + h * k3v, k4v = acc(x + h * k3x, v + h * k3v);
    const double xn = x + h / 6.0 * (k1x + 2 * k2x + 2 * k3x + k4x);
    const double vn = v + h / 6.0 * (k1v + 2 * k2v + 2 * k3v + k4v);
    if (i > 0 && xn <= 0.0) {
      const double f = x / (x - xn);
      return -(v + f * (vn - v));
    }
    x = xn;
    v = vn;
  }
  return 0.0;  // never left (overdamped)
}

double hertz_damping_alpha(double e) {
  if (!(e < 1.0)) return 0.0;
  double lo = 0.0, hi = 1.0;
  while (hertz_restitution(hi) > e && hi < 64.0) hi *= 2.0;
  for (int it = 0; it < 50; ++it) {
    const double mid = 0.5 * (lo + hi);
    if (hertz_restitution(mid) > e) lo = mid;
    else hi = mid;
  }
  return 0.5 * (lo + hi);
}

double hertz_contact_time(double mu, double K, double v) {
  if (!(v > 0.0) || !(K > 0.0)) return INFINITY;
  // x_max from mu v^2 / 2 = (2/5) K x^{5/2}; t_c = 2 (x_max / v) * (2/5) B(2/5, 1/2)
  const double xmax = std::pow(1.25 * mu * v * v / K, 0.4);
  const double I = 0.4 * std::tgamma(0.4) * std::tgamma(0.5) / std::tgamma(0.9);
  return 2.0 * xmax / v * I;
}

}  // namespace ssdem
