/// @file elastic.cpp
/// Material styles "elastic" and "neo_hookean".
///
/// elastic — hypoelastic small-strain linear elasticity with an objective rate:
///   sigma_{n+1} = R sigma_n R^T + dt (lambda tr(D) I + 2 G D),  D = sym(L),
///   R the Hughes–Winget rotation increment (Hughes & Winget 1980, IJNME 15:1862, eq. 31),
///   lambda = K - 2G/3. Wave speeds c_dil = sqrt((K + 4G/3)/rho), c_bulk = sqrt(K/rho) with the
///   current density (Uintah convention, shared/reference/mpm.md §1.4).
///
/// neo_hookean — compressible neo-Hookean, the form of Uintah's CNH_MMS used by the
///   Wallstedt & Guilkey (2008, JCP 227:9628) manufactured solution:
///   sigma = [lambda ln J I + G (F F^T - I)] / J,  lambda = K - 2G/3.
///   Wave speeds as above with the current density (Uintah UCNH).
#include <Eigen/Core>
#include <cmath>

#include "mpm/material.hpp"
#include "mpm/materials/builtin.hpp"

namespace mpmfrag {
namespace {

common::Schema moduli_schema() {
  common::Schema s("elastic moduli");
  s.add_real("bulk_modulus", std::nullopt, "Pa", 0.0, 1e15, "bulk modulus K", true);
  s.add_real("shear_modulus", std::nullopt, "Pa", 0.0, 1e15, "shear modulus G");
  return s;
}

class ElasticBase : public Material {
 public:
  ElasticBase(double rho, double K, double G) : rho0_(rho), K_(K), G_(G) {}
  double density() const override { return rho0_; }
  double reference_wave_speed() const override { return std::sqrt((K_ + 4.0 * G_ / 3.0) / rho0_); }
  /// Deviatoric elastic energy V s : s / (4 G) (exact for the linear style; the small-strain value
  /// of the neo-Hookean one).
  void stored_energies(const MaterialBatch& b, double* elastic, double* dissipated) const override {
    for (std::size_t k = 0; k < b.n; ++k) {
      const double* s = b.stress + 6 * k;
      const double m = (s[0] + s[1] + s[2]) / 3.0, a = s[0] - m, c = s[1] - m, d = s[2] - m;
      const double ss = a * a + c * c + d * d + 2.0 * (s[3] * s[3] + s[4] * s[4] + s[5] * s[5]);
      elastic[k] = G_ > 0.0 ? b.volume[k] * ss / (4.0 * G_) : 0.0;
      dissipated[k] = 0.0;
    }
  }

 protected:
  double rho0_, K_, G_;
};

class LinearElastic final : public ElasticBase {
 public:
  using ElasticBase::ElasticBase;
  BatchResult update(const MaterialBatch& b) const override {
    BatchResult r;
    const double lam = K_ - 2.0 * G_ / 3.0, cd2 = K_ + 4.0 * G_ / 3.0;
    for (std::size_t k = 0; k < b.n; ++k) {
      const double* L = b.L + 9 * k;
      double* s = b.stress + 6 * k;
      const double J = det3(b.F + 9 * k);
      if (!(J > 0.0) || !std::isfinite(J)) {
        if (!r.failed++) { r.first_failed = k; r.reason = "J <= 0 or non-finite"; }
        continue;
      }
      if (b.dt > 0.0) {
        rotate_stress_hughes_winget(s, L, b.dt);
        const double trD = L[0] + L[4] + L[8];
        const double dt = b.dt;
        s[0] += dt * (lam * trD + 2.0 * G_ * L[0]);
        s[1] += dt * (lam * trD + 2.0 * G_ * L[4]);
        s[2] += dt * (lam * trD + 2.0 * G_ * L[8]);
        s[3] += dt * G_ * (L[5] + L[7]);
        s[4] += dt * G_ * (L[2] + L[6]);
        s[5] += dt * G_ * (L[1] + L[3]);
      }
      const double rho = b.mass[k] / b.volume[k];
      b.wave_speed[k] = std::sqrt(cd2 / rho);
      if (b.bulk_speed) b.bulk_speed[k] = std::sqrt(K_ / rho);
    }
    return r;
  }
};

class NeoHookean final : public ElasticBase {
 public:
  using ElasticBase::ElasticBase;
  BatchResult update(const MaterialBatch& b) const override {
    BatchResult r;
    const double lam = K_ - 2.0 * G_ / 3.0, cd2 = K_ + 4.0 * G_ / 3.0;
    for (std::size_t k = 0; k < b.n; ++k) {
      const double* F = b.F + 9 * k;
      double* s = b.stress + 6 * k;
      const double J = det3(F);
      if (!(J > 0.0) || !std::isfinite(J)) {
        if (!r.failed++) { r.first_failed = k; r.reason = "J <= 0 or non-finite"; }
        continue;
      }
      // B = F F^T (row-major F: row i = F[3i..3i+2])
      auto dot = [F](int i, int j) { return F[3 * i] * F[3 * j] + F[3 * i + 1] * F[3 * j + 1] + F[3 * i + 2] * F[3 * j + 2]; };
      const double iJ = 1.0 / J, p = lam * std::log(J);
      s[0] = (p + G_ * (dot(0, 0) - 1.0)) * iJ;
      s[1] = (p + G_ * (dot(1, 1) - 1.0)) * iJ;
      s[2] = (p + G_ * (dot(2, 2) - 1.0)) * iJ;
      s[3] = G_ * dot(1, 2) * iJ;
      s[4] = G_ * dot(0, 2) * iJ;
      s[5] = G_ * dot(0, 1) * iJ;
      const double rho = b.mass[k] / b.volume[k];
      b.wave_speed[k] = std::sqrt(cd2 / rho);
      if (b.bulk_speed) b.bulk_speed[k] = std::sqrt(K_ / rho);
    }
    return r;
  }
};

}  // namespace

void register_elastic(MaterialRegistry& reg) {
  StyleInfo s;
  s.name = "elastic";
  s.description = "linear elasticity, Hughes–Winget objective rate (K, G)";
  s.schema = moduli_schema();
  s.create = [](const common::Scene& e) -> std::unique_ptr<Material> {
    return std::make_unique<LinearElastic>(e.real("density"), e.real("bulk_modulus"), e.real("shear_modulus"));
  };
  reg.add(std::move(s));
}

void register_neo_hookean(MaterialRegistry& reg) {
  StyleInfo s;
  s.name = "neo_hookean";
  s.description = "compressible neo-Hookean, sigma = [lambda ln J I + G(B - I)]/J (K, G)";
  s.schema = moduli_schema();
  s.create = [](const common::Scene& e) -> std::unique_ptr<Material> {
    return std::make_unique<NeoHookean>(e.real("density"), e.real("bulk_modulus"), e.real("shear_modulus"));
  };
  reg.add(std::move(s));
}

/// Factory helpers for tests (no scene needed).
std::unique_ptr<Material> make_linear_elastic(double rho, double K, double G) {
  return std::make_unique<LinearElastic>(rho, K, G);
}
std::unique_ptr<Material> make_neo_hookean(double rho, double K, double G) {
  return std::make_unique<NeoHookean>(rho, K, G);
}

}  // namespace mpmfrag
