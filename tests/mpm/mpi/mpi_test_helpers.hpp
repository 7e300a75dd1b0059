/// @file mpi_test_helpers.hpp
/// Helpers of the MPI tests of mpm-frag (test_mpm_mpi.cpp): rank queries, stepping a serial or a
/// distributed run to a time, and the largest per-array difference between two particle sets
/// matched by particle id (every ParticleSet array and every style state field), and the
/// Tonge–Ramesh impact scene shared by test_mpm_mpi.cpp and test_mpm_mpi_restart.cpp, and a
/// directory shared by the ranks.
#pragma once
#include <gtest/gtest.h>
#include <mpi.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
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

/// The ORB (mpm/mpi/orb.hpp) of `ps` weighted by w (empty: 1 per particle) for `ranks` ranks,
/// computed here from the whole set: what every DomainSolver must arrive at.
inline mpi::Orb orb_of(const common::GridInfo& g, int ranks, int min_width, const ParticleSet& ps,
                       const std::vector<long long>& w = {}) {
  mpi::Orb layout;
  layout.shape = g.shape;
  layout.halo = 2;
  layout.min_width = min_width;
  return mpi::orb_of_particles(layout, g, ranks, [&](const auto& add) {
    for (std::size_t p = 0; p < ps.size(); ++p) add(&ps.x[3 * p], w.empty() ? 1 : w[p]);
  });
}

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

/// Every particle array and every style state array of two sets, bit for bit (repeated runs).
inline void expect_same_bits(const ParticleSet& a, const std::vector<MaterialSlot>& ma, const ParticleSet& b,
                             const std::vector<MaterialSlot>& mb) {
  ASSERT_EQ(a.size(), b.size());
  ParticleSet::for_each_array([&](const auto& arr) {
    const auto& va = a.*arr.member;
    const auto& vb = b.*arr.member;
    ASSERT_EQ(va.size(), vb.size()) << arr.info.name;
    EXPECT_EQ(0, std::memcmp(va.data(), vb.data(), va.size() * sizeof(va[0]))) << arr.info.name;
  });
  ASSERT_EQ(ma.size(), mb.size());
  for (std::size_t m = 0; m < ma.size(); ++m)
    for (std::size_t f = 0; f < ma[m].state.size(); ++f)
      EXPECT_TRUE(ma[m].state[f].size() == mb[m].state[f].size() &&
                  std::memcmp(ma[m].state[f].data(), mb[m].state[f].data(), ma[m].state[f].size() * sizeof(double)) == 0)
          << ma[m].style->state_fields[f].name;
}

/// The agreement of a Tonge–Ramesh impact with one rank (measured on 2 and 3 ranks after ~250
/// steps: v 2.2e-12 m/s, x 7e-17 m, stress 1.6e-4 Pa, damage 3.3e-12, energy 8.4e-10 J/kg):
/// tolerances ~50-200x those, scaled by the impact speed U, the cell h, the shock stress
/// rho U c (2700 x U x 6000 Pa) and U^2.
inline void expect_impact_agreement(const Diff& df, double U, double h) {
  EXPECT_LT(df.max.at("v"), 1e-12 * U);
  EXPECT_LT(df.max.at("x"), 1e-12 * h);
  EXPECT_LT(df.max.at("stress"), 1e-12 * 2700.0 * U * 6000.0);
  EXPECT_LT(df.max.at("state:damage"), 1e-9);
  EXPECT_LT(df.max.at("energy"), 1e-12 * U * U);
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
// inside it, the boxes balancing the particle count): hundreds of particles change ranks.
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
