/// @file test_flaw_blocks.cpp
/// Scale-aware flaw sampling (flaws.hpp, issue 16): block draws shared by the particles of a
/// block and independent of the thread count and the particle order; mean density and damage per
/// bin over many blocks equal to the Pareto values within sampling error (and the block-volume
/// variance); the expected density where a block exceeds the specimen; the specimen-size rule of
/// the populations; identical to per-particle Poisson sampling at planetary cell sizes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <random>
#include <tuple>
#include <vector>

#include "mpm/tonge_ramesh/flaws.hpp"

using namespace mpmfrag::tonge_ramesh;

namespace {
Params small_only() {
  Params p = basalt_el_mir();
  p.populations.resize(1);  // 5 um - 1 mm, eta = 2e12 m^-3, 25 bins
  return p;
}
double bin_density(const FlawPopulation& f, const std::vector<double>& e, int k) {
  return f.density * (pareto_cdf(f, e[k]) - pareto_cdf(f, e[k + 1]));
}
}  // namespace

// Block multiple m of eq. (3): per particle where (dx)^3 n_k >= 1 and dx >= 4 s_h, else the
// smallest cube that satisfies both.
TEST(FlawBlocks, BlockMultipleFollowsCountAndSizeRules) {
  const Params p = basalt_el_mir();
  EXPECT_EQ(block_multiple(p, 2e12, 1e-6, 1e-4), 1);           // 2 flaws per (0.1 mm)^3
  EXPECT_EQ(block_multiple(p, 1e9, 1e-6, 1e-4), 10);           // spacing 1 mm = 10 dx
  EXPECT_EQ(block_multiple(p, 1.001e9, 1e-6, 1e-4), 10);       // spacing just under 1 mm: still 10
  EXPECT_EQ(block_multiple(p, 2e12, 0.6e-4, 1e-4), 3);         // size rule: 4 x 60 um = 2.4 dx
  EXPECT_EQ(block_multiple(p, 0.0, 1e-6, 1e-4), 1);            // empty bin
}

// Every particle of a block carries the same draw; the draws do not depend on the thread count,
// the order in which particles are sampled, or their ids (only on the positions); a block edge
// of m particles holds m^3 particles of the lattice whatever its origin.
TEST(FlawBlocks, BlockDrawsSharedReproducibleThreadAndOrderIndependent) {
  const Params p = small_only();
  const int nb = p.total_bins();
  const double dx = 1e-4, V = dx * dx * dx;
  const int n1 = 24;
  const double origin = -1.2345e-3;  // lattice not aligned with the world-anchored blocks
  const std::size_t n = std::size_t(n1) * n1 * n1;
  std::vector<double> x(3 * n);
  for (std::size_t q = 0; q < n; ++q) {
    x[3 * q] = origin + dx * (q % n1 + 0.5);
    x[3 * q + 1] = origin + dx * ((q / n1) % n1 + 0.5);
    x[3 * q + 2] = origin + dx * (q / (n1 * n1) + 0.5);
  }
  std::vector<double> om1(n * nb), s1(n * nb), om2(n * nb), s2(n * nb);
  for (std::size_t q = 0; q < n; ++q) sample_flaws(p, V, &x[3 * q], q, 0, &om1[q * nb], &s1[q * nb]);
  std::vector<std::size_t> perm(n);
  std::iota(perm.begin(), perm.end(), 0);
  std::shuffle(perm.begin(), perm.end(), std::mt19937(5));
#pragma omp parallel for num_threads(3) schedule(dynamic, 7)
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t q = perm[i];
    sample_flaws(p, V, &x[3 * q], q, 0, &om2[q * nb], &s2[q * nb]);
  }
  EXPECT_EQ(om1, om2);
  EXPECT_EQ(s1, s2);

  const auto e = bin_edges(p.populations[0]);
  int block_bins = 0, shared_checked = 0;
  for (int k = 0; k < nb; ++k) {
    const long m = block_multiple(p, bin_density(p.populations[0], e, k), e[k], dx);
    if (m == 1 || m > 8) continue;
    ++block_bins;
    std::map<std::tuple<long, long, long>, std::pair<std::vector<std::size_t>, double>> blocks;
    for (std::size_t q = 0; q < n; ++q) {
      const double L = m * dx;
      auto& b = blocks[{long(std::floor(x[3 * q] / L)), long(std::floor(x[3 * q + 1] / L)),
                        long(std::floor(x[3 * q + 2] / L))}];
      b.first.push_back(q);
    }
    std::size_t full = 0, distinct = 0;
    double first = -1;
    for (auto& [key, b] : blocks) {
      const std::size_t q0 = b.first.front();
      for (std::size_t q : b.first) {
        ASSERT_EQ(om1[q * nb + k], om1[q0 * nb + k]) << "bin " << k << " m " << m;
        ASSERT_EQ(s1[q * nb + k], s1[q0 * nb + k]) << "bin " << k << " m " << m;
      }
      // interior blocks hold exactly m^3 particles
      if (b.first.size() == std::size_t(m * m * m)) ++full;
      if (first < 0) first = om1[q0 * nb + k];
      distinct += om1[q0 * nb + k] != first;
      ++shared_checked;
    }
    EXPECT_GE(full, std::size_t(std::pow(n1 / m - 1, 3))) << "bin " << k;
    EXPECT_GT(distinct, 0u) << "bin " << k << ": every block got the same count";
  }
  EXPECT_GE(block_bins, 5);  // at 0.1 mm most small-flaw bins are drawn per block
  EXPECT_GT(shared_checked, 100);
}

// Over many independent blocks, the mean omega_k is eta dF_k and the mean omega_k s_k^3 is
// eta dF_k E[s^3 | bin k] (flaws.hpp: E[N]/V_s and Wald's identity), within 4 standard errors
// (~3 % here: a density computed with the particle instead of the block volume is off by m^3 >= 8);
// the variance of omega_k is that of a Poisson count in the block volume, n_k / V_s (a per-
// particle draw would give n_k / V, m^3 times larger).
TEST(FlawBlocks, MeanDensityPerBinOverManyBlocksEqualsPareto) {
  const Params p = small_only();
  const FlawPopulation& f = p.populations[0];
  const int nb = p.total_bins();
  const double dx = 1e-4, V = dx * dx * dx;
  const auto e = bin_edges(f);
  double Lmax = 0;
  for (int k = 0; k < nb; ++k)
    Lmax = std::max(Lmax, dx * block_multiple(p, bin_density(f, e, k), e[k], dx));
  const int N = 20000;
  std::vector<double> sum(nb, 0.0), sum2(nb, 0.0), sum3(nb, 0.0), om(nb), s(nb);
  for (int i = 0; i < N; ++i) {
    // one particle per block for every bin: positions Lmax apart (and off the lattice of blocks)
    const double x[3] = {(i + 0.37) * Lmax, 0.29 * dx, -0.61 * dx};
    sample_flaws(p, V, x, 17, 0, om.data(), s.data());
    for (int k = 0; k < nb; ++k) {
      sum[k] += om[k];
      sum2[k] += om[k] * om[k];
      sum3[k] += om[k] * s[k] * s[k] * s[k];
    }
  }
  int blocks = 0;
  for (int k = 0; k < nb; ++k) {
    const double nk = bin_density(f, e, k);
    const long m = block_multiple(p, nk, e[k], dx);
    const double Vs = std::pow(m * dx, 3), lam = nk * Vs;
    blocks += m > 1;
    const double mean = sum[k] / N;
    EXPECT_NEAR(mean, nk, 4 * std::sqrt(nk / Vs / N)) << "bin " << k << " m " << m;
    const double var = sum2[k] / N - mean * mean;
    const double rel_se_var = std::sqrt((1.0 / lam + 2.0) / N);
    EXPECT_NEAR(var * Vs / nk, 1.0, 5 * rel_se_var) << "bin " << k;
    const double e3 = pareto_moment(f.exponent, e[k + 1], e[k], 3);
    const double e6 = pareto_moment(f.exponent, e[k + 1], e[k], 6);
    EXPECT_NEAR(sum3[k] / N, nk * e3, 4 * std::sqrt(lam * e6 / N) / Vs) << "bin " << k;
  }
  EXPECT_GE(blocks, 20);
}

// Where a bin's block would exceed the specimen, the bin carries its expected density exactly;
// smaller blocks are still drawn.
TEST(FlawBlocks, ExpectedDensityWhereTheBlockExceedsTheSpecimen) {
  Params p = small_only();
  p.specimen_size = 10e-3;
  const FlawPopulation& f = p.populations[0];
  const double dx = 1e-4;
  const auto e = bin_edges(f);
  std::vector<double> om(25), s(25);
  const double x[3] = {1e-3, 2e-3, 0.5e-4};
  sample_flaws(p, dx * dx * dx, x, 3, 0, om.data(), s.data());
  int expected = 0;
  for (int k = 0; k < 25; ++k) {
    const double nk = bin_density(f, e, k);
    if (block_multiple(p, nk, e[k], dx) * dx > p.specimen_size) {
      ++expected;
      EXPECT_DOUBLE_EQ(om[k], nk) << "bin " << k;
      EXPECT_NEAR(s[k], std::cbrt(pareto_moment(f.exponent, e[k + 1], e[k], 3)), 1e-15);
    }
  }
  EXPECT_GE(expected, 1);  // the 0.5-1 mm flaws are ~1 cm apart
  EXPECT_LE(expected, 6);
}

// The basalt preset's 1 cm-80 m population applies to bodies of 1 m and more: a 10 mm disk has
// empty large-flaw bins (and the same small-flaw bins as without the large population); a 25 km
// target carries both, with the large population's density per unit volume.
TEST(FlawBlocks, SpecimenSizeRuleDropsLargeFlawsFromLabSpecimens) {
  Params p = basalt_el_mir();
  std::vector<double> om(50), s(50), om_s(25), s_s(25);
  const double x[3] = {0.0, 0.0, 0.0};
  p.specimen_size = 10e-3;
  sample_flaws(p, 1e-12, x, 9, 0, om.data(), s.data());
  for (int k = 25; k < 50; ++k) EXPECT_EQ(om[k], 0.0) << "bin " << k;
  Params ps = small_only();
  ps.specimen_size = 10e-3;
  sample_flaws(ps, 1e-12, x, 9, 0, om_s.data(), s_s.data());
  for (int k = 0; k < 25; ++k) EXPECT_EQ(om[k], om_s[k]);
  p.specimen_size = 25e3;
  const double Vp = 1e9;  // 1 km particles
  double n_large = 0.0;
  const int N = 200;
  for (int i = 0; i < N; ++i) {
    const double xi[3] = {1000.0 * i, 0.0, 0.0};
    sample_flaws(p, Vp, xi, i, 0, om.data(), s.data());
    for (int k = 25; k < 50; ++k) n_large += om[k];
  }
  EXPECT_NEAR(n_large / N / 250.0, 1.0, 0.01);  // 2.5e11 flaws per particle: ~2e-6 noise
  // the rule is a property of the population: with no specimen size, every population applies
  EXPECT_TRUE(population_applies(p.populations[1], 0.0));
  EXPECT_FALSE(population_applies(p.populations[1], 0.5));
  EXPECT_TRUE(population_applies(p.populations[1], 1.0));
}

// At the demo's particle sizes (1 km target, 0.5 km impactor particles) every bin of both
// populations expects >= 9.8 flaws per particle and is larger than 4 x its flaws, so scale-aware
// sampling is the per-particle Poisson draw, bit for bit; at the paper's 200 m cells the top bins
// of the large population (50-80 m flaws, 0.63 per particle) are drawn per block.
TEST(FlawBlocks, IdenticalToPoissonAtPlanetaryCellSizes) {
  Params sa = basalt_el_mir();
  sa.specimen_size = 25e3;
  Params po = sa;
  po.flaw_sampling = FlawSampling::poisson;
  std::vector<double> a(50), b(50), sa_(50), sb(50);
  for (double dx : {1000.0, 500.0}) {
    for (int k = 0; k < 2; ++k) {
      const auto& f = sa.populations[k];
      const auto e = bin_edges(f);
      for (int j = 0; j < f.bins; ++j)
        EXPECT_EQ(block_multiple(sa, bin_density(f, e, j), e[j], dx), 1) << dx << " " << k << " " << j;
    }
    for (std::uint64_t id = 0; id < 50; ++id) {
      const double x[3] = {dx * id, -3.0 * dx, 7.0 * dx};
      sample_flaws(sa, dx * dx * dx, x, id, 0, a.data(), sa_.data());
      sample_flaws(po, dx * dx * dx, x, id, 0, b.data(), sb.data());
      ASSERT_EQ(a, b) << "dx " << dx << " id " << id;
      ASSERT_EQ(sa_, sb) << "dx " << dx << " id " << id;
    }
  }
  const auto& lg = sa.populations[1];
  const auto e = bin_edges(lg);
  EXPECT_EQ(block_multiple(sa, bin_density(lg, e, 0), e[0], 200.0), 2);
}
