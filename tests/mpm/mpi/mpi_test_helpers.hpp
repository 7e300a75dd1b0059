/// @file mpi_test_helpers.hpp
/// Helpers of the MPI tests of mpm-frag (test_mpm_mpi.cpp): rank queries, stepping a serial or a
/// distributed run to a time, and the largest per-array difference between two particle sets
/// matched by particle id (every ParticleSet array and every style state field), and the
/// Tonge–Ramesh impact scene shared by test_mpm_mpi.cpp and test_mpm_mpi_restart.cpp, and a
/// directory shared by the ranks.
#pragma once
#include <mpi.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "../test_helpers.hpp"
#include "mpm/mpi/domain.hpp"

namespace mpmtest {

using namespace mpmfrag;
using mpmfrag::mpi::DomainSolver;

inline int rank() {
  int r = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &r);
  return r;
}
inline int ranks() {
  int r = 0;
  MPI_Comm_size(MPI_COMM_WORLD, &r);
  return r;
}

/// A directory shared by the ranks (rank 0 makes it), removed at the end of the test.
struct SharedDir {
  std::string path;
  SharedDir() {
    char tmpl[] = "/tmp/mpm_mpi_test.XXXXXX";
    std::string p = rank() == 0 ? std::string(::mkdtemp(tmpl)) : std::string();
    path = mpi::Comm(MPI_COMM_WORLD).bcast(p);
  }
  ~SharedDir() {
    MPI_Barrier(MPI_COMM_WORLD);
    if (rank() == 0) std::filesystem::remove_all(path);
  }
};

inline void run_serial(Solver& s, double t) {
  while (s.time() < t * (1 - 1e-12)) s.step(std::min(s.stable_dt(), t - s.time()));
}
inline void run_domain(DomainSolver& s, double t) {
  while (s.time() < t * (1 - 1e-12)) s.step(std::min(s.stable_dt(), t - s.time()));
}

/// Largest difference of array `name` (per component) between two particle sets matched by id,
/// and of every style state field.
struct Diff {
  std::map<std::string, double> max;
  bool same_ids = true;
};
inline Diff compare(const ParticleSet& a, const std::vector<MaterialSlot>& ma, const ParticleSet& b,
             const std::vector<MaterialSlot>& mb) {
  Diff d;
  std::map<std::uint64_t, std::size_t> ib;
  for (std::size_t p = 0; p < b.size(); ++p) ib[b.id[p]] = p;
  if (a.size() != b.size()) d.same_ids = false;
  for (std::size_t p = 0; p < a.size() && d.same_ids; ++p) {
    const auto it = ib.find(a.id[p]);
    if (it == ib.end() || b.material[it->second] != a.material[p]) {
      d.same_ids = false;
      break;
    }
    const std::size_t q = it->second;
    ParticleSet::for_each_array([&](const auto& arr) {
      const auto& va = a.*arr.member;
      const auto& vb = b.*arr.member;
      if (va.empty() || vb.empty()) return;
      const std::size_t w = static_cast<std::size_t>(arr.info.width);
      double& m = d.max[arr.info.name];
      for (std::size_t c = 0; c < w; ++c)
        m = std::max(m, std::fabs(static_cast<double>(va[w * p + c]) - static_cast<double>(vb[w * q + c])));
    });
    const MaterialSlot& sa = ma[a.material[p]];
    const MaterialSlot& sb = mb[b.material[q]];
    for (std::size_t f = 0; f < sa.state.size(); ++f) {
      const std::size_t nc = static_cast<std::size_t>(sa.style->state_fields[f].ncomp);
      double& m = d.max["state:" + sa.style->state_fields[f].name];
      for (std::size_t c = 0; c < nc; ++c)
        m = std::max(m, std::fabs(sa.state[f][nc * (p - sa.begin) + c] - sb.state[f][nc * (q - sb.begin) + c]));
    }
  }
  return d;
}

// The two materials of the MPI test scenes: a Tonge–Ramesh rock and an elastic solid.
inline const std::string kRockAndSoft = R"(
[[material]]
name = "rock"
model = "tonge_ramesh"
density = 2700.0
[[material]]
name = "soft"
model = "elastic"
density = 1000.0
bulk_modulus = 1e8
shear_modulus = 1e7
)";

// ------------------------------------------------------------------------------------------
// A Tonge–Ramesh rock sphere moving at 150 m/s hit by an elastic sphere moving at -300 m/s
// (tests/common/data/tiny_impact.toml without its outflow body): two materials, the style state,
// scheme midpoint, artificial viscosity. The rock moves 1.8 cells through the cuts (which sit
// inside it, the slabs balancing the particle count): hundreds of particles change ranks.
inline Setup impact_setup() {
  return mpmtest::setup_from(R"(
[grid]
domain_min = [0.0, 0.0, 0.0]
domain_max = [0.2, 0.1, 0.1]
cell_size = 0.01
[solver]
scheme = "midpoint"
flip = 0.99
artificial_viscosity.enabled = true
[time]
end = 2e-4
)" + kRockAndSoft + R"(
[[body]]
material = "rock"
shape = "sphere"
center = [0.07, 0.05, 0.05]
radius = 0.03
velocity = [150.0, 0.0, 0.0]
[[body]]
material = "soft"
shape = "sphere"
center = [0.13, 0.05, 0.05]
radius = 0.012
velocity = [-300.0, 0.0, 0.0]
)");
}
constexpr double kImpactEnd = 1.2e-4;  // the impactor has crossed the cut(s) and hit the rock
inline mpi::DomainOptions impact_options() {
  mpi::DomainOptions o;
  o.rebalance_every = 5;
  o.imbalance_threshold = 1.02;  // low, so that the run rebalances as the impactor changes ranks
  return o;
}

// ------------------------------------------------------------------------------------------
// Outflow removal (grid.outflow = "remove"): two flyers (Tonge–Ramesh rock and elastic) side by
// side along the split axis leave the grid through y+ at 400 m/s next to a resting rock bar;
// removals at 6.9e-5 and 8.2e-5 s.
inline Setup outflow_setup(const std::vector<std::string>& overrides = {}) {
  return mpmtest::setup_from(R"(
[grid]
domain_min = [0.0, 0.0, 0.0]
domain_max = [0.3, 0.06, 0.04]
cell_size = 0.01
outflow = "remove"
[time]
end = 1.0
)" + kRockAndSoft + R"(
[[body]]
material = "rock"
shape = "box"
min = [0.02, 0.01, 0.01]
max = [0.28, 0.03, 0.03]
[[body]]
material = "rock"
shape = "box"
min = [0.02, 0.04, 0.01]
max = [0.14, 0.05, 0.03]
velocity = [0.0, 400.0, 0.0]
[[body]]
material = "soft"
shape = "box"
min = [0.16, 0.04, 0.01]
max = [0.28, 0.05, 0.03]
velocity = [0.0, 400.0, 0.0]
)", overrides);
}
}  // namespace mpmtest
