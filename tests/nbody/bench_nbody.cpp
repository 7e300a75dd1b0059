/// @file bench_nbody.cpp
/// Benchmark: self-gravitating gravel-like rubble pile (FCC lattice, every interior sphere in
/// contact with 12 neighbours), 5e4 and 2e5 spheres, 1 and 2 threads, gravity every k steps.
/// Counters: us per particle-step per core (total and split gravity / neighbour search /
/// contacts / integration), contacts per sphere, bytes per sphere. Use the median of repetitions.
#include <benchmark/benchmark.h>
#include <omp.h>

#include <cmath>

#include "ssdem/dt_rule.hpp"
#include "ssdem/generators.hpp"
#include "ssdem/simulation.hpp"

using namespace ssdem;

namespace {
// Pile of ~n spheres of radius 1 m, grain density 2000 kg/m^3, lattice squeezed by 1e-6 s so
// that all lattice neighbours touch; k_n from the rule at 1.2 v_esc, dt = tau/30.
struct Setup {
  Spheres sp;
  SimConfig cfg;
};
Setup make(std::size_t n, int every) {
  const double s = 1.0;
  const double R = s * std::cbrt(static_cast<double>(n) / 0.7405) * 1.0;
  Setup st;
  st.sp = lattice_pile(R, s, 2000.0, 0.0, 1);
  for (auto& x : st.sp.x) x *= 1.0 - 1e-6;  // contacts closed; gravity keeps them
  const double M = total_mass(st.sp), G = 6.674e-11;
  const double vesc = std::sqrt(2 * G * M / R);
  const DtAdvice a = choose_kn_dt(st.sp.m[0], s, 1.2 * vesc, 0.55, 0.01, 30);
  st.cfg.self_gravity = true;
  st.cfg.gravity.G = G;
  st.cfg.gravity_every = every;
  st.cfg.contacts = true;
  st.cfg.contact = gravel_preset(a.kn);
  st.cfg.dt = a.dt;
  return st;
}
}  // namespace

static void BM_RubblePile(benchmark::State& state) {
  const auto n = static_cast<std::size_t>(state.range(0));
  const int threads = static_cast<int>(state.range(1));
  const int every = static_cast<int>(state.range(2));
  omp_set_num_threads(threads);
  Setup s = make(n, every);
  Simulation sim(s.sp, s.cfg);
  sim.run(2 * every);  // warm-up (first neighbour build, tree)
  const PhaseTimes t0 = sim.times();
  std::int64_t steps = 0;
  for (auto _ : state) {
    const int nst = every * std::max(1, 50 / every);
    sim.run(nst);
    steps += nst;
  }
  const PhaseTimes& t1 = sim.times();
  const double ps = static_cast<double>(steps) * static_cast<double>(sim.spheres().size());
  const double core = threads * 1e6 / ps;
  state.counters["N"] = static_cast<double>(sim.spheres().size());
  // wall-clock x threads per particle-step ("per core"), and process CPU time per particle-step
  const double cpu = 1e6 / ps;
  state.counters["wall_us_core"] = ((t1.gravity - t0.gravity) + (t1.neighbours - t0.neighbours) +
                                    (t1.contacts - t0.contacts) + (t1.integrate - t0.integrate)) * core;
  state.counters["cpu_us"] = ((t1.cpu_gravity - t0.cpu_gravity) + (t1.cpu_neighbours - t0.cpu_neighbours) +
                              (t1.cpu_contacts - t0.cpu_contacts) + (t1.cpu_integrate - t0.cpu_integrate)) * cpu;
  state.counters["cpu_us_gravity"] = (t1.cpu_gravity - t0.cpu_gravity) * cpu;
  state.counters["cpu_us_neighbours"] = (t1.cpu_neighbours - t0.cpu_neighbours) * cpu;
  state.counters["cpu_us_contacts"] = (t1.cpu_contacts - t0.cpu_contacts) * cpu;
  state.counters["cpu_us_integrate"] = (t1.cpu_integrate - t0.cpu_integrate) * cpu;
  state.counters["contacts_per_sphere"] = 2.0 * sim.contact_stats().contacts / sim.spheres().size();
  state.counters["bytes_per_sphere"] = sim.bytes_per_sphere();
  state.SetItemsProcessed(steps * static_cast<std::int64_t>(sim.spheres().size()));
}
BENCHMARK(BM_RubblePile)
    ->ArgNames({"N", "threads", "grav_every"})
    ->Args({50000, 1, 1})
    ->Args({50000, 1, 10})
    ->Args({50000, 1, 50})
    ->Args({50000, 2, 50})
    ->Args({200000, 1, 50})
    ->Args({200000, 2, 50})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(3);

BENCHMARK_MAIN();
