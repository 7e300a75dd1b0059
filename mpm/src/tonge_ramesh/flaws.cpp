/// @file flaws.cpp
/// Bounded-Pareto flaw sampling (see flaws.hpp for the equations; PTR `initalizeFlawDist`
/// RandomizeMethod 7 and the `pareto_*` moment helpers; Tonge 2015 ARL-SR-0344 §3).
#include "mpm/tonge_ramesh/flaws.hpp"

#include <algorithm>
#include <cmath>

#include "common/rng.hpp"

namespace mpmfrag::tonge_ramesh {

double pareto_cdf(const FlawPopulation& f, double s) {
  if (s <= f.s_min) return 0.0;
  if (s >= f.s_max) return 1.0;
  const double a = f.exponent;
  return (1.0 - std::pow(f.s_min / s, a)) / (1.0 - std::pow(f.s_min / f.s_max, a));
}

double pareto_moment(double a, double s_l, double s_h, int n) {
  const double c = std::pow(s_l, a) / (1.0 - std::pow(s_l / s_h, a));
  if (std::abs(a - n) < 1e-8) return c * a * std::log(s_h / s_l);
  return c * a / (a - n) * (std::pow(s_l, n - a) - std::pow(s_h, n - a));
}

double pareto_inverse(double a, double s_l, double s_h, double u) {
  const double Ra = std::pow(s_h / s_l, a);
  return s_h / std::pow(Ra - u * (Ra - 1.0), 1.0 / a);
}

std::vector<double> bin_edges(const FlawPopulation& f) {
  const int N = f.bins;
  std::vector<double> e(N + 1);
  e[0] = f.s_max;
  const double b = f.bin_bias;
  if (b == 1.0) {
    for (int k = 1; k <= N; ++k) e[k] = f.s_max - k * (f.s_max - f.s_min) / N;
  } else if (b > 0) {
    for (int k = 1; k <= N; ++k) {
      const double xi = std::max(1.0 - double(k) / N, 0.0);
      e[k] = f.s_min + std::pow(xi, b) * (f.s_max - f.s_min);
    }
  } else {
    const double beta = -b;
    const double dxi = (std::pow(f.s_max / f.s_min, 1.0 / beta) - 1.0) / N;
    for (int k = 1; k <= N; ++k) e[k] = f.s_max / std::pow(1.0 + k * dxi, beta);
  }
  e[N] = f.s_min;  // exact end point despite round-off
  return e;
}

double sample_flaws(const Params& p, double V, std::uint64_t particle_id,
                    std::uint64_t material_id, double* omega, double* s) {
  double D0 = 0.0;
  int off = 0;
  for (std::size_t ip = 0; ip < p.populations.size(); ++ip) {
    const FlawPopulation& f = p.populations[ip];
    common::KeyedRng rng(p.flaw_seed, particle_id, 1 + material_id * 64 + ip);
    const auto e = bin_edges(f);
    for (int k = 0; k < f.bins; ++k) {
      const double sh = e[k], sl = e[k + 1];
      const double dF = pareto_cdf(f, sh) - pareto_cdf(f, sl);
      if (p.flaw_sampling == FlawSampling::expected) {
        omega[off + k] = f.density * dF;
        s[off + k] = std::cbrt(pareto_moment(f.exponent, sl, sh, 3));
        D0 += omega[off + k] * s[off + k] * s[off + k] * s[off + k];
        continue;
      }
      const double lambda = f.density * V * dF;
      // Poisson count; for astronomically large means (planetary-scale particles, where a uint64
      // would overflow) the relative fluctuation ~lambda^-1/2 < 1e-6 is dropped: n = round(lambda).
      const double n = lambda < 1e12 ? double(rng.poisson(lambda)) : std::floor(lambda + 0.5);
      double sk;
      if (n == 0) {
        sk = 0.5 * (sl + sh);
      } else if (n < 20) {
        double m3 = 0.0;
        for (int i = 0; i < int(n); ++i) {
          const double x = pareto_inverse(f.exponent, sl, sh, rng.uniform());
          m3 += x * x * x;
        }
        sk = std::cbrt(m3 / n);
      } else {
        const double E3 = pareto_moment(f.exponent, sl, sh, 3);
        const double E6 = pareto_moment(f.exponent, sl, sh, 6);
        const double sd = std::sqrt(std::max(E6 - E3 * E3, 0.0) / n);
        double m3 = E3;
        for (int tries = 0; tries < 10; ++tries) {
          const double x = E3 + sd * rng.normal();
          if (x >= sl * sl * sl && x <= sh * sh * sh) {
            m3 = x;
            break;
          }
        }
        sk = std::cbrt(m3);
      }
      omega[off + k] = n / V;
      s[off + k] = sk;
      D0 += omega[off + k] * sk * sk * sk;
    }
    off += f.bins;
  }
  return D0;
}

}  // namespace mpmfrag::tonge_ramesh
