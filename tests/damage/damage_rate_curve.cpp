/// @file damage_rate_curve.cpp
/// damage_rate_curve: single-element (one material point, homogeneous uniaxial stress) peak
/// tensile and compressive strength of El Mir (2019) basalt against strain rate.
/// Usage: damage_rate_curve <out.csv> [volume_m3=1e-9] [seeds=5] [rates...]
/// Environment: TR_SAMPLING = flaw_sampling of the point (default poisson: the point's own
/// flaws), TR_SPECIMEN = specimen_size [m] (default 0: every flaw population applies).
/// Writes rows: mode,rate_per_s,seed,peak_stress_Pa,strain_at_peak,final_damage,steps.
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "mpm/tonge_ramesh/element_driver.hpp"

using namespace mpmfrag::tonge_ramesh;

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s out.csv [volume=1e-9] [seeds=5] [rates...]\n", argv[0]);
    return 2;
  }
  const double V = argc > 2 ? std::atof(argv[2]) : 1e-9;
  const int seeds = argc > 3 ? std::atoi(argv[3]) : 5;
  std::vector<double> rates;
  for (int i = 4; i < argc; ++i) rates.push_back(std::atof(argv[i]));
  if (rates.empty()) rates = {1e1, 3e1, 1e2, 3e2, 1e3, 3e3, 1e4, 3e4, 1e5, 1e6};
  Params p = basalt_el_mir();
  p.flaw_sampling = FlawSampling::poisson;
  if (const char* e = std::getenv("TR_SAMPLING")) {
    const auto smp = common::choice_value(kFlawSamplings, e);
    if (!smp) {
      std::fprintf(stderr, "TR_SAMPLING must be scale_aware, poisson or expected, got '%s'\n", e);
      return 2;
    }
    p.flaw_sampling = *smp;
  }
  if (const char* e = std::getenv("TR_SPECIMEN")) p.specimen_size = std::atof(e);
  std::FILE* f = std::fopen(argv[1], "w");
  if (!f) {
    std::perror(argv[1]);
    return 4;
  }
  std::fprintf(f, "mode,rate_per_s,seed,peak_stress_Pa,strain_at_peak,final_damage,steps\n");
  for (const char* mode : {"tension", "compression"}) {
    const double sign = std::string(mode) == "tension" ? 1.0 : -1.0;
    for (double r : rates) {
      for (int s = 0; s < seeds; ++s) {
        const ElementResult res = run_uniaxial_stress(p, V, 1000 + s, sign * r, 2e-6, 0.2);
        if (!res.ok) {
          std::fprintf(stderr, "update failed: %s rate %g seed %d\n", mode, r, s);
          std::fclose(f);
          return 3;
        }
        std::fprintf(f, "%s,%.6g,%d,%.6e,%.6e,%.6e,%ld\n", mode, r, s, res.peak_stress,
                     res.strain_at_peak, res.final_D, res.steps);
        std::fflush(f);
      }
    }
  }
  std::fclose(f);
  return 0;
}
