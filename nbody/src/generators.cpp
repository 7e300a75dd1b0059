/// @file generators.cpp
/// Initial-condition generators (generators.hpp).
#include "ssdem/generators.hpp"

#include <cmath>
#include <unordered_map>
#include <vector>

#include "common/rng.hpp"
#include "common/status.hpp"

namespace ssdem {

Spheres lattice_pile(double R, double s, double rho, double jitter, std::uint64_t seed,
                     const Vec3& centre, std::uint64_t first_id) {
  if (!(R > 0 && s > 0 && rho > 0)) throw common::InputError("lattice_pile: R, s, rho must be > 0");
  Spheres sp;
  const double a = 2.0 * std::sqrt(2.0) * s;  // FCC cube edge for nn distance 2s
  const int n = static_cast<int>(std::ceil(R / a)) + 1;
  const Vec3 basis[4] = {Vec3(0, 0, 0), Vec3(0.5, 0.5, 0), Vec3(0.5, 0, 0.5), Vec3(0, 0.5, 0.5)};
  std::uint64_t id = first_id;
  for (int i = -n; i <= n; ++i)
    for (int j = -n; j <= n; ++j)
      for (int k = -n; k <= n; ++k)
        for (const auto& b : basis) {
          const Vec3 p = a * (Vec3(i, j, k) + b);
          if (p.norm() + s > R) continue;
          common::KeyedRng rng(seed, id, 7);
          const double r = s * (1.0 - jitter * rng.uniform());
          const double m = rho * 4.0 / 3.0 * M_PI * r * r * r;
          sp.push(id, centre + p, Vec3::Zero(), Vec3::Zero(), m, r);
          ++id;
        }
  return sp;
}

Spheres random_cloud(std::size_t n, double R, double s, double rho, std::uint64_t seed,
                     const Vec3& centre, std::uint64_t first_id) {
  if (static_cast<double>(n) * s * s * s > 0.3 * R * R * R)
    throw common::InputError("random_cloud: too many spheres for the ball (filling > 30 %)");
  Spheres sp;
  const double m = rho * 4.0 / 3.0 * M_PI * s * s * s;
  // hash grid of cell size 2s: a new sphere can only overlap spheres in the 27 cells around it
  const double cs = 2.0 * s;
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> grid;
  auto key = [&](long long i, long long j, long long k) {
    return (static_cast<std::uint64_t>(i + (1 << 20)) << 42) |
           (static_cast<std::uint64_t>(j + (1 << 20)) << 21) | static_cast<std::uint64_t>(k + (1 << 20));
  };
  std::uint64_t tries = 0;
  for (std::size_t q = 0; q < n; ++q) {
    const std::uint64_t id = first_id + q;
    common::KeyedRng rng(seed, id, 11);
    for (;;) {
      if (++tries > 1000 * n + 1000) throw common::InputError("random_cloud: placement failed");
      Vec3 p(2 * rng.uniform() - 1, 2 * rng.uniform() - 1, 2 * rng.uniform() - 1);
      if (p.norm() > 1.0) continue;
      p *= (R - s);
      const long long ci = static_cast<long long>(std::floor(p.x() / cs));
      const long long cj = static_cast<long long>(std::floor(p.y() / cs));
      const long long ck = static_cast<long long>(std::floor(p.z() / cs));
      bool ok = true;
      for (long long a = -1; a <= 1 && ok; ++a)
        for (long long b = -1; b <= 1 && ok; ++b)
          for (long long c = -1; c <= 1 && ok; ++c) {
            auto it = grid.find(key(ci + a, cj + b, ck + c));
            if (it == grid.end()) continue;
            for (std::uint32_t o : it->second)
              if ((sp.x[o] - centre - p).squaredNorm() < 4 * s * s) {
                ok = false;
                break;
              }
          }
      if (!ok) continue;
      grid[key(ci, cj, ck)].push_back(static_cast<std::uint32_t>(sp.size()));
      sp.push(id, centre + p, Vec3::Zero(), Vec3::Zero(), m, s);
      break;
    }
  }
  return sp;
}

void append_body(Spheres& a, const Spheres& b, const Vec3& shift, const Vec3& velocity) {
  std::uint64_t next = 0;
  for (auto id : a.id) next = std::max(next, id + 1);
  const std::size_t first = a.size();
  a.append(b);
  for (std::size_t i = 0; i < b.size(); ++i) {
    a.id[first + i] = next + i;
    a.x[first + i] += shift;
    a.v[first + i] += velocity;
  }
}

Spheres plummer(std::size_t n, double M, double a, double G, double s, std::uint64_t seed) {
  Spheres sp;
  const double m = M / static_cast<double>(n);
  Vec3 cx = Vec3::Zero(), cv = Vec3::Zero();
  for (std::size_t i = 0; i < n; ++i) {
    common::KeyedRng rng(seed, i, 3);
    double r;
    do {
      const double X = rng.uniform_open0();
      r = a / std::sqrt(std::pow(X, -2.0 / 3.0) - 1.0);
    } while (!(r < 20 * a));
    auto unit = [&]() {
      const double z = 2 * rng.uniform() - 1, ph = 2 * M_PI * rng.uniform();
      const double q = std::sqrt(1 - z * z);
      return Vec3(q * std::cos(ph), q * std::sin(ph), z);
    };
    const Vec3 x = r * unit();
    double q;
    for (;;) {
      q = rng.uniform();
      const double g = q * q * std::pow(1 - q * q, 3.5);
      if (0.1 * rng.uniform() < g) break;
    }
    const double ve = std::sqrt(2 * G * M / std::sqrt(r * r + a * a));
    const Vec3 v = q * ve * unit();
    sp.push(i, x, v, Vec3::Zero(), m, s);
    cx += m * x;
    cv += m * v;
  }
  cx /= M;
  cv /= M;
  for (std::size_t i = 0; i < n; ++i) {
    sp.x[i] -= cx;
    sp.v[i] -= cv;
  }
  return sp;
}

double total_mass(const Spheres& sp) {
  double M = 0;
  for (double m : sp.m) M += m;
  return M;
}

}  // namespace ssdem
