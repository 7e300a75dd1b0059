/// @file convergence_study.cpp
/// Error-vs-cost study driver (pipelines/mpm/rules.mk target mpm-convergence): the axis-aligned
/// manufactured solution and the planar Tillotson shock at 4+ resolutions; one CSV row per run.
/// usage: mpm_convergence <out.csv> [max MMS N (default 32)] [max shock cells (default 400)]
#include <omp.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>

#include "mms_problem.hpp"
#include "shock_problem.hpp"

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s <out.csv> [max_mms_N] [max_shock_cells]\n", argv[0]);
    return 2;
  }
  const int max_n = argc > 2 ? std::atoi(argv[2]) : 32;
  const int max_cells = argc > 3 ? std::atoi(argv[3]) : 400;
  std::ofstream out(argv[1]);
  if (!out) return 4;
  out << "problem,variant,resolution,h_m,particles,steps,wall_s,error,error2,threads\n";
  const int threads = omp_get_max_threads();
  using mpmfrag::Scheme;
  using mpmfrag::ShapeKind;
  struct V { const char* name; ShapeKind k; Scheme s; };
  const V variants[] = {{"ugimp_usl", ShapeKind::ugimp, Scheme::usl},
                        {"ugimp_musl", ShapeKind::ugimp, Scheme::musl},
                        {"ugimp_usf", ShapeKind::ugimp, Scheme::usf},
                        {"linear_usl", ShapeKind::linear, Scheme::usl}};
  for (const V& v : variants)
    for (int N = 4; N <= max_n; N *= 2) {
      const mms::Result r = mms::run(N, v.k, v.s);
      std::printf("mms %-11s N=%3d particles=%7zu steps=%5lld wall=%8.2f s L2=%.4e Linf=%.4e\n", v.name, N,
                  r.particles, static_cast<long long>(r.steps), r.wall_s, r.l2, r.linf);
      std::fflush(stdout);
      out << "mms," << v.name << ',' << N << ',' << 1.0 / N << ',' << r.particles << ',' << r.steps << ','
          << r.wall_s << ',' << r.l2 << ',' << r.linf << ',' << threads << '\n';
      out.flush();
    }
  const shock::Exact ex = shock::hugoniot(mpmfrag::TillotsonParams{}, 2500.0);
  for (int cells = 25; cells <= max_cells; cells *= 2) {
    const shock::Result r = shock::run(cells);
    const double eP = std::fabs(r.P / ex.P - 1), eU = std::fabs(r.shock_speed_lab / (ex.Us - 2500.0) - 1);
    std::printf("shock cells=%4d particles=%6zu steps=%5lld wall=%7.2f s P=%.2f GPa (err %.3f%%) U=%.1f m/s (err %.3f%%) L1=%.4f\n",
                cells, r.particles, static_cast<long long>(r.steps), r.wall_s, r.P / 1e9, 100 * eP,
                r.shock_speed_lab, 100 * eU, r.l1);
    std::fflush(stdout);
    out << "shock,ugimp_musl_av," << cells << ',' << 0.1 / cells << ',' << r.particles << ',' << r.steps << ','
        << r.wall_s << ',' << r.l1 << ',' << std::max(eP, eU) << ',' << threads << '\n';
    out.flush();
  }
  return 0;
}
