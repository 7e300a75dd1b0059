/// @file bench_damage.cpp
/// Benchmarks of the Tonge–Ramesh style (label bench; run `make -C pipelines damage-bench` or the
/// executable directly). Reported as us per particle-step per core (items/s -> invert).
///  * BM_StyleUpdate/<case>: the batched material update of 4096 particles, single thread, 50 flaw
///    bins (both El Mir Table 1 populations), elastic loading below the growth threshold
///    (case 0: 0.1 mm particles, ~2 flaws each; case 1: 1 mm particles, ~2000 flaws), and during
///    active crack growth with damage sub-stepping (case 2).
///  * BM_DiskStep/<style>: full mpm-frag steps of the reduced Brazilian disk (0.5 mm, ~950
///    particles) with the basalt as tonge_ramesh (0) or as plain tillotson (1): the difference is
///    the share of the step taken by the damage model. On a shared machine use the _cpu counter
///    (process CPU seconds over particle-steps = per-core cost); the run goes through failure, so
///    it includes the crack-growth sub-stepping phase.
#include <benchmark/benchmark.h>
#include <omp.h>

#include <ctime>
#include <vector>

#include "brazilian.hpp"
#include "style_batch.hpp"

namespace {
using namespace mpmfrag;

void BM_StyleUpdate(benchmark::State& st) {
  omp_set_num_threads(1);
  const int c = static_cast<int>(st.range(0));
  const double V = c == 0 ? 1e-12 : 1e-9;
  auto m = make_tonge_ramesh(tonge_ramesh::basalt_el_mir());
  Batch b(4096, V);
  m->initialize(b.b);
  // case 2: preload in tension to just below the largest-flaw onset, then load fast: growth.
  const double rate = c == 2 ? 1e4 : 1e2, dt = 1e-8;
  long steps = 0;
  for (auto _ : st) {
    b.advance(rate, dt);
    benchmark::DoNotOptimize(m->update(b.b));
    ++steps;
    if (c != 2 && steps % 1000 == 0) {  // stay elastic: reset the stretch
      st.PauseTiming();
      for (std::size_t k = 0; k < b.n; ++k) b.F[9 * k] = 1.0;
      std::fill(b.stress.begin(), b.stress.end(), 0.0);
      st.ResumeTiming();
    }
  }
  st.SetItemsProcessed(st.iterations() * static_cast<long>(b.n));
  double D = 0;
  for (std::size_t k = 0; k < b.n; ++k) D += b.state[0][k];
  st.counters["mean_D"] = D / b.n;
  st.counters["us_per_particle_step"] =
      benchmark::Counter(static_cast<double>(st.iterations()) * b.n,
                         benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_StyleUpdate)->Arg(0)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond);

void BM_DiskStep(benchmark::State& st) {
  omp_set_num_threads(static_cast<int>(st.range(1)));
  brazilian::Config c;
  c.h = 0.5e-3;
  c.rate = 1500.0;
  c.basalt_style = st.range(0) == 0 ? "tonge_ramesh" : "tillotson";
  double wall = 0, cpu = 0;
  long psteps = 0;
  for (auto _ : st) {
    const std::clock_t c0 = std::clock();  // process CPU time (all threads): per-core cost
    const auto r = brazilian::run(c);
    cpu += double(std::clock() - c0) / CLOCKS_PER_SEC;
    wall += r.wall_s;
    psteps += r.steps * static_cast<long>(r.particles);
    st.counters["steps"] = r.steps;
    st.counters["particles"] = r.particles;
    st.counters["bytes_per_particle"] = r.bytes_per_particle;
  }
  st.counters["us_per_particle_step_wall"] = 1e6 * wall / psteps;
  st.counters["us_per_particle_step_cpu"] = 1e6 * cpu / psteps;  // per core
}
BENCHMARK(BM_DiskStep)->Args({0, 1})->Args({1, 1})->Args({0, 2})->Args({1, 2})
    ->Unit(benchmark::kMillisecond)->Iterations(1);
}  // namespace

BENCHMARK_MAIN();
