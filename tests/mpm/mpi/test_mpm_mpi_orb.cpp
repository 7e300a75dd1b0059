/// @file test_mpm_mpi_orb.cpp
/// An impact where ORB boxes meet (label mpi; part of test_mpm_mpi; mpm/mpi/orb.hpp): a
/// Tonge–Ramesh rock sphere at the centre of a grid as wide in x as in y, hit obliquely by an
/// elastic sphere. On 3 ranks the tree cuts x, then the upper part along y: three boxes meet
/// along a line through the rock, whose nodes three ranks hold (the owner's ordered sum of
/// halo.cpp, not one commutative addition). The run rebalances as the impactor moves and must
/// match one rank to the tolerances of the Tonge–Ramesh impact test (test_mpm_mpi.cpp), conserve
/// mass and momentum to round-off, and repeat bit for bit.
#include <gtest/gtest.h>

#include "mpi_test_helpers.hpp"

using namespace mpmtest;

namespace {

Setup junction_setup() {
  return mpmtest::setup_from(R"(
[grid]
domain_min = [0.0, 0.0, 0.0]
domain_max = [0.12, 0.12, 0.06]
cell_size = 0.006
[solver]
scheme = "midpoint"
flip = 0.99
artificial_viscosity.enabled = true
[time]
end = 8e-5
)" + kRockAndSoft + R"(
[[body]]
material = "rock"
shape = "sphere"
center = [0.06, 0.06, 0.03]
radius = 0.024
[[body]]
material = "soft"
shape = "sphere"
center = [0.094, 0.094, 0.03]
radius = 0.01
velocity = [-250.0, -250.0, 0.0]
)");
}
constexpr double kEnd = 8e-5;  // the impactor has hit the rock near the line where the boxes meet

struct JunctionRun {
  ParticleSet ps;
  std::vector<MaterialSlot> mats;
  Diagnostics d0, d1;
  mpi::Orb orb0;
  long long migrated = 0, rebalances = 0, shared3 = 0;
};

JunctionRun run_junction() {
  mpi::DomainOptions opt;
  opt.rebalance_every = 5;
  opt.imbalance_threshold = 1.02;
  DomainSolver dom(MPI_COMM_WORLD, junction_setup(), opt);
  JunctionRun r;
  r.orb0 = dom.orb();
  // nodes of this rank's own box that two other ranks hold too
  const mpi::Orb& o = dom.orb();
  const mpi::Box own = o.own()[static_cast<std::size_t>(rank())];
  for (int k = own.lo[2]; k < own.hi[2]; ++k)
    for (int j = own.lo[1]; j < own.hi[1]; ++j)
      for (int i = own.lo[0]; i < own.hi[0]; ++i) {
        int holders = 0;
        for (int q = 0; q < o.ranks(); ++q) holders += o.held(q).contains(Eigen::Vector3i(i, j, k));
        r.shared3 += holders >= 3;
      }
  dom.initialize();
  r.d0 = dom.diagnostics();
  run_domain(dom, kEnd);
  r.d1 = dom.diagnostics();
  r.migrated = dom.stats().migrated;
  r.rebalances = dom.stats().rebalances;
  long long c[3] = {r.migrated, r.rebalances, r.shared3};
  MPI_Allreduce(MPI_IN_PLACE, c, 3, MPI_LONG_LONG, MPI_SUM, MPI_COMM_WORLD);
  r.migrated = c[0];
  r.shared3 = c[2];
  dom.gather(0, r.ps, r.mats);
  return r;
}

}  // namespace

TEST(MpmMpiOrb, ImpactWhereThreeBoxesMeetMatchesOneRankAndRepeats) {
  const JunctionRun a = run_junction(), b = run_junction();
  if (rank() != 0) return;
  if (ranks() == 3) {
    ASSERT_EQ(a.orb0.split.size(), 2u);
    EXPECT_NE(a.orb0.split[0].axis, a.orb0.split[1].axis) << "the boxes must meet along a line: " << a.orb0.describe();
    EXPECT_GT(a.shared3, 0) << "no node held by three ranks";
  }
  Solver ser = mpmtest::solver_from(junction_setup());
  const Diagnostics s0 = ser.diagnostics();
  run_serial(ser, kEnd);
  const Diagnostics s1 = ser.diagnostics();
  std::printf("%d ranks, %s at the start; %lld nodes held by 3 ranks, %lld particle moves, %lld rebalancings\n", ranks(),
              a.orb0.describe().c_str(), a.shared3, a.migrated, a.rebalances);
  EXPECT_GT(a.migrated, 50);
  EXPECT_GE(a.rebalances, 1);
  const Diff df = compare(a.ps, a.mats, ser.particles(), ser.materials());
  ASSERT_TRUE(df.same_ids);
  std::printf("  max |diff| vs one rank: v %.3e m/s, x %.3e m, stress %.3e Pa, damage %.3e, energy %.3e J/kg\n",
              df.max.at("v"), df.max.at("x"), df.max.at("stress"), df.max.at("state:damage"), df.max.at("energy"));
  const double U = 354.0, M = s0.mass, P = std::sqrt(2 * M * s0.kinetic);
  const double eps_sum = 2.2e-16 * static_cast<double>(a.ps.size());
  EXPECT_NEAR(a.d1.mass, M, eps_sum * M);
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(a.d1.momentum[k], a.d0.momentum[k], 1e-12 * P) << k;
    EXPECT_NEAR(a.d1.momentum[k], s1.momentum[k], 1e-12 * P) << k;
  }
  EXPECT_NEAR(a.d1.total(), s1.total(), 1e-9 * s0.total());
  expect_impact_agreement(df, U, 0.006);  // the Tonge–Ramesh impact test's tolerances
  expect_same_bits(a.ps, a.mats, b.ps, b.mats);  // repeated: bit for bit
}
