/// @file bench_mpm.cpp
/// Benchmark (label bench): microseconds per particle-step per core for an elastic uGIMP sphere
/// (>= 2e5 particles) and a Tillotson impact, on 1 and 2 threads, plus bytes per particle.
/// Run: build-mpm/tests/mpm/mpm_bench --benchmark_repetitions=3 --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>
#include <omp.h>

#include <chrono>
#include <ctime>
#include <memory>

#include "test_helpers.hpp"

using namespace mpmfrag;

namespace {

std::string sphere_scene(const char* scheme, const char* shape) {
  // R/h = 19, 2 ppc per axis -> about 2.3e5 particles
  return std::string(R"(
[grid]
domain_min = [-0.22, -0.22, -0.22]
domain_max = [0.22, 0.22, 0.22]
cell_size = 0.01
[solver]
scheme = ")") + scheme + R"("
shape = ")" + shape + R"("
courant = 0.3
[time]
end = 1.0
[[material]]
name = "rock"
model = "elastic"
density = 2700.0
bulk_modulus = 26.7e9
shear_modulus = 22.7e9
[[body]]
material = "rock"
shape = "sphere"
center = [0.0, 0.0, 0.0]
radius = 0.19
velocity = [10.0, 0.0, 0.0]
angular_velocity = [0.0, 0.0, 100.0]
)";
}

std::string impact_scene(const char* scheme) {
  return std::string(R"(
[grid]
domain_min = [-0.22, -0.22, -0.22]
domain_max = [0.22, 0.22, 0.26]
cell_size = 0.01
[solver]
scheme = ")") + scheme + R"("
courant = 0.3
artificial_viscosity.enabled = true
[time]
end = 1.0
[[material]]
name = "basalt"
model = "tillotson"
density = 2700.0
[[body]]
material = "basalt"
shape = "sphere"
center = [0.0, 0.0, 0.0]
radius = 0.19
[[body]]
material = "basalt"
shape = "sphere"
center = [0.0, 0.0, 0.215]
radius = 0.024
velocity = [0.0, 0.0, -5000.0]
)";
}

void run_bench(benchmark::State& state, const std::string& toml) {
  const int threads = static_cast<int>(state.range(0));
  omp_set_num_threads(threads);
  Solver s = mpmtest::solver_from(mpmtest::setup_from(toml));
  for (int i = 0; i < 3; ++i) s.step(s.stable_dt());  // warm-up (allocations, first sort)
  const double n = static_cast<double>(s.particles().size());
  double wall = 0, cpu = 0;
  for (auto _ : state) {
    const auto w0 = std::chrono::steady_clock::now();
    const std::clock_t c0 = std::clock();  // process CPU time (all threads)
    s.step(s.stable_dt());
    cpu += static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;
    wall += std::chrono::duration<double>(std::chrono::steady_clock::now() - w0).count();
  }
  const double psteps = n * static_cast<double>(state.iterations());
  state.counters["particles"] = n;
  state.counters["bytes_per_particle"] = s.bytes_per_particle();
  // wall-clock us per particle-step, and per core (x threads)
  state.counters["us_per_pstep"] = 1e6 * wall / psteps;
  state.counters["us_per_pstep_core"] = 1e6 * wall * threads / psteps;
  // process CPU time per particle-step (= per-core cost; insensitive to other load on the machine)
  state.counters["cpu_us_per_pstep_core"] = 1e6 * cpu / psteps;
}

}  // namespace

static void BM_ElasticSphere_USL(benchmark::State& st) { run_bench(st, sphere_scene("usl", "ugimp")); }
static void BM_ElasticSphere_MUSL(benchmark::State& st) { run_bench(st, sphere_scene("musl", "ugimp")); }
static void BM_ElasticSphere_USF(benchmark::State& st) { run_bench(st, sphere_scene("usf", "ugimp")); }
static void BM_ElasticSphere_Linear_USL(benchmark::State& st) { run_bench(st, sphere_scene("usl", "linear")); }
static void BM_TillotsonImpact_MUSL(benchmark::State& st) { run_bench(st, impact_scene("musl")); }
static void BM_TillotsonImpact_USL(benchmark::State& st) { run_bench(st, impact_scene("usl")); }

BENCHMARK(BM_ElasticSphere_USL)->Arg(1)->Arg(2)->Iterations(20)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ElasticSphere_MUSL)->Arg(1)->Arg(2)->Iterations(20)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ElasticSphere_USF)->Arg(1)->Arg(2)->Iterations(20)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ElasticSphere_Linear_USL)->Arg(1)->Arg(2)->Iterations(20)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_TillotsonImpact_MUSL)->Arg(1)->Arg(2)->Iterations(20)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_TillotsonImpact_USL)->Arg(1)->Arg(2)->Iterations(20)->UseRealTime()->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
