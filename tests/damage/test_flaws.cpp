/// @file test_flaws.cpp
/// Flaw-population tests: bounded-Pareto moments and per-particle Poisson sampling statistics
/// (tonge-ramesh spec §4; El Mir et al. 2019 Table 1 basalt populations).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "mpm/tonge_ramesh/flaws.hpp"

using namespace mpmfrag::tonge_ramesh;

namespace {
Params single(const FlawPopulation& f) {
  Params p = basalt_el_mir();
  p.populations = {f};
  p.flaw_sampling = FlawSampling::poisson;
  return p;
}
}  // namespace

TEST(Flaws, ParetoMomentsMatchBasaltInitialDamage) {
  const Params p = basalt_el_mir();
  const auto& sm = p.populations[0];
  const auto& lg = p.populations[1];
  // eta E[s^3]: 3.97e-3 (small) and 6.74e-3 (large), spec §4.6.
  EXPECT_NEAR(sm.density * pareto_moment(3, sm.s_min, sm.s_max, 3), 3.97e-3, 0.01e-3);
  EXPECT_NEAR(lg.density * pareto_moment(3, lg.s_min, lg.s_max, 3), 6.74e-3, 0.01e-3);
  // Non-log branch against a midpoint-rule integral of s^1 g(s).
  const double a = 2.5, sl = 1e-5, sh = 1e-3;
  double num = 0.0;
  const int N = 200000;
  const double c = a * std::pow(sl, a) / (1 - std::pow(sl / sh, a));
  for (int i = 0; i < N; ++i) {
    const double x = std::log(sl) + (i + 0.5) * std::log(sh / sl) / N;
    const double s = std::exp(x);
    num += s * c * std::pow(s, -a - 1) * s * std::log(sh / sl) / N;
  }
  EXPECT_NEAR(pareto_moment(a, sl, sh, 1) / num, 1.0, 1e-6);
  // Inverse CDF: F(s(u)) = u.
  FlawPopulation f{sl, sh, a, 1.0, 1, 1.0};
  for (double u : {0.0, 0.1, 0.5, 0.9, 0.999})
    EXPECT_NEAR(pareto_cdf(f, pareto_inverse(a, sl, sh, u)), u, 1e-12);
}

TEST(Flaws, BinEdgesCoverTheRangeMonotonically) {
  for (double bias : {1.0, 2.0, -3.0}) {
    FlawPopulation f{5e-6, 1e-3, 3.0, 2e12, 25, bias};
    const auto e = bin_edges(f);
    ASSERT_EQ(e.size(), 26u);
    EXPECT_DOUBLE_EQ(e.front(), 1e-3);
    EXPECT_DOUBLE_EQ(e.back(), 5e-6);
    for (int k = 0; k < 25; ++k) EXPECT_GT(e[k], e[k + 1]) << "bias " << bias << " bin " << k;
  }
}

// Mean counts per bin, total count and the sum omega s^3 over many particles agree with
// eta V (F(s_h)-F(s_l)) and eta E[s^3] within 4 standard errors; every size lies in its bin.
TEST(Flaws, PoissonRealisationStatistics) {
  FlawPopulation f{5e-6, 1e-3, 3.0, 2e12, 25, -3.0};
  const Params p = single(f);
  const double V = 1e-11;  // 20 flaws expected per particle: exercises both n<20 and n>=20 paths
  const int N = 20000;
  const auto e = bin_edges(f);
  std::vector<double> cnt(25, 0.0), m3(25, 0.0), om(25), s(25);
  double sum_d0 = 0.0, sum_n = 0.0;
  for (int i = 0; i < N; ++i) {
    const double d0 = sample_flaws(p, V, i, 0, om.data(), s.data());
    sum_d0 += d0;
    for (int k = 0; k < 25; ++k) {
      cnt[k] += om[k] * V;
      m3[k] += om[k] * s[k] * s[k] * s[k];
      sum_n += om[k] * V;
      ASSERT_LE(s[k], e[k] * (1 + 1e-12));
      ASSERT_GE(s[k], e[k + 1] * (1 - 1e-12));
    }
  }
  const double lam = f.density * V;
  EXPECT_NEAR(sum_n / N, lam, 4 * std::sqrt(lam / N));
  for (int k = 0; k < 25; ++k) {
    const double lk = lam * (pareto_cdf(f, e[k]) - pareto_cdf(f, e[k + 1]));
    EXPECT_NEAR(cnt[k] / N, lk, 4 * std::sqrt(lk / N) + 1e-12) << "bin " << k;
  }
  // Whole-population initial damage (heavy-tailed: wide error bar) ...
  const double E3 = pareto_moment(3, f.s_min, f.s_max, 3);
  const double E6 = pareto_moment(3, f.s_min, f.s_max, 6);
  const double se = std::sqrt(lam * E6) / V / std::sqrt(double(N));
  EXPECT_NEAR(sum_d0 / N, f.density * E3, 4 * se);
  // ... and per bin, where the third-moment check is sharp.
  int sharp = 0;
  for (int k = 0; k < 25; ++k) {
    const double lk = lam * (pareto_cdf(f, e[k]) - pareto_cdf(f, e[k + 1]));
    const double e3 = pareto_moment(3, e[k + 1], e[k], 3), e6 = pareto_moment(3, e[k + 1], e[k], 6);
    const double mean = lk * e3 / V, sek = std::sqrt(lk * e6 / N) / V;
    EXPECT_NEAR(m3[k] / N, mean, 4 * sek) << "bin " << k;
    if (4 * sek < 0.05 * mean) ++sharp;
  }
  EXPECT_GE(sharp, 8);  // at least 8 bins checked to better than 5 %
}

TEST(Flaws, LargePopulationAndTwoPopulationConcatenation) {
  Params p = basalt_el_mir();
  p.flaw_sampling = FlawSampling::poisson;
  const int nb = p.total_bins();
  ASSERT_EQ(nb, 50);
  std::vector<double> om(nb), s(nb);
  const double V = 1.0;  // 250 large flaws expected per m^3
  const int N = 4000;
  double sum_large = 0.0, sum_small_n = 0.0;
  for (int i = 0; i < N; ++i) {
    sample_flaws(p, V, 1000000 + i, 3, om.data(), s.data());
    for (int k = 25; k < 50; ++k) sum_large += om[k] * s[k] * s[k] * s[k];
    for (int k = 0; k < 25; ++k) sum_small_n += om[k] * V;
  }
  const auto& lg = p.populations[1];
  const double E3 = pareto_moment(3, lg.s_min, lg.s_max, 3);
  const double E6 = pareto_moment(3, lg.s_min, lg.s_max, 6);
  const double se = std::sqrt(lg.density * V * E6) / V / std::sqrt(double(N));
  EXPECT_NEAR(sum_large / N, lg.density * E3, 4 * se);
  EXPECT_NEAR(sum_small_n / N / (2e12 * V), 1.0, 1e-4);
}

TEST(Flaws, ReproducibleKeyedByParticleAndSeed) {
  Params p = basalt_el_mir();
  std::vector<double> a(50), sa(50), b(50), sb(50);
  sample_flaws(p, 1e-9, 42, 0, a.data(), sa.data());
  sample_flaws(p, 1e-9, 42, 0, b.data(), sb.data());
  EXPECT_EQ(a, b);
  EXPECT_EQ(sa, sb);
  sample_flaws(p, 1e-9, 43, 0, b.data(), sb.data());
  EXPECT_NE(a, b);
  p.flaw_seed = 7;
  sample_flaws(p, 1e-9, 42, 0, b.data(), sb.data());
  EXPECT_NE(a, b);
}

// Planetary-scale particles (200 m .. 1 km cells): the expected counts exceed 2^64; sampling must
// stay finite and reproduce eta E[s^3] (relative fluctuations ~1e-10).
TEST(Flaws, HugeParticleVolumes) {
  const Params p = basalt_el_mir();
  std::vector<double> om(50), s(50);
  const double D0 = sample_flaws(p, 1e9, 7, 0, om.data(), s.data());
  double Dsmall = 0.0;
  for (int k = 0; k < 25; ++k) Dsmall += om[k] * s[k] * s[k] * s[k];
  const auto& sm = p.populations[0];
  // small flaws: 2e21 per particle, essentially no sampling noise
  EXPECT_NEAR(Dsmall / (sm.density * pareto_moment(3, sm.s_min, sm.s_max, 3)), 1.0, 1e-6);
  // large flaws: heavy tail, standard error of D0 ~ 3.6e-4 per particle
  EXPECT_NEAR(D0, 3.97e-3 + 6.74e-3, 1.5e-3);
  for (int k = 0; k < 50; ++k) {
    EXPECT_TRUE(std::isfinite(om[k]));
    EXPECT_GT(om[k], 0.0);
  }
}

// Expected-density sampling: every bin carries eta (F(s_h) - F(s_l)) whatever the particle volume,
// so sum omega = eta and sum omega s^3 = eta E[s^3] exactly (basalt: 3.97e-3 + 6.74e-3), and two
// particles of different volume and id get the same bins.
TEST(Flaws, ExpectedDensityIsVolumeIndependentAndExact) {
  Params p = basalt_el_mir();
  p.flaw_sampling = FlawSampling::expected;
  std::vector<double> a(50), sa(50), b(50), sb(50);
  const double D0 = sample_flaws(p, 1e-12, 1, 0, a.data(), sa.data());
  sample_flaws(p, 1e3, 99, 0, b.data(), sb.data());
  EXPECT_EQ(a, b);
  EXPECT_EQ(sa, sb);
  double n_small = 0.0, n_large = 0.0;
  for (int k = 0; k < 25; ++k) n_small += a[k];
  for (int k = 25; k < 50; ++k) n_large += a[k];
  EXPECT_NEAR(n_small / 2e12, 1.0, 1e-12);
  EXPECT_NEAR(n_large / 250.0, 1.0, 1e-12);
  EXPECT_NEAR(D0, 3.97374e-3 + 6.74040e-3, 1e-8);
  const auto& sm = p.populations[0];
  const auto e = bin_edges(sm);
  for (int k = 0; k < 25; ++k) {
    EXPECT_GT(sa[k], e[k + 1]);  // representative size inside its bin
    EXPECT_LT(sa[k], e[k]);
  }
}
