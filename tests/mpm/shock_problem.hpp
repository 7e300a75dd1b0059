/// @file shock_problem.hpp
/// Planar symmetric Tillotson-basalt impact (1D column, roller side faces): two plates at
/// +-u_p collide at z = 0; behind each shock the material is at rest at the Hugoniot state.
/// Exact answer (Rankine–Hugoniot with the Tillotson EOS, validation-data.md §2.3): for
/// u_p = 2.5 km/s, P = 48.13 GPa, rho/rho0 = 1.5399, U_s = 7.131 km/s (relative to the
/// unshocked plate), so in the lab frame the shock moves at U_s - u_p = 4.631 km/s.
/// Shared by the verification test and the convergence study.
#pragma once
#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>
#include <vector>

#include "mpm/materials/tillotson.hpp"
#include "test_helpers.hpp"

namespace shock {

struct Exact {
  double P, rho, Us, e;
};

/// Tillotson Hugoniot state for particle velocity up (from rest, P0 = 0, e0 = 0): solve
/// P(rho, e) (1/rho0 - 1/rho) = up^2 with e = up^2/2 by bisection on rho.
inline Exact hugoniot(const mpmfrag::TillotsonParams& p, double up) {
  double lo = p.rho0 * 1.0000001, hi = p.rho0 * 4;
  const double e = 0.5 * up * up;
  for (int it = 0; it < 200; ++it) {
    const double mid = 0.5 * (lo + hi);
    const double f = mpmfrag::tillotson_pressure(p, mid, e) * (1 / p.rho0 - 1 / mid) - up * up;
    (f > 0 ? hi : lo) = mid;
  }
  const double rho = 0.5 * (lo + hi);
  return {mpmfrag::tillotson_pressure(p, rho, e), rho, up * rho / (rho - p.rho0), e};
}

struct Result {
  double P = 0, rho = 0, v_behind = 0, shock_speed_lab = 0, wall_s = 0;
  double l1 = 0;  ///< mean over cell bins of the upper plate of |<P>_bin - P_exact| / P_H (exact: a step)
  std::size_t particles = 0;
  std::int64_t steps = 0;
  double e_behind = 0;            ///< mean specific internal energy behind the shock (upper plate) [J/kg]
  mpmfrag::Diagnostics d0, d1;    ///< totals at t = 0 and t_end
};

/// cells: cells across one plate (plate thickness 0.1 m); t_end such that the shock has run
/// about 60 % of the plate.
inline Result run(int cells, double up = 2500.0, double t_end = 1.2e-5, int ppc = 2,
                  const std::string& scheme = "musl") {
  const double Lp = 0.1, h = Lp / cells;
  const std::string toml = R"(
[grid]
domain_min = [0.0, 0.0, -0.11]
domain_max = [)" + std::to_string(h) + ", " + std::to_string(h) + R"(, 0.11]
cell_size = )" + std::to_string(h) + R"(
[solver]
scheme = ")" + scheme + R"("
courant = 0.3
artificial_viscosity.enabled = true
[boundary]
x_min = "symmetry"
x_max = "symmetry"
y_min = "symmetry"
y_max = "symmetry"
[time]
end = 1.0
[[material]]
name = "basalt"
model = "tillotson"
density = 2700.0
shear_modulus = 0.0
[[body]]
material = "basalt"
shape = "box"
min = [0.0, 0.0, -0.1]
max = [)" + std::to_string(h) + ", " + std::to_string(h) + R"(, 0.0]
velocity = [0.0, 0.0, )" + std::to_string(up) + R"(]
ppc = )" + std::to_string(ppc) + R"(
[[body]]
material = "basalt"
shape = "box"
min = [0.0, 0.0, 0.0]
max = [)" + std::to_string(h) + ", " + std::to_string(h) + R"(, 0.1]
velocity = [0.0, 0.0, )" + std::to_string(-up) + R"(]
ppc = )" + std::to_string(ppc) + R"(
)";
  const auto t0 = std::chrono::steady_clock::now();
  mpmfrag::Solver s = mpmtest::solver_from(mpmtest::setup_from(toml));
  Result r;
  r.d0 = s.diagnostics();
  mpmtest::run_to(s, t_end);
  r.d1 = s.diagnostics();
  r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  r.particles = s.particles().size();
  r.steps = s.step_count();
  // pressure profile of the upper (z > 0) plate: P = -tr(sigma)/3
  const mpmfrag::ParticleSet& ps = s.particles();
  const double zs_guess = (hugoniot(mpmfrag::TillotsonParams{}, up).Us - up) * t_end;
  std::vector<std::pair<double, double>> prof;  // (z, P)
  double Psum = 0, rsum = 0, vsum = 0, esum = 0;
  int cnt = 0;
  for (std::size_t p = 0; p < ps.size(); ++p) {
    const double z = ps.x[3 * p + 2];
    if (z < 0) continue;
    const double P = -(ps.stress[6 * p] + ps.stress[6 * p + 1] + ps.stress[6 * p + 2]) / 3;
    prof.push_back({z, P});
    if (z > 0.25 * zs_guess && z < 0.75 * zs_guess) {
      Psum += P;
      rsum += ps.mass[p] / ps.volume[p];
      vsum += ps.v[3 * p + 2];
      esum += ps.energy[p];
      ++cnt;
    }
  }
  r.P = Psum / cnt;
  r.rho = rsum / cnt;
  r.v_behind = vsum / cnt;
  r.e_behind = esum / cnt;
  const Exact ex = hugoniot(mpmfrag::TillotsonParams{}, up);
  const double zs_exact = (ex.Us - up) * t_end;
  // cell-binned profile (mass-weighted = particle mean, equal masses), as recommended for MPM
  // shock comparisons (particle-level pressure scatter is not resolved by the grid)
  const int nbins = cells;
  std::vector<double> bsum(nbins, 0.0);
  std::vector<int> bcnt(nbins, 0);
  for (const auto& zp : prof) {
    const int b = static_cast<int>(zp.first / h);
    if (b >= 0 && b < nbins) {
      bsum[b] += zp.second;
      ++bcnt[b];
    }
  }
  // shock position: where the binned P first drops below P/2 going outward (linear interpolation)
  double zs = 0, zprev = 0, pprev = -1;
  for (int b = 0; b < nbins; ++b) {
    if (!bcnt[b]) continue;
    const double zc = (b + 0.5) * h, pb = bsum[b] / bcnt[b];
    if (pprev >= 0.5 * r.P && pb < 0.5 * r.P && zc > 0.5 * zs_guess) {
      zs = zprev + (zc - zprev) * (pprev - 0.5 * r.P) / (pprev - pb);
      break;
    }
    zprev = zc;
    pprev = pb;
  }
  r.shock_speed_lab = zs / t_end;
  double l1 = 0;
  int nb = 0;
  for (int b = 0; b < nbins; ++b) {
    if (!bcnt[b]) continue;
    const double zc = (b + 0.5) * h;
    l1 += std::fabs(bsum[b] / bcnt[b] - (zc < zs_exact ? ex.P : 0.0)) / ex.P;
    ++nb;
  }
  r.l1 = l1 / nb;
  return r;
}

}  // namespace shock
