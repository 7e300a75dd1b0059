/// @file bench_analysis.cpp
/// Benchmarks of the reaccumulation analysis: FOF (cell list) and FOF + bound mass on a
/// reaccumulated-remnant-like set: a ball of touching spheres plus 10 % fragments and singles
/// spread out to 100 remnant radii. Arguments: N, threads.
#include <benchmark/benchmark.h>
#include <omp.h>

#include <cmath>
#include <random>

#include "analysis/bound.hpp"
#include "analysis/fof.hpp"
#include "common/sphere_file.hpp"

namespace {

common::SphereSet make_set(std::size_t n) {
  common::SphereSet s;
  const double r = 100.0;
  const std::size_t n_ball = n * 9 / 10;
  const int k = static_cast<int>(std::ceil(std::cbrt(n_ball * 6 / M_PI))) + 1;
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  auto push = [&](double x, double y, double z, double vx, double vy, double vz) {
    s.id.push_back(s.id.size());
    s.position.insert(s.position.end(), {x, y, z});
    s.velocity.insert(s.velocity.end(), {vx, vy, vz});
    s.spin.insert(s.spin.end(), {0, 0, 0});
    s.mass.push_back(1e10);
    s.radius.push_back(r * (0.9 + 0.1 * u(rng)));
  };
  const double R = k * r;
  for (int i = 0; i < k && s.count() < n_ball; ++i)
    for (int j = 0; j < k && s.count() < n_ball; ++j)
      for (int l = 0; l < k && s.count() < n_ball; ++l) {
        const double x = (2 * i - k) * r, y = (2 * j - k) * r, z = (2 * l - k) * r;
        if (x * x + y * y + z * z <= R * R) push(x, y, z, 0.01 * u(rng), 0.01 * u(rng), 0.01 * u(rng));
      }
  while (s.count() < n) {  // fragments of 1-8 spheres and singles out to 100 R
    const double x = 100 * R * u(rng), y = 100 * R * u(rng), z = 100 * R * u(rng);
    const int m = 1 + static_cast<int>(4 * (u(rng) + 1));
    const double vx = 20 * u(rng), vy = 20 * u(rng), vz = 20 * u(rng);
    for (int q = 0; q < m && s.count() < n; ++q) push(x + 2 * r * q, y, z, vx, vy, vz);
  }
  return s;
}

void BM_Fof(benchmark::State& st) {
  const auto s = make_set(static_cast<std::size_t>(st.range(0)));
  omp_set_num_threads(static_cast<int>(st.range(1)));
  for (auto _ : st) {
    auto f = analysis::friends_of_friends(s.position.data(), s.radius.data(), s.mass.data(), s.count(), 20.0);
    benchmark::DoNotOptimize(f.clump_mass.data());
  }
  st.SetItemsProcessed(st.iterations() * static_cast<std::int64_t>(s.count()));
  st.counters["spheres"] = static_cast<double>(s.count());
}

void BM_FofBound(benchmark::State& st) {
  const auto s = make_set(static_cast<std::size_t>(st.range(0)));
  omp_set_num_threads(static_cast<int>(st.range(1)));
  std::size_t nb = 0;
  for (auto _ : st) {
    auto f = analysis::friends_of_friends(s.position.data(), s.radius.data(), s.mass.data(), s.count(), 20.0);
    auto cp = analysis::clump_properties(s.position.data(), s.velocity.data(), s.mass.data(), s.count(), f);
    auto b = analysis::bound_to_largest(cp, 6.674e-11);
    nb = b.n_bound_clumps;
    benchmark::DoNotOptimize(b.bound_mass);
  }
  st.counters["bound_clumps"] = static_cast<double>(nb);
  st.SetItemsProcessed(st.iterations() * static_cast<std::int64_t>(s.count()));
  st.counters["spheres"] = static_cast<double>(s.count());
}

}  // namespace

BENCHMARK(BM_Fof)->Args({100000, 1})->Args({100000, 2})->Args({1000000, 1})->Args({1000000, 2})
    ->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_FofBound)->Args({100000, 1})->Args({1000000, 1})->Args({1000000, 2})
    ->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_MAIN();
