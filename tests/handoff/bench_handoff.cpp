// Hand-off throughput: 10^6 synthetic particles (2 per cell per axis, random velocities),
// projection + G2P + aggregation + audit, file I/O excluded. Reports particles/s.
#include <benchmark/benchmark.h>
#include <omp.h>
#include <sys/resource.h>

#include "handoff/run_handoff.hpp"
#include "particle_sets.hpp"

static void BM_HandOff(benchmark::State& state) {
  const int threads = static_cast<int>(state.range(0));
  // 50^3 cells filled with 2^3 particles each = 10^6 particles.
  static const auto s = testsets::filled_box(56, 1.0, 3, 50, 2, 1.0, [](const Eigen::Vector3d& x) {
    return Eigen::Vector3d(std::sin(x.y()), std::cos(x.z()), 3000.0 + x.x());
  });
  handoff::HandoffConfig c;
  c.input = "bench";
  c.method = "paper";
  omp_set_num_threads(threads);
  for (auto _ : state) {
    auto o = handoff::hand_off(s, c);
    benchmark::DoNotOptimize(o.result.spheres.velocity.data());
  }
  state.counters["particles_per_s"] = benchmark::Counter(static_cast<double>(s.count()), benchmark::Counter::kIsIterationInvariantRate);
  state.counters["particles_per_s_per_core"] =
      benchmark::Counter(static_cast<double>(s.count()) / threads, benchmark::Counter::kIsIterationInvariantRate);
  state.counters["threads"] = threads;
  rusage ru{};
  getrusage(RUSAGE_SELF, &ru);
  state.counters["peak_rss_MB"] = ru.ru_maxrss / 1024.0;  // whole process, input arrays included
}
BENCHMARK(BM_HandOff)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_MAIN();
