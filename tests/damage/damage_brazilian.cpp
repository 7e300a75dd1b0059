/// @file damage_brazilian.cpp
/// damage_brazilian: dynamic Brazilian disk of basalt (see brazilian.hpp).
/// Usage: damage_brazilian <outdir> <rate_per_s> [cell_m=1e-4] [courant=0.3] [seed=1] [style]
///        [sampling=scale_aware|poisson|expected] [flaw_block_count=1] [platen_density=7.85e6]
/// Writes <outdir>/history_<rate>.csv, <outdir>/damage_<rate>.csv and one summary line
/// (rate,eff_rate,peak_F_N,sigma_t_Pa,t_peak_s,steps,particles,wall_s,centre_rate) on stdout:
/// nominal 2v/D, (d sigma_t/dt)/E and (d sigma_xx,centre/dt)/E over the 20-80 % rise.
/// Exit 3 on a numerical failure (the partial history and damage field are written first).
#include <cstdio>
#include <cstdlib>
#include <string>

#include "brazilian.hpp"

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: %s outdir rate [cell=1e-4] [courant=0.3] [seed=1]\n", argv[0]);
    return 2;
  }
  const std::string out = argv[1];
  brazilian::Config c;
  c.rate = std::atof(argv[2]);
  if (argc > 3) c.h = std::atof(argv[3]);
  if (argc > 4) c.courant = std::atof(argv[4]);
  if (argc > 5) c.seed = std::strtoull(argv[5], nullptr, 10);
  if (argc > 6) c.basalt_style = argv[6];  // "tillotson": undamageable reference disk
  if (argc > 7) {
    const auto smp = common::choice_value(mpmfrag::tonge_ramesh::kFlawSamplings, argv[7]);
    if (!smp) {
      std::fprintf(stderr, "sampling must be scale_aware, poisson or expected, got '%s'\n", argv[7]);
      return 2;
    }
    c.sampling = *smp;
  }
  if (argc > 8) c.block_count = std::atof(argv[8]);
  if (argc > 9) c.platen_density = std::atof(argv[9]);
  if (argc > 9 && std::string(argv[9]) == "kinematic") c.kinematic = true, c.platen_density = 7850.0;
  c.progress_every = 500;
  const auto r = brazilian::run(c);
  char tag[64];
  std::snprintf(tag, sizeof tag, "%g_h%g_c%g_s%llu", c.rate, c.h, c.courant, (unsigned long long)c.seed);
  {
    std::FILE* f = std::fopen((out + "/history_" + tag + ".csv").c_str(), "w");
    if (!f) return 4;
    std::fprintf(f, "t_s,F_N,sigma_t_Pa,mean_D,max_D,F_platen_N,sxx_center_Pa\n");
    for (const auto& s : r.history)
      std::fprintf(f, "%.6e,%.6e,%.6e,%.6e,%.6e,%.6e,%.6e\n", s.t, s.F, s.sigma_t, s.meanD,
                   s.maxD, s.F_platen, s.sxx_center);
    std::fclose(f);
  }
  {
    std::FILE* f = std::fopen((out + "/damage_" + tag + ".csv").c_str(), "w");
    if (!f) return 4;
    std::fprintf(f, "x_m,y_m,z_m,D\n");
    for (std::size_t i = 0; i < r.snap_x.size(); ++i)
      std::fprintf(f, "%.5e,%.5e,%.5e,%.5e\n", r.snap_x[i], r.snap_y[i], r.snap_z[i], r.snap_D[i]);
    std::fclose(f);
  }
  std::printf("%g,%g,%.6e,%.6e,%.6e,%lld,%zu,%.2f,%g\n", c.rate, r.effective_rate, r.peak_F,
              r.peak_sigma_t, r.t_peak, (long long)r.steps, r.particles, r.wall_s, r.centre_rate);
  if (r.failed_numerically) {
    std::fprintf(stderr, "numerical failure: %s\n", r.failure.c_str());
    return 3;
  }
  return 0;
}
