/// @file test_memory_bounds.cpp
/// The memory estimate of a scene (memory_bounds.hpp) against what build_setup and the Solver
/// really allocate, and its refusal (InputError naming the keys and the sizes) when the machine
/// has less memory than the scene needs.
#include <gtest/gtest.h>
#include <sys/resource.h>

#include <algorithm>
#include <limits>

#include "common/status.hpp"
#include "mpm/memory_bounds.hpp"
#include "mpm/scene_setup.hpp"
#include "mpm/shape_functions.hpp"

using namespace mpmfrag;

namespace {
common::Scene scene(const std::string& grid) {
  return common::Scene::parse(mpm_schema(), grid + R"(
[time]
end = 1e-4
[[material]]
name = "m"
model = "elastic"
density = 1000.0
bulk_modulus = 1e7
shear_modulus = 1e6
[[body]]
material = "m"
shape = "sphere"
center = [0.1, 0.05, 0.05]
radius = 0.037
ppc = 3
[[body]]
material = "m"
shape = "box"
min = [0.01, 0.01, 0.01]
max = [0.043, 0.03, 0.09]
)",
                              "t.toml");
}
const std::string kGrid = "[grid]\ndomain_min = [0.0, 0.0, 0.0]\ndomain_max = [0.2, 0.1, 0.1]\ncell_size = 0.007\n";
}  // namespace

TEST(MemoryBounds, EstimateMatchesWhatTheRunAllocates) {
  const common::Scene sc = scene(kGrid);
  const MemoryEstimate e = estimate_memory(sc);
  mpmfrag::Setup st = build_setup(sc);
  EXPECT_EQ(e.grid_nodes, static_cast<double>(node_count(st.grid)));  // ceil(0.2/0.007)=29 cells: 34 x 20 x 20 nodes
  EXPECT_EQ(e.grid_nodes, 34.0 * 20 * 20);
  const double n = static_cast<double>(st.particles.size());
  EXPECT_NEAR(e.particles / n, 1.0, 0.05) << e.particles << " estimated, " << n << " generated";
  const double per_particle = e.particle_bytes / e.particles;
  // every array counted, the optional q (artificial viscosity, off here) too: an upper bound
  EXPECT_NEAR(per_particle, 2 * (static_cast<double>(st.particles.bytes()) / n + 8) + 96, 1e-9);
}

TEST(MemoryBounds, SceneLargerThanTheMemoryIsRefusedNamingKeysAndSizes) {
  const common::Scene sc = scene(kGrid);
  EXPECT_NO_THROW(check_memory(sc, 1e9));
  try {
    check_memory(sc, 1e5);  // 100 kB "machine"
    FAIL() << "expected InputError";
  } catch (const common::InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("t.toml: grid.cell_size: the grid over grid.domain_min .. grid.domain_max at this cell size has "
                     "1.36e+04 nodes (0.0012 GB)"),
              std::string::npos)
        << m;
    EXPECT_NE(m.find("more than the 0.0001 GB of memory available"), std::string::npos) << m;
  }
  // on MPI ranks a node holds its ranks' share: 8 ranks, 1 per node, fit where one rank does not
  const double need = estimate_memory(sc).total();
  EXPECT_THROW(check_memory(sc, 0.5 * need), common::InputError);
  EXPECT_NO_THROW(check_memory(sc, 0.5 * need, builtin_materials(), 8, 1));
  EXPECT_NO_THROW(check_memory(sc, 0.5 * need, builtin_materials(), 8, 3));
  try {
    check_memory(sc, 0.5 * need, builtin_materials(), 8, 8);  // all 8 on one node: the whole scene
    FAIL() << "expected InputError";
  } catch (const common::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("for the 8 of 8 MPI ranks on this node"), std::string::npos) << e.what();
  }
  // the process limit (RLIMIT_AS) and the node's memory make up what one process may use
  EXPECT_EQ(available_memory(), std::min(node_memory(), process_memory_limit()));
  EXPECT_GT(node_memory(), 0.0);
  rlimit rl{};  // (not lowered here: a sanitizer's shadow mappings would exceed any small limit)
  ASSERT_EQ(getrlimit(RLIMIT_AS, &rl), 0);
  EXPECT_EQ(process_memory_limit(), rl.rlim_cur == RLIM_INFINITY ? std::numeric_limits<double>::infinity()
                                                                  : static_cast<double>(rl.rlim_cur));
  // 4096 cells per axis (the old per-axis limit) on a real machine: 6e12 bytes of grid alone
  const common::Scene huge = scene("[grid]\ndomain_min = [0.0, 0.0, 0.0]\ndomain_max = [4.096, 4.096, 4.096]\ncell_size = 0.001\n");
  EXPECT_GT(estimate_memory(huge).grid_bytes, 6e12);
  EXPECT_THROW(check_memory(huge), common::InputError);
}
