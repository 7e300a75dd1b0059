/// @file debris_cloud.cpp
/// nbody-debris-cloud: writes the synthetic debris benchmark scene of the neighbour-list study
/// (pipelines/nbody/rules.mk, nbody-debris-bench) as an ssdem.spheres file: a self-gravitating
/// FCC pile of ~n_pile spheres (radius s, jitter 0.05) and n_fly spheres of the same radius flying
/// radially outward from a shell around it (radius 1.05 R .. 3 R, uniform in volume, no overlap
/// with a 2 s grid spacing) at speeds log-uniform in [vmin, vmax] (1-100 m/s by default): a few
/// fast fragments, many slow ones, as after an impact.
/// Usage: nbody-debris-cloud OUT.h5 [n_pile=10000] [n_fly=10000] [vmin=1] [vmax=100] [s=1]
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <unordered_set>

#include "common/provenance.hpp"
#include "ssdem/generators.hpp"
#include "ssdem/io.hpp"

int main(int argc, char** argv) {
  using ssdem::Vec3;
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s OUT.h5 [n_pile] [n_fly] [vmin] [vmax] [s]\n", argv[0]);
    return 2;
  }
  const std::string out = argv[1];
  const double n_pile = argc > 2 ? std::atof(argv[2]) : 1e4;
  const std::size_t n_fly = argc > 3 ? std::strtoull(argv[3], nullptr, 10) : 10000;
  const double vmin = argc > 4 ? std::atof(argv[4]) : 1.0;
  const double vmax = argc > 5 ? std::atof(argv[5]) : 100.0;
  const double s = argc > 6 ? std::atof(argv[6]) : 1.0;
  const double rho = 2000.0;
  // FCC: N ~ 0.7405 (R / s)^3
  const double R = s * std::cbrt(n_pile / 0.7405);
  ssdem::Spheres sp = ssdem::lattice_pile(R, s, rho, 0.05, 1);
  std::mt19937_64 rng(12345);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  const double r0 = 1.05 * R + 2 * s, r1 = 3.0 * R;
  const double g = 2.2 * s;  // occupancy grid: one flyer per cell, so none overlap
  std::unordered_set<std::uint64_t> used;
  std::uint64_t id = sp.size();
  const double m = rho * 4.0 / 3.0 * M_PI * s * s * s;
  while (used.size() < n_fly) {
    Vec3 d(U(rng) * 2 - 1, U(rng) * 2 - 1, U(rng) * 2 - 1);
    const double dn = d.norm();
    if (dn > 1.0 || dn < 1e-6) continue;
    d /= dn;
    const double r = std::cbrt(r0 * r0 * r0 + U(rng) * (r1 * r1 * r1 - r0 * r0 * r0));
    const Vec3 x = r * d;
    const auto q = [&](double v) {
      return static_cast<std::uint64_t>(std::floor(v / g) + (1 << 20));
    };
    const std::uint64_t key = (q(x.x()) << 42) | (q(x.y()) << 21) | q(x.z());
    if (!used.insert(key).second) continue;
    const Vec3 c = (Vec3(std::floor(x.x() / g), std::floor(x.y() / g), std::floor(x.z() / g)) +
                    Vec3::Constant(0.5)) * g;
    const double v = vmin * std::pow(vmax / vmin, U(rng));
    sp.push(id++, c, v * c.normalized(), Vec3::Zero(), m, s);
  }
  ssdem::write_snapshot(out, sp, 0.0, 0, common::Provenance{"nbody-debris-cloud", "", "", "", ""});
  std::printf("%s: %zu spheres (pile R = %.3g m), %zu flying at %.3g-%.3g m/s\n", out.c_str(),
              sp.size(), R, n_fly, vmin, vmax);
  return 0;
}
