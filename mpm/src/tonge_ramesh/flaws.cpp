/// @file flaws.cpp
/// Bounded-Pareto flaw sampling per particle or per block of particles (see flaws.hpp for the
/// equations and the derivation; PTR `initalizeFlawDist` RandomizeMethod 7 and the `pareto_*`
/// moment helpers; Tonge 2015 ARL-SR-0344 §3).
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

bool population_applies(const FlawPopulation& f, double specimen) {
  return !(specimen > 0.0) || (specimen >= f.min_specimen && specimen <= f.max_specimen);
}

long block_multiple(const Params& p, double n_k, double s_h, double dx) {
  if (!(n_k > 0.0)) return 1;
  const double edge = std::max(std::cbrt(p.block_count / n_k), p.block_size_factor * s_h);
  const double m = std::ceil(edge / dx * (1.0 - 1e-12));
  // Cap far beyond any domain (4096 cells per axis): the block then holds the whole body.
  return m <= 1.0 ? 1 : static_cast<long>(std::min(m, 1e15));
}

namespace {

/// Count and representative size of one bin realised in a sampling volume with expected count
/// lambda (eq. 2 of flaws.hpp).
void draw_bin(common::KeyedRng& rng, double a, double sl, double sh, double lambda, double& n,
              double& sk) {
  // Poisson count; for astronomically large means (planetary-scale particles, where a uint64
  // would overflow) the relative fluctuation ~lambda^-1/2 < 1e-6 is dropped: n = round(lambda).
  n = lambda < 1e12 ? double(rng.poisson(lambda)) : std::floor(lambda + 0.5);
  if (n == 0) {
    sk = 0.5 * (sl + sh);
  } else if (n < 20) {
    double m3 = 0.0;
    for (int i = 0; i < int(n); ++i) {
      const double x = pareto_inverse(a, sl, sh, rng.uniform());
      m3 += x * x * x;
    }
    sk = std::cbrt(m3 / n);
  } else {
    const double E3 = pareto_moment(a, sl, sh, 3);
    const double E6 = pareto_moment(a, sl, sh, 6);
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
}

/// Key of a block (eq. 4 of flaws.hpp): block indices and edge multiple, or a lone point's id.
std::uint64_t block_key(const double* x, std::uint64_t particle_id, long m, double edge) {
  if (!x) return common::mix64(particle_id ^ 0x5851F42D4C957F2Dull) ^ common::mix64(std::uint64_t(m));
  std::uint64_t k = common::mix64(std::uint64_t(m) + 0x2545F4914F6CDD1Dull);
  for (int d = 0; d < 3; ++d) {
    const double b = std::floor(x[d] / edge);
    k = common::mix64(k ^ static_cast<std::uint64_t>(static_cast<std::int64_t>(b)));
  }
  return k;
}

}  // namespace

double sample_flaws(const Params& p, double V, const double* x, std::uint64_t particle_id,
                    std::uint64_t material_id, double* omega, double* s) {
  double D0 = 0.0;
  int off = 0;
  const double dx = std::cbrt(V);
  for (std::size_t ip = 0; ip < p.populations.size(); ++ip) {
    const FlawPopulation& f = p.populations[ip];
    const std::uint64_t stream = 1 + material_id * 64 + ip;
    common::KeyedRng rng(p.flaw_seed, particle_id, stream);
    const auto e = bin_edges(f);
    const bool applies = population_applies(f, p.specimen_size);
    for (int k = 0; k < f.bins; ++k) {
      const double sh = e[k], sl = e[k + 1];
      const double nk = f.density * (pareto_cdf(f, sh) - pareto_cdf(f, sl));
      double n = 0.0, sk = 0.5 * (sl + sh), Vs = V;
      if (!applies) {
        // population not realised in a body of this size: empty bin
      } else if (p.flaw_sampling == FlawSampling::expected) {
        n = nk;
        Vs = 1.0;
        sk = std::cbrt(pareto_moment(f.exponent, sl, sh, 3));
      } else if (p.flaw_sampling == FlawSampling::poisson) {
        draw_bin(rng, f.exponent, sl, sh, nk * V, n, sk);
      } else {
        const long m = block_multiple(p, nk, sh, dx);
        const double edge = double(m) * dx;
        if (m == 1) {
          draw_bin(rng, f.exponent, sl, sh, nk * V, n, sk);
        } else if (p.specimen_size > 0.0 && edge > p.specimen_size) {
          n = nk;
          Vs = 1.0;
          sk = std::cbrt(pareto_moment(f.exponent, sl, sh, 3));
        } else {
          Vs = edge * edge * edge;
          common::KeyedRng brng(p.flaw_seed ^ 0xB10C5EEDB10C5EEDull, block_key(x, particle_id, m, edge),
                                stream * 64 + static_cast<std::uint64_t>(k));
          draw_bin(brng, f.exponent, sl, sh, nk * Vs, n, sk);
        }
      }
      omega[off + k] = n / Vs;
      s[off + k] = sk;
      D0 += omega[off + k] * sk * sk * sk;
    }
    off += f.bins;
  }
  return D0;
}

}  // namespace mpmfrag::tonge_ramesh
