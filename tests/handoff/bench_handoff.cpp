/// @file bench_handoff.cpp
/// Hand-off throughput: 10^6 synthetic particles (2 per cell per axis, smooth velocity field),
/// projection + G2P + aggregation + audit, file I/O excluded. Reports particles/s. Three layouts:
/// 0 the regular lattice of a fresh mpm-frag body, in creation order; 1 the same lattice with every
/// particle moved randomly within its sub-cell (positions as after deformation, where the weights'
/// branch regions vary from particle to particle), creation order; 2 layout 1 in the block-sorted
/// order in which mpm-frag writes snapshots after its first step (the realistic input); the
/// projection alone also runs on 3, layout 1 in the hand-off's own cell order (best case).
/// BM_WriteSnapshot / BM_ReadSnapshot: the same snapshot through the HDF5 file contract (atomic
/// write with fsync; read with validation) in MB/s, to compare with the disk's sequential rate
/// (pipelines/handoff/rules.mk runs dd beside it).
#include <benchmark/benchmark.h>
#include <omp.h>
#include <sys/resource.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "common/provenance.hpp"
#include "handoff/audit.hpp"
#include "handoff/invariants.hpp"
#include "handoff/projection.hpp"
#include "handoff/run_handoff.hpp"
#include "particle_sets.hpp"

// 50^3 cells filled with 2^3 particles each = 10^6 particles.
static const common::ParticleSnapshot& snapshot() {
  static const auto s = testsets::filled_box(56, 1.0, 3, 50, 2, 1.0, [](const Eigen::Vector3d& x) {
    return Eigen::Vector3d(std::sin(x.y()), std::cos(x.z()), 3000.0 + x.x());
  });
  return s;
}

static const common::ParticleSnapshot& jittered() {
  static const auto s = [] {
    common::ParticleSnapshot j = snapshot();
    const double spacing = j.grid.cell_size[0] / 2;  // 2 particles per cell per axis
    for (std::size_t p = 0; p < j.count(); ++p) {
      std::uint64_t z = j.id[p] * 3 + 12345;  // splitmix64 keyed by id: u in [-0.45, 0.45)
      for (int d = 0; d < 3; ++d) {
        z += 0x9E3779B97F4A7C15ull;
        std::uint64_t r = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        r = (r ^ (r >> 27)) * 0x94D049BB133111EBull;
        r ^= r >> 31;
        j.position[3 * p + d] += spacing * 0.9 * (static_cast<double>(r >> 11) * 0x1.0p-53 - 0.5);
      }
    }
    return j;
  }();
  return s;
}

/// The particles of `j` sorted by key(position, size) (stable in index).
template <class Key>
static common::ParticleSnapshot sorted_by(const common::ParticleSnapshot& j, Key key_of) {
  std::vector<std::uint32_t> key(j.count()), perm(j.count());
  for (std::size_t p = 0; p < j.count(); ++p) {
    key[p] = key_of(&j.position[3 * p], &j.size[3 * p]);
    perm[p] = static_cast<std::uint32_t>(p);
  }
  std::stable_sort(perm.begin(), perm.end(), [&](std::uint32_t a, std::uint32_t b) { return key[a] < key[b]; });
  common::ParticleSnapshot o = j;
  for (std::size_t q = 0; q < perm.size(); ++q) {
    const std::size_t p = perm[q];
    for (int d = 0; d < 3; ++d) {
      o.position[3 * q + d] = j.position[3 * p + d];
      o.velocity[3 * q + d] = j.velocity[3 * p + d];
      o.size[3 * q + d] = j.size[3 * p + d];
    }
    o.mass[q] = j.mass[p];
    o.volume[q] = j.volume[p];
    o.id[q] = j.id[p];
    o.material[q] = j.material[p];
  }
  return o;
}

// Layout 2: the jittered set in the order mpm-frag writes its snapshots: solver.reorder_every
// (default 25 steps) sorts particles by 4^3-cell block of their first stencil node, stable in
// index (mpm/src/solver/binning.cpp, Solver::reorder), so a snapshot after step 0 is block-sorted.
// Layout 3: the jittered set in the hand-off's own cell order (x fastest), the best case for its
// memory access (a reference for how much the input order costs, not an input users have).
static const common::ParticleSnapshot& mpmfrag_order() {
  static const auto s = [] {
    const common::GridInfo& g = jittered().grid;
    const int nb[3] = {(g.shape[0] + 3) / 4, (g.shape[1] + 3) / 4, (g.shape[2] + 3) / 4};
    return sorted_by(jittered(), [&](const double* x, const double* size) {
      int b[3];
      for (int d = 0; d < 3; ++d)
        b[d] = mpmfrag::axis_weights(mpmfrag::ShapeKind::ugimp, x[d], g.origin[d], g.cell_size[d], 0.5 * size[d]).first / 4;
      return static_cast<std::uint32_t>(b[0] + nb[0] * (b[1] + nb[1] * b[2]));
    });
  }();
  return s;
}
static const common::ParticleSnapshot& cell_order() {
  static const auto s = [] {
    const common::GridInfo& g = jittered().grid;
    return sorted_by(jittered(), [&](const double* x, const double*) {
      int c[3];
      for (int d = 0; d < 3; ++d) c[d] = static_cast<int>(std::floor((x[d] - g.origin[d]) / g.cell_size[d]));
      return static_cast<std::uint32_t>(c[0] + g.shape[0] * (c[1] + g.shape[1] * c[2]));
    });
  }();
  return s;
}

static const common::ParticleSnapshot& layout(std::int64_t k) {
  return k == 0 ? snapshot() : k == 1 ? jittered() : k == 2 ? mpmfrag_order() : cell_order();
}

static void BM_HandOff(benchmark::State& state) {
  const int threads = static_cast<int>(state.range(0));
  const auto& s = layout(state.range(1));
  handoff::HandoffConfig c;
  c.input = "bench";
  c.method = handoff::HandoffMethod::paper;
  omp_set_num_threads(threads);
  for (auto _ : state) {
    auto o = handoff::hand_off(s, c);
    benchmark::DoNotOptimize(o.result.spheres.velocity.data());
  }
  state.counters["particles_per_s"] = benchmark::Counter(static_cast<double>(s.count()), benchmark::Counter::kIsIterationInvariantRate);
  state.counters["particles_per_s_per_core"] =
      benchmark::Counter(static_cast<double>(s.count()) / threads, benchmark::Counter::kIsIterationInvariantRate);
  state.counters["threads"] = threads;
  state.counters["layout"] = static_cast<double>(state.range(1));
  rusage ru{};
  getrusage(RUSAGE_SELF, &ru);
  state.counters["peak_rss_MB"] = ru.ru_maxrss / 1024.0;  // whole process, input arrays included
}
BENCHMARK(BM_HandOff)->ArgsProduct({{1, 2}, {0, 1, 2}})->ArgNames({"threads", "layout"})->Unit(benchmark::kMillisecond)->UseRealTime();

// The phases of BM_HandOff on their own: the projection (binning, P2G, G2P, cell averages, id
// map; layouts 0-3, 1 and 2 threads), one audit pass over the particles (compensated sums of M, X,
// P, K, L), and the audit's minimum gap between the spheres.
static void BM_Projection(benchmark::State& state) {
  const auto& s = layout(state.range(1));
  handoff::ProjectionOptions opt;
  omp_set_num_threads(static_cast<int>(state.range(0)));
  for (auto _ : state) {
    auto r = handoff::project_to_spheres(s, opt, "bench");
    benchmark::DoNotOptimize(r.spheres.velocity.data());
  }
  state.counters["particles_per_s"] = benchmark::Counter(static_cast<double>(s.count()), benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_Projection)->ArgsProduct({{1, 2}, {0, 1, 2, 3}})->ArgNames({"threads", "layout"})->Unit(benchmark::kMillisecond)->UseRealTime();

// The projection with the portable build of the inner loops (what CPUs without AVX2 run; on
// those, BM_Projection measures the same thing), layout 2.
static void BM_ProjectionPortable(benchmark::State& state) {
  const auto& s = layout(2);
  handoff::ProjectionOptions opt;
  opt.vector_kernels = false;
  omp_set_num_threads(static_cast<int>(state.range(0)));
  for (auto _ : state) {
    auto r = handoff::project_to_spheres(s, opt, "bench");
    benchmark::DoNotOptimize(r.spheres.velocity.data());
  }
  state.counters["particles_per_s"] = benchmark::Counter(static_cast<double>(s.count()), benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_ProjectionPortable)->Arg(1)->Arg(2)->ArgName("threads")->Unit(benchmark::kMillisecond)->UseRealTime();

static void BM_SphereGap(benchmark::State& state) {
  omp_set_num_threads(1);
  const auto r = handoff::project_to_spheres(snapshot(), handoff::ProjectionOptions{}, "bench");
  for (auto _ : state) benchmark::DoNotOptimize(handoff::min_sphere_gap(r));
  state.counters["spheres"] = static_cast<double>(r.spheres.count());
}
BENCHMARK(BM_SphereGap)->Unit(benchmark::kMillisecond)->UseRealTime();

// BM_AuditPass on 2 threads is also the machine's reference for thread scaling: fixed chunks,
// no serial part, streaming reads of 56 B per particle (speed-up 2 would be ideal).
static void BM_AuditPass(benchmark::State& state) {
  const auto& s = snapshot();
  omp_set_num_threads(static_cast<int>(state.range(0)));
  for (auto _ : state) {
    auto inv = handoff::compute_invariants(s.count(), s.position.data(), s.velocity.data(), s.mass.data());
    benchmark::DoNotOptimize(inv.mass);
  }
  state.counters["particles_per_s"] = benchmark::Counter(static_cast<double>(s.count()), benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_AuditPass)->Arg(1)->Arg(2)->ArgName("threads")->Unit(benchmark::kMillisecond)->UseRealTime();

static std::string bench_file() {
  return (std::filesystem::temp_directory_path() / "bench_handoff_snapshot.h5").string();
}

static void BM_WriteSnapshot(benchmark::State& state) {
  const auto& s = snapshot();
  const common::Provenance prov{"bench", "0", "0", "bench", ""};
  for (auto _ : state) common::write_particle_snapshot(bench_file(), s, prov);
  const double mb = std::filesystem::file_size(bench_file()) / 1e6;
  state.counters["file_MB"] = mb;
  state.counters["MB_per_s"] = benchmark::Counter(mb, benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_WriteSnapshot)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);

static void BM_ReadSnapshot(benchmark::State& state) {
  if (!std::filesystem::exists(bench_file()))
    common::write_particle_snapshot(bench_file(), snapshot(), common::Provenance{"bench", "0", "0", "bench", ""});
  for (auto _ : state) {
    auto r = common::read_particle_snapshot(bench_file());
    benchmark::DoNotOptimize(r.position.data());
  }
  const double mb = std::filesystem::file_size(bench_file()) / 1e6;
  state.counters["file_MB"] = mb;
  state.counters["MB_per_s"] = benchmark::Counter(mb, benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_ReadSnapshot)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);
BENCHMARK_MAIN();
