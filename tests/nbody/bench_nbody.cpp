/// @file bench_nbody.cpp
/// Benchmark: self-gravitating gravel-like rubble pile (FCC lattice, every interior sphere in
/// contact with 12 neighbours), 5e4 and 2e5 spheres, 1 and 2 threads, gravity every k steps.
/// Counters: us per particle-step per core (total and split gravity / neighbour search /
/// contacts / integration), contacts per sphere, bytes per sphere. Use the median of repetitions.
/// BM_ContactPairs: the pair loop alone on a 10^4-sphere pile (every listed pair in contact, gravel
/// parts), ns per pair evaluation: ContactSystem::compute (packs of kLanes pairs, gathered and
/// scattered) against a loop of the one-pair kernel over the same pairs and a history of its own.
#include <benchmark/benchmark.h>
#include <omp.h>

#include <cmath>

#include <chrono>
#include <algorithm>
#include <random>

#include "ssdem/contacts.hpp"
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
  sim.set_cpu_timing(true);
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

static void BM_ContactPairs(benchmark::State& state) {
  const bool packs = state.range(0) != 0;
  omp_set_num_threads(1);
  Setup s = make(10000, 1);
  if (state.range(1) != 0) {  // spheres in random order (a reaccumulated pile, not a lattice)
    std::vector<std::size_t> perm(s.sp.size());
    for (std::size_t i = 0; i < perm.size(); ++i) perm[i] = i;
    std::shuffle(perm.begin(), perm.end(), std::mt19937_64(3));
    Spheres o;
    for (std::size_t i : perm) o.push(s.sp.id[i], s.sp.x[i], s.sp.v[i], s.sp.w[i], s.sp.m[i], s.sp.s[i]);
    s.sp = o;
  }
  const ContactParams& cp = s.cfg.contact;
  ContactSystem cs(cp, {}, 0.1);
  cs.update_neighbors(s.sp, true);
  std::mt19937_64 g(7);
  std::normal_distribution<double> nd(0.0, 1e-3);
  const std::size_t n = s.sp.size();
  std::vector<Vec3> vp(n), wp(n), F, T;
  for (std::size_t i = 0; i < n; ++i) {
    s.sp.v[i] = Vec3(nd(g), nd(g), nd(g));
    s.sp.w[i] = Vec3(nd(g), nd(g), nd(g));
    vp[i] = s.sp.v[i];
    wp[i] = s.sp.w[i];
  }
  const std::size_t P = cs.pair_count();
  ContactHistory hist(cp.parts);
  hist.assign(P);
  const ContactCoeffs coeffs(cp);
  std::vector<Vec3> pF(P);
  std::int64_t evals = 0;
  double secs = 0.0;
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    if (packs) {
      cs.compute(s.sp, vp, wp, s.cfg.dt, F, T);
    } else {
      dispatch_parts(cp.parts, [&](auto parts) {
        constexpr unsigned PARTS = decltype(parts)::value;
        for (std::size_t p = 0; p < P; ++p) {
          const std::size_t i = cs.pair_i()[p], j = cs.pair_j()[p];
          bool act = hist.active[p];
          PairResult res;
          const double mu = s.sp.m[i] * s.sp.m[j] / (s.sp.m[i] + s.sp.m[j]);
          contact_pair<PARTS, false>(coeffs, s.sp.x[j] - s.sp.x[i], s.sp.s[i], s.sp.s[j], mu, vp[i], vp[j], wp[i],
                                     wp[j], s.sp.v[i], s.sp.v[j], s.sp.w[i], s.sp.w[j], s.cfg.dt, act, hist.row(p), res);
          hist.active[p] = act;
          pF[p] = res.F;
        }
        return 0;
      });
    }
    secs += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    evals += static_cast<std::int64_t>(P);
  }
  state.counters["pairs"] = static_cast<double>(P);
  state.counters["lanes"] = packs ? ContactSystem::lanes() : 1;
  state.counters["ns_per_pair"] = secs * 1e9 / static_cast<double>(evals);
}
BENCHMARK(BM_ContactPairs)->ArgNames({"packs", "shuffled"})->Args({0, 0})->Args({1, 0})->Args({0, 1})->Args({1, 1})->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(1.0);

BENCHMARK_MAIN();
