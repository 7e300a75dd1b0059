/// @file dense_pile.cpp
/// nbody-dense-pile: writes the dense-pile gravity benchmark scene of issue 15
/// (pipelines/nbody, nbody-gravity-bench) as an ssdem.spheres file: the n spheres nearest the
/// centre of a hexagonal-close-packed lattice (ABAB stacking; in-plane spacing d, layer spacing
/// d sqrt(2/3)) with d = (2 - 1e-7) s, so every lattice neighbour overlaps by 1e-7 s, at rest.
/// Prints the contact stiffness and step the benchmark uses: k_n = m v_esc^2 / (0.01 s)^2 (1 %
/// overlap at the pile's escape speed, ssdem.md §1.7) and dt = pi sqrt(m / (2 k_n)) / 30, as
/// "kn=<N/m> dt=<s> vesc=<m/s>" on the last line.
/// Usage: nbody-dense-pile OUT.h5 [n=10000] [s=100] [rho=3500]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numeric>
#include <string>

#include "common/provenance.hpp"
#include "ssdem/io.hpp"
#include "ssdem/spheres.hpp"

int main(int argc, char** argv) {
  using ssdem::Vec3;
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s OUT.h5 [n] [s] [rho]\n", argv[0]);
    return 2;
  }
  const std::string out = argv[1];
  const std::size_t n = argc > 2 ? std::strtoull(argv[2], nullptr, 10) : 10000;
  const double s = argc > 3 ? std::atof(argv[3]) : 100.0;
  const double rho = argc > 4 ? std::atof(argv[4]) : 3500.0;
  if (n < 1 || !(s > 0) || !(rho > 0)) {
    std::fprintf(stderr, "%s: need n >= 1, s > 0, rho > 0\n", argv[0]);
    return 2;
  }
  const double d = (2.0 - 1e-7) * s, dz = d * std::sqrt(2.0 / 3.0);
  // lattice points within a ball a little larger than needed (HCP packing 0.7405 at d = 2 s)
  const double Rb = 1.15 * s * std::cbrt(static_cast<double>(n) / 0.7405) + 2 * d;
  const int kz = static_cast<int>(Rb / dz) + 1, kxy = static_cast<int>(Rb / d) + 2;
  std::vector<Vec3> pts;
  for (int l = -kz; l <= kz; ++l) {
    const bool b = (l & 1) != 0;  // B layers shifted by (d/2, d/(2 sqrt 3))
    for (int j = -kxy; j <= kxy; ++j)
      for (int i = -kxy; i <= kxy; ++i) {
        const Vec3 p(d * (i + 0.5 * j + (b ? 0.5 : 0.0)),
                     d * (std::sqrt(3.0) / 2.0 * j + (b ? 1.0 / (2.0 * std::sqrt(3.0)) : 0.0)), dz * l);
        if (p.norm() <= Rb) pts.push_back(p);
      }
  }
  if (pts.size() < n) {
    std::fprintf(stderr, "%s: lattice too small (%zu < %zu)\n", argv[0], pts.size(), n);
    return 1;
  }
  std::vector<std::size_t> order(pts.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return pts[a].squaredNorm() < pts[b].squaredNorm(); });
  const double m = rho * 4.0 / 3.0 * M_PI * s * s * s;
  ssdem::Spheres sp;
  double R = 0;
  for (std::size_t k = 0; k < n; ++k) {
    sp.push(k, pts[order[k]], Vec3::Zero(), Vec3::Zero(), m, s);
    R = std::max(R, pts[order[k]].norm() + s);
  }
  const double G = 6.674e-11, M = m * static_cast<double>(n);
  const double vesc = std::sqrt(2 * G * M / R);
  const double kn = m * vesc * vesc / (0.01 * s * 0.01 * s);
  const double dt = M_PI * std::sqrt(m / (2 * kn)) / 30.0;
  ssdem::write_snapshot(out, sp, 0.0, 0, common::Provenance{"nbody-dense-pile", "", "", "", ""});
  std::printf("%s: %zu spheres, HCP spacing (2 - 1e-7) s, s = %g m, rho = %g kg/m^3, R = %.6g m\n",
              out.c_str(), n, s, rho, R);
  std::printf("kn=%.17g dt=%.17g vesc=%.17g\n", kn, dt, vesc);
  return 0;
}
