/// @file test_mpm_mpi_stiff.cpp
/// Stiff cases of mpm-frag on MPI (label mpi; part of test_mpm_mpi, whose main() initialises MPI):
/// ranks that start without particles, a body flying through the boxes of several ranks and the
/// rebalancing that follows it, against one rank (tolerances as in test_mpm_mpi.cpp: ~1e-12 of
/// each field's scale, mass to N eps, momentum to 1e-12).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

#include "../test_helpers.hpp"
#include "mpi_test_helpers.hpp"

using namespace mpmfrag;
using namespace mpmtest;

namespace {
// A small elastic sphere (3 cells across) flying at 400 m/s (and 30 m/s across) along a
// 30-cell column.
Setup column_setup() {
  return mpmtest::setup_from(R"(
[grid]
domain_min = [0.0, 0.0, 0.0]
domain_max = [0.3, 0.04, 0.04]
cell_size = 0.01
[solver]
scheme = "musl"
[time]
end = 1.0
[[material]]
name = "m"
model = "elastic"
density = 1000.0
bulk_modulus = 1e8
shear_modulus = 1e7
[[body]]
material = "m"
shape = "sphere"
center = [0.05, 0.02, 0.02]
radius = 0.015
velocity = [400.0, 30.0, 0.0]
)");
}
}  // namespace

TEST(MpmMpi, RanksWithoutParticlesAndAFlyingBodyMatchOneRank) {
  // A small elastic sphere (3 cells across) flying at 400 m/s along a 30-cell
  // column: the boxes of the other ranks start empty (every box keeps 4 planes), the sphere
  // crosses into them and the rebalancing follows it.
  const auto setup = column_setup;
  const double t_end = 4e-4;  // 16 cm
  mpi::DomainOptions o;
  o.rebalance_every = 5;
  DomainSolver dom(MPI_COMM_WORLD, setup(), o);
  double n0 = static_cast<double>(dom.local().particles().size());
  const std::vector<double> counts0 = dom.comm().allgather(&n0, 1);
  dom.initialize();
  const Diagnostics d0 = dom.diagnostics();
  // step by step: how often each rank held no particle, and the particles that changed rank
  int empty_steps = 0;
  while (dom.time() < t_end * (1 - 1e-12)) {
    dom.step(std::min(dom.stable_dt(), t_end - dom.time()));
    double n = static_cast<double>(dom.local().particles().size());
    const std::vector<double> c = dom.comm().allgather(&n, 1);
    empty_steps += *std::min_element(c.begin(), c.end()) == 0.0;
  }
  long long moved = dom.stats().migrated;
  dom.comm().sum(&moved, 1);
  const Diagnostics d1 = dom.diagnostics();
  ParticleSet g;
  std::vector<MaterialSlot> gm;
  dom.gather(0, g, gm);
  const long long rebalances = dom.stats().rebalances;
  if (rank() != 0) return;
  int empty = 0;
  for (double c : counts0) empty += c == 0.0;
  // 3 ranks: the cut inside the sphere, the next one 4 planes on, past the sphere: the last rank
  // starts empty (2 ranks split the sphere; the first empties as the sphere flies on)
  if (ranks() >= 3) {
    EXPECT_GE(empty, 1) << "a rank must start without particles";
    EXPECT_GE(empty_steps, 1) << "a rank must step without particles";
  }
  EXPECT_GE(rebalances, 1);
  EXPECT_GT(moved, static_cast<long long>(g.size()) / 2) << "the body must move between ranks";
  Solver ser = mpmtest::solver_from(setup());
  run_serial(ser, t_end);
  const Diagnostics s1 = ser.diagnostics();
  const Diff df = compare(g, gm, ser.particles(), ser.materials());
  ASSERT_TRUE(df.same_ids);
  std::printf("%d ranks: %d empty at start, %d steps with an empty rank, %lld moves, %lld rebalancings; max |diff| vs one rank: v %.3e m/s, x %.3e m, stress %.3e Pa\n",
              ranks(), empty, empty_steps, moved, rebalances, df.max.at("v"), df.max.at("x"), df.max.at("stress"));
  const double U = 400.0, eps_sum = 2.2e-16 * static_cast<double>(g.size()), M = d0.mass;
  EXPECT_LT(df.max.at("v"), 1e-12 * U);
  EXPECT_LT(df.max.at("x"), 1e-12 * 0.01);
  EXPECT_LT(df.max.at("stress"), 1e-12 * 1000.0 * U * 400.0);  // rho U c
  EXPECT_NEAR(d1.mass, s1.mass, eps_sum * M);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(d1.momentum[k], d0.momentum[k], 1e-12 * M * U) << k;
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(d1.momentum[k], s1.momentum[k], 1e-12 * M * U) << k;
}

TEST(MpmMpi, DebrisJumpingEverySlabInOneStepAndACollapseOntoOneRankMatchOneRank) {
  // The same column without rebalancing: after 1e-5 s every particle is moved 0.12 m (12 cells,
  // more than any box; 0.12 m in one step of ~5 us is > 5 km/s) on both the distributed and the
  // serial run. The migration must deliver every particle across all the boxes in one step, the
  // last rank then holds all of them (the collapse onto one rank) and the others none; an
  // explicit rebalancing spreads them again. Fields against one rank as above.
  const auto setup = column_setup;
  const double t_jump = 1e-5, t_end = 1.2e-4, jump = 0.12;
  const auto shift = [&](ParticleSet& ps) {
    for (std::size_t p = 0; p < ps.size(); ++p) ps.x[3 * p] += jump;
  };
  mpi::DomainOptions o;
  o.rebalance_every = 0;
  DomainSolver dom(MPI_COMM_WORLD, setup(), o);
  dom.initialize();
  const Diagnostics d0 = dom.diagnostics();
  run_domain(dom, t_jump);
  const auto counts = [&] {
    double n = static_cast<double>(dom.local().particles().size());
    return dom.comm().allgather(&n, 1);
  };
  const std::vector<double> before = counts();
  shift(dom.local().particles_mutable());
  const long long migrated0 = dom.stats().migrated;
  dom.step(dom.stable_dt());
  const std::vector<double> after = counts();
  long long moved = dom.stats().migrated - migrated0;
  dom.comm().sum(&moved, 1);
  dom.rebalance();
  const std::vector<double> spread = counts();
  run_domain(dom, t_end);
  const Diagnostics d1 = dom.diagnostics();
  ParticleSet g;
  std::vector<MaterialSlot> gm;
  dom.gather(0, g, gm);
  if (rank() != 0) return;
  const double N = static_cast<double>(g.size());
  const int R = ranks();
  // before the jump the body is split among the first ranks (the last one holds none of it)
  EXPECT_LT(before[R - 1], N);
  // the jump: every particle of the other ranks went to the last one in one step
  EXPECT_EQ(static_cast<double>(moved), N - before[R - 1]);
  EXPECT_EQ(after[R - 1], N) << "all particles on the last rank";
  for (int r = 0; r + 1 < R; ++r) EXPECT_EQ(after[r], 0.0) << "rank " << r << " must be empty";
  EXPECT_LT(*std::max_element(spread.begin(), spread.end()), N) << "rebalancing must spread them";
  Solver ser = mpmtest::solver_from(setup());
  run_serial(ser, t_jump);
  shift(ser.particles_mutable());
  ser.step(ser.stable_dt());
  run_serial(ser, t_end);
  const Diagnostics s1 = ser.diagnostics();
  const Diff df = compare(g, gm, ser.particles(), ser.materials());
  ASSERT_TRUE(df.same_ids);
  std::printf("%d ranks: %.0f of %.0f particles jumped to the last rank; after rebalancing max %.0f per rank; max |diff| vs one rank: v %.3e m/s, x %.3e m, stress %.3e Pa\n",
              R, static_cast<double>(moved), N, *std::max_element(spread.begin(), spread.end()), df.max.at("v"), df.max.at("x"), df.max.at("stress"));
  const double U = 400.0, M = d0.mass;
  EXPECT_LT(df.max.at("v"), 1e-12 * U);
  EXPECT_LT(df.max.at("x"), 1e-12 * 0.01);
  EXPECT_LT(df.max.at("stress"), 1e-12 * 1000.0 * U * 400.0);  // rho U c
  EXPECT_NEAR(d1.mass, s1.mass, 2.2e-16 * N * M);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(d1.momentum[k], s1.momentum[k], 1e-12 * M * U) << k;
}
