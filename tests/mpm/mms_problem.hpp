/// @file mms_problem.hpp
/// Axis-aligned manufactured solution (Wallstedt & Guilkey 2008, JCP 227:9628; Uintah AA.ups /
/// CNH_MMS; shared/reference/mpm.md §2.2), shared by the verification test and the
/// convergence study driver.
#pragma once
#include <chrono>
#include <cmath>
#include <vector>

#include "mpm/materials/builtin.hpp"
#include "mpm/solver.hpp"

namespace mms {

struct Result {
  double l2 = 0, linf = 0, wall_s = 0;
  std::size_t particles = 0;
  std::int64_t steps = 0;
};

inline Result run(int N, mpmfrag::ShapeKind shape, mpmfrag::Scheme scheme, double A = 0.05,
                  int ppc = 2, double courant = 0.2, double T = 0.02) {
  using namespace mpmfrag;
  const double K = 8333.33, G = 3846.15, rho0 = 1.0;
  const double lam = K - 2.0 * G / 3.0;
  const double E = 9.0 * K * G / (3.0 * K + G);
  const double c = std::sqrt(E / rho0);
  const double PI = M_PI;
  const double phi[3] = {0.0, 2.0 / 3.0, 4.0 / 3.0};
  const double h = 1.0 / N;
  SolverConfig cfg;
  cfg.shape = shape;
  cfg.scheme = scheme;
  cfg.flip = 1.0;
  cfg.courant = courant;
  cfg.min_mass_fraction = 0.0;
  for (auto& b : cfg.boundary) b = BoundaryType::symmetry;
  const common::GridInfo grid = make_grid(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones(), h, 2);
  const int np1 = N * ppc;
  const std::size_t n = static_cast<std::size_t>(np1) * np1 * np1;
  ParticleSet ps;
  ps.resize(n, false);
  std::vector<double> X(3 * n);
  const double Vref = std::pow(h / ppc, 3);
  std::size_t p = 0;
  for (int k = 0; k < np1; ++k)
    for (int j = 0; j < np1; ++j)
      for (int i = 0; i < np1; ++i, ++p) {
        const int idx[3] = {i, j, k};
        double J = 1.0;
        for (int d = 0; d < 3; ++d) {
          const double Xd = (idx[d] + 0.5) * h / ppc;
          X[3 * p + d] = Xd;
          const double u = A * std::sin(PI * Xd) * std::sin(PI * phi[d]);
          const double Fdd = 1.0 + A * PI * std::cos(PI * Xd) * std::sin(PI * phi[d]);
          ps.x[3 * p + d] = Xd + u;
          ps.v[3 * p + d] = A * PI * c * std::sin(PI * Xd) * std::cos(PI * phi[d]);
          ps.F[9 * p + 4 * d] = Fdd;
          ps.half_width[3 * p + d] = 0.5 * h / ppc * Fdd;
          J *= Fdd;
        }
        ps.id[p] = p;
        ps.material[p] = 0;
        ps.mass[p] = rho0 * Vref;
        ps.volume0[p] = Vref;
        ps.volume[p] = Vref * J;
      }
  std::vector<MaterialSlot> mats(1);
  mats[0].name = "mms";
  static const StyleInfo style = *builtin_materials().find("neo_hookean");
  mats[0].style = &style;
  mats[0].model = make_neo_hookean(rho0, K, G);
  mats[0].begin = 0;
  mats[0].end = n;
  Solver s(cfg, grid, std::move(ps), std::move(mats));
  auto u_exact = [&](double Xd, int d, double t) { return A * std::sin(PI * Xd) * std::sin(PI * (phi[d] + c * t)); };
  s.set_body_force([&](std::size_t b, std::size_t e, double t, const ParticleSet& P, double* acc) {
    for (std::size_t q = b; q < e; ++q) {
      const double* Xp = &X[3 * P.id[q]];
      double Fd[3], J = 1.0;
      for (int d = 0; d < 3; ++d) {
        Fd[d] = 1.0 + A * PI * std::cos(PI * Xp[d]) * std::sin(PI * (phi[d] + c * t));
        J *= Fd[d];
      }
      for (int d = 0; d < 3; ++d) {
        const double u = u_exact(Xp[d], d, t);
        acc[3 * (q - b) + d] = PI * PI * u * (G / rho0 - c * c - (lam * (std::log(J) - 1.0) - G) / (rho0 * Fd[d] * Fd[d]));
      }
    }
  });
  const auto t0 = std::chrono::steady_clock::now();
  s.initialize();
  while (s.time() < T * (1 - 1e-12)) s.step(std::min(s.stable_dt(), T - s.time()));
  Result r;
  r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const ParticleSet& P = s.particles();
  double sum = 0;
  for (std::size_t q = 0; q < n; ++q) {
    const double* Xp = &X[3 * P.id[q]];
    double e2 = 0;
    for (int d = 0; d < 3; ++d) {
      const double err = P.x[3 * q + d] - Xp[d] - u_exact(Xp[d], d, s.time());
      e2 += err * err;
    }
    sum += e2;
    r.linf = std::max(r.linf, std::sqrt(e2));
  }
  r.l2 = std::sqrt(sum / n);
  r.particles = n;
  r.steps = s.step_count();
  return r;
}

}  // namespace mms
