/// @file tillotson_eos.cpp
/// Tillotson EOS (Tillotson 1962; Benz & Asphaug 1999, Icarus 142:5, eqs. in §2 of their paper;
/// validation-data.md §2.2). See tillotson.hpp for the equations and the documented deviations.
#include <algorithm>

#include "mpm/materials/tillotson.hpp"

namespace mpmfrag {
namespace {

struct PD {
  double P, dPdr, dPde;
};

// Compressed / cold branch.
PD branch_c(const TillotsonParams& q, double rho, double e) {
  const double eta = rho / q.rho0, mu = eta - 1.0;
  const double w = e / (q.E0 * eta * eta) + 1.0;
  const double P = (q.a + q.b / w) * rho * e + q.A * mu + q.B * mu * mu;
  const double dwdr = -2.0 * (w - 1.0) / rho;
  const double dPdr = (q.a + q.b / w) * e - rho * e * q.b / (w * w) * dwdr + (q.A + 2.0 * q.B * mu) / q.rho0;
  const double dPde = rho * (q.a + q.b / (w * w));
  return {P, dPdr, dPde};
}

// Expanded hot branch.
PD branch_e(const TillotsonParams& q, double rho, double e) {
  const double eta = rho / q.rho0, mu = eta - 1.0, nu = 1.0 / eta - 1.0;
  const double w = e / (q.E0 * eta * eta) + 1.0;
  const double eb = std::exp(-q.beta * nu), ea = std::exp(-q.alpha * nu * nu);
  const double X = q.b * rho * e / w + q.A * mu * eb;
  const double P = q.a * rho * e + X * ea;
  const double dwdr = -2.0 * (w - 1.0) / rho;
  const double dnudr = -q.rho0 / (rho * rho);
  const double dXdr = q.b * e / w - q.b * rho * e / (w * w) * dwdr + q.A / q.rho0 * eb -
                      q.A * mu * eb * q.beta * dnudr;
  const double deadr = ea * (-2.0 * q.alpha * nu * dnudr);
  const double dPdr = q.a * e + dXdr * ea + X * deadr;
  const double dPde = q.a * rho + q.b * rho * ea / (w * w);
  return {P, dPdr, dPde};
}

}  // namespace

TillotsonState tillotson_eos(const TillotsonParams& q, double rho, double e_in) {
  TillotsonState s;
  const double c0sq = q.A / q.rho0;
  const double cmin2 = q.c_min_fraction * q.c_min_fraction * c0sq;
  if (!(rho > 1e-12 * q.rho0) || !std::isfinite(rho)) {
    s.pressure = 0.0;
    s.c2 = cmin2;
    s.branch = TillotsonBranch::expanded;
    return s;
  }
  const double e = std::isfinite(e_in) ? std::max(e_in, 0.0) : 0.0;
  PD r;
  if (rho >= q.rho0 || e <= q.Eiv) {
    r = branch_c(q, rho, e);
    s.branch = TillotsonBranch::compressed;
  } else if (e >= q.Ecv) {
    r = branch_e(q, rho, e);
    s.branch = TillotsonBranch::expanded;
  } else {
    const PD c = branch_c(q, rho, e), x = branch_e(q, rho, e);
    const double den = q.Ecv - q.Eiv, we = (e - q.Eiv) / den, wc = (q.Ecv - e) / den;
    r.P = we * x.P + wc * c.P;
    r.dPdr = we * x.dPdr + wc * c.dPdr;
    r.dPde = we * x.dPde + wc * c.dPde + (x.P - c.P) / den;
    s.branch = TillotsonBranch::hybrid;
  }
  double P = r.P;
  if (P < q.pressure_min) {
    P = q.pressure_min;
    r.dPdr = 0.0;
    r.dPde = 0.0;
  }
  double c2 = r.dPdr + P / (rho * rho) * r.dPde;
  if (!(c2 > cmin2)) c2 = cmin2;
  s.pressure = std::isfinite(P) ? P : 0.0;
  s.c2 = std::isfinite(c2) ? c2 : cmin2;
  return s;
}

}  // namespace mpmfrag
