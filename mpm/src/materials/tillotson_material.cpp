/// @file tillotson_material.cpp
/// Material style "tillotson": Tillotson EOS pressure + hypoelastic deviatoric stress.
///
///   sigma = s - P(rho, e) I
///   s_{n+1} = R s_n R^T + 2 G dt dev(D)        (Hughes–Winget rotation R, IJNME 15:1862)
///   P from tillotson_eos (Tillotson 1962; Benz & Asphaug 1999 basalt defaults; see tillotson.hpp)
///
/// The EOS needs e_{n+1}, which depends on P_{n+1} (dE = -P dV + s:D dV): one predictor-corrector
/// pass, e* = e_n + dt/rho (sigma_n : D), P* = P(rho_{n+1}, e*), then
/// e** = e_n + dt/rho [ (s_n+s_{n+1})/2 : D - (P_n + P*)/2 tr D ], P_{n+1} = P(rho_{n+1}, e**).
/// (Benz & Asphaug 1999 integrate de/dt = -(P/rho) tr D + s:D/rho explicitly in SPH; the
/// corrector makes the EOS energy second-order consistent with the solver's trapezoidal energy
/// integration.) Viscous heating from the artificial viscosity enters e_n via the solver.
/// Wave speeds: c_bulk^2 = dP/drho + P/rho^2 dP/de, c_dil^2 = c_bulk^2 + 4G/(3 rho).
/// No strength limit or damage here (an elastic deviatoric response, as in the issue); the
/// Tonge–Ramesh style adds those.
#include <cmath>

#include "mpm/material.hpp"
#include "mpm/materials/builtin.hpp"
#include "mpm/materials/tillotson.hpp"

namespace mpmfrag {
namespace {

class Tillotson final : public Material {
 public:
  Tillotson(const TillotsonParams& p, double G) : p_(p), G_(G) {}
  double density() const override { return p_.rho0; }
  double reference_wave_speed() const override {
    return std::sqrt((tillotson_eos(p_, p_.rho0, 0.0).c2 + 4.0 * G_ / (3.0 * p_.rho0)));
  }

  BatchResult update(const MaterialBatch& b) const override {
    BatchResult r;
    for (std::size_t k = 0; k < b.n; ++k) {
      const double* L = b.L + 9 * k;
      double* s = b.stress + 6 * k;
      const double J = det3(b.F + 9 * k);
      const double rho = b.mass[k] / b.volume[k];
      if (!(J > 0.0) || !std::isfinite(J) || !std::isfinite(rho)) {
        if (!r.failed++) { r.first_failed = k; r.reason = "J <= 0 or non-finite"; }
        continue;
      }
      const double pn = -(s[0] + s[1] + s[2]) / 3.0;
      double dev[6] = {s[0] + pn, s[1] + pn, s[2] + pn, s[3], s[4], s[5]};
      const double dt = b.dt;
      const double en = b.energy[k];
      double P;
      TillotsonState st;
      if (dt > 0.0) {
        const double D[6] = {L[0], L[4], L[8], 0.5 * (L[5] + L[7]), 0.5 * (L[2] + L[6]), 0.5 * (L[1] + L[3])};
        const double trD = D[0] + D[1] + D[2];
        auto ddot = [&D](const double* v) {
          return v[0] * D[0] + v[1] * D[1] + v[2] * D[2] + 2.0 * (v[3] * D[3] + v[4] * D[4] + v[5] * D[5]);
        };
        const double dev_old_D = ddot(dev);
        rotate_stress_hughes_winget(dev, L, dt);
        const double third = trD / 3.0;
        dev[0] += 2.0 * G_ * dt * (D[0] - third);
        dev[1] += 2.0 * G_ * dt * (D[1] - third);
        dev[2] += 2.0 * G_ * dt * (D[2] - third);
        dev[3] += 2.0 * G_ * dt * D[3];
        dev[4] += 2.0 * G_ * dt * D[4];
        dev[5] += 2.0 * G_ * dt * D[5];
        const double e1 = en + dt / rho * (dev_old_D - pn * trD);
        const double p1 = tillotson_pressure(p_, rho, e1);
        const double e2 = en + dt / rho * (0.5 * (dev_old_D + ddot(dev)) - 0.5 * (pn + p1) * trD);
        st = tillotson_eos(p_, rho, e2);
      } else {
        st = tillotson_eos(p_, rho, en);
      }
      P = st.pressure;
      s[0] = dev[0] - P;
      s[1] = dev[1] - P;
      s[2] = dev[2] - P;
      s[3] = dev[3];
      s[4] = dev[4];
      s[5] = dev[5];
      b.wave_speed[k] = std::sqrt(st.c2 + 4.0 * G_ / (3.0 * rho));
      if (b.bulk_speed) b.bulk_speed[k] = std::sqrt(st.c2);
    }
    return r;
  }

 private:
  TillotsonParams p_;
  double G_;
};

}  // namespace

void register_tillotson(MaterialRegistry& reg) {
  StyleInfo s;
  s.name = "tillotson";
  s.description = "Tillotson EOS + elastic deviatoric stress; defaults: basalt (Benz & Asphaug 1999)";
  const TillotsonParams d;
  common::Schema& c = s.schema;
  c.add_real("A", d.A, "Pa", 0.0, 1e15, "Tillotson A (bulk modulus)", true);
  c.add_real("B", d.B, "Pa", 0.0, 1e15, "Tillotson B");
  c.add_real("a", d.a, "1", 0.0, 10.0, "Tillotson a");
  c.add_real("b", d.b, "1", 0.0, 10.0, "Tillotson b");
  c.add_real("alpha", d.alpha, "1", 0.0, 100.0, "Tillotson alpha");
  c.add_real("beta", d.beta, "1", 0.0, 100.0, "Tillotson beta");
  c.add_real("E0", d.E0, "J/kg", 0.0, 1e15, "Tillotson E0", true);
  c.add_real("E_iv", d.Eiv, "J/kg", 0.0, 1e15, "energy of incipient vaporisation");
  c.add_real("E_cv", d.Ecv, "J/kg", 0.0, 1e15, "energy of complete vaporisation");
  c.add_real("shear_modulus", 22.7e9, "Pa", 0.0, 1e15, "shear modulus G (basalt: 22.7 GPa)");
  c.add_real("pressure_min", -1e30, "Pa", -1e30, 0.0,
             "tensile pressure floor (default -1e30: none; 0 = no tension)");
  s.create = [](const common::Scene& e) -> std::unique_ptr<Material> {
    TillotsonParams p;
    p.rho0 = e.real("density");
    p.A = e.real("A");
    p.B = e.real("B");
    p.a = e.real("a");
    p.b = e.real("b");
    p.alpha = e.real("alpha");
    p.beta = e.real("beta");
    p.E0 = e.real("E0");
    p.Eiv = e.real("E_iv");
    p.Ecv = e.real("E_cv");
    p.pressure_min = e.real("pressure_min");
    if (!(p.Ecv > p.Eiv)) throw std::invalid_argument("tillotson: E_cv must exceed E_iv");
    return std::make_unique<Tillotson>(p, e.real("shear_modulus"));
  };
  reg.add(std::move(s));
}

std::unique_ptr<Material> make_tillotson(const TillotsonParams& p, double G) {
  return std::make_unique<Tillotson>(p, G);
}

}  // namespace mpmfrag
