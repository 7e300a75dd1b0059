/// @file test_rate_dependence.cpp
/// Single-element (one material point, homogeneous uniaxial stress) strength against strain rate
/// for El Mir (2019) basalt: the peak tensile and compressive stresses rise monotonically with
/// rate (finite crack speed, Tonge & Ramesh 2016), the quasi-static tensile peak equals the
/// analytic wing-crack onset stress of the particle's largest flaw, and magnitudes are plausible
/// (tension ~ 1/10 of compression, validation-data.md §1.1).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "mpm/tonge_ramesh/element_driver.hpp"
#include "mpm/tonge_ramesh/flaws.hpp"
#include "mpm/tonge_ramesh/micromechanics.hpp"

using namespace mpmfrag::tonge_ramesh;

namespace {
constexpr double kV = 1e-9;  // (1 mm)^3 point: ~2000 small flaws
constexpr std::uint64_t kId = 1000;
const double kRates[] = {1e1, 1e2, 1e3, 1e4, 1e5};
// The point's own flaws, drawn per particle (PTR method 7): the analytic onset below refers to
// the largest flaw of this particle (scale-aware sampling would give a lone point block-drawn
// large flaws whose wings cannot reach D_c within the test).
Params per_particle() {
  Params p = basalt_el_mir();
  p.flaw_sampling = FlawSampling::poisson;
  return p;
}
}  // namespace

TEST(RateDependence, TensileStrengthRisesWithRateFromAnalyticOnset) {
  const Params p = per_particle();
  const Derived d(p);
  // Largest flaw of this particle and its uniaxial-tension onset stress (sigma_a = 0).
  std::vector<double> om(p.total_bins()), s(p.total_bins());
  sample_flaws(p, kV, kId, 0, om.data(), s.data());
  double smax = 0.0;
  for (int k = 0; k < p.total_bins(); ++k)
    if (om[k] > 0) smax = std::max(smax, s[k]);
  double lo = 1e6, hi = 1e10;
  for (int i = 0; i < 200; ++i) {
    const double m = 0.5 * (lo + hi);
    (stress_intensity(p, d, 0.0, m, smax, 0.0) > p.KIc ? hi : lo) = m;
  }
  const double onset = lo;
  double prev = 0.0;
  for (double r : kRates) {
    const ElementResult res = run_uniaxial_stress(p, kV, kId, r, 2e-6, 0.1);
    ASSERT_TRUE(res.ok);
    EXPECT_LT(res.max_lateral_residual, 1e-5);
    EXPECT_GT(res.peak_stress, prev * 1.01) << "rate " << r;
    EXPECT_GE(res.final_D, p.critical_damage - 1e-6) << "rate " << r;  // it did fail
    if (r == 1e1) {
      EXPECT_GE(res.peak_stress / onset, 1.0 - 1e-3);
      EXPECT_LT(res.peak_stress / onset, 1.05);
      EXPECT_GT(res.peak_stress, 20e6);
      EXPECT_LT(res.peak_stress, 150e6);
    }
    prev = res.peak_stress;
  }
  EXPECT_GT(prev / onset, 4.0);  // strong rate hardening by 1e5 1/s
}

TEST(RateDependence, CompressiveStrengthRisesWithRate) {
  const Params p = per_particle();
  std::vector<double> peaks;
  for (double r : kRates) {
    const ElementResult res = run_uniaxial_stress(p, kV, kId, -r, 2e-6, 0.1);
    ASSERT_TRUE(res.ok);
    EXPECT_LT(res.max_lateral_residual, 1e-5);
    EXPECT_GE(res.final_D, p.critical_damage - 1e-6) << "rate " << r;
    if (!peaks.empty()) {
      EXPECT_GT(res.peak_stress, peaks.back() * 1.0005) << "rate " << r;
    }
    peaks.push_back(res.peak_stress);
  }
  const ElementResult t = run_uniaxial_stress(p, kV, kId, 1e1, 2e-6, 0.1);
  // Quasi-static compression/tension ratio of a brittle rock: ~10 (5..20 accepted).
  EXPECT_GT(peaks.front() / t.peak_stress, 5.0);
  EXPECT_LT(peaks.front() / t.peak_stress, 20.0);
  EXPECT_GT(peaks.back() / peaks.front(), 1.5);  // strong rise by 1e5 1/s
}
