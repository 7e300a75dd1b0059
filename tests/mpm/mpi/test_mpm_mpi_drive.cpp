/// @file test_mpm_mpi_drive.cpp
/// Velocity-driven bodies on MPI ranks (label mpi; part of test_mpm_mpi, whose main() initialises
/// MPI): a soft block squeezed between two driven platens. The upper one spans the split axis,
/// so every cut runs through it; the lower one ends at the first cut (a free box at rest, apart
/// from everything, holds the particles the lower platen lacks beyond the cut, so the particle
/// count per plane and the cuts do not move), so the nodes of the two
/// planes past the cut are constrained by rank 0's particles only and the neighbour learns it
/// from the swapped flags (GridExchange::min_shared_drive; without the swap the test fails). The
/// upper platen also moves along the split axis, and the run rebalances as it does (the drives'
/// node flags follow the new boxes, Solver::set_subdomain). Against one rank: the particle
/// state within the cross-rank tolerances of test_mpm_mpi.cpp, the platens rigid at v_T, and
/// each platen's reaction (the force of the last step and the impulse since t = 0, summed over
/// the nodes each rank owns, then over the ranks) within 1e-10 of its size; every rank holds the
/// same loads, bit for bit.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "mpi_test_helpers.hpp"

using namespace mpmfrag;
using namespace mpmtest;

namespace {

/// `xe`: where the lower platen ends (a free box at rest above the rest takes its x-range to 0.27).
mpmfrag::Setup squeeze_setup(double xe) {
  const std::string e = std::to_string(xe);
  return mpmtest::setup_from(R"(
[grid]
domain_min = [0.0, 0.0, 0.0]
domain_max = [0.3, 0.15, 0.05]
cell_size = 0.01
[solver]
flip = 0.97
[time]
end = 1.0
[[material]]
name = "soft"
model = "elastic"
density = 1000.0
bulk_modulus = 1e8
shear_modulus = 1e7
[[material]]
name = "platen"
model = "elastic"
density = 7800.0
bulk_modulus = 1.6e11
shear_modulus = 8e10
[[body]]
material = "soft"
shape = "box"
min = [0.04, 0.03, 0.015]
max = [0.26, 0.06, 0.035]
[[body]]
material = "platen"
shape = "box"
min = [0.03, 0.015, 0.01]
max = [)" + e + R"(, 0.03, 0.04]
drive.enabled = true
drive.velocity = [0.0, 3.0, 0.0]
drive.ramp_time = 2e-5
[[body]]
material = "soft"
shape = "box"
min = [)" + e + R"(, 0.1, 0.01]
max = [0.27, 0.115, 0.04]
[[body]]
material = "platen"
shape = "box"
min = [0.03, 0.06, 0.01]
max = [0.27, 0.075, 0.04]
drive.enabled = true
drive.velocity = [30.0, -3.0, 0.5]
drive.ramp_time = 2e-5
)");
}
constexpr double kEnd = 6e-4, U = 3.0, H = 0.01;


TEST(MpmMpi, DrivenPlatensAcrossTheCutsMatchOneRank) {
  // the first cut (the same for any xe: the particles are the same, only their drive differs)
  const mpmfrag::Setup probe = squeeze_setup(0.15);
  const int P = DomainSolver(MPI_COMM_WORLD, probe).orb().split[0].cut;  // the root's cut (along x)
  const double xe = probe.grid.origin[0] + P * H;  // node plane P (the grid's origin holds the ghost layers)
  ASSERT_GT(xe, 0.05);
  ASSERT_LT(xe, 0.25);
  const mpmfrag::Setup st = squeeze_setup(xe);
  ASSERT_EQ(st.drives.size(), 2u);
  mpi::DomainOptions opt;  // the upper platen moves along the split axis: the cuts follow it
  opt.rebalance_every = 3;
  opt.imbalance_threshold = 1.0 + 1e-9;
  DomainSolver dom(MPI_COMM_WORLD, st, opt);
  ASSERT_EQ(dom.orb().split[0].axis, 0);
  ASSERT_EQ(dom.orb().split[0].cut, P) << "the lower platen must end at the first cut";
  dom.initialize();
  run_domain(dom, kEnd);
  const long long rebalances = dom.stats().rebalances;
  const std::vector<DriveLoad> loads = dom.local().drive_loads();
  std::vector<double> mine;
  for (const DriveLoad& l : loads) mine.insert(mine.end(), {l.force[0], l.force[1], l.force[2], l.impulse[0], l.impulse[1], l.impulse[2]});
  const std::vector<double> all = dom.comm().allgather(mine.data(), static_cast<int>(mine.size()));
  ParticleSet g;
  std::vector<MaterialSlot> gm;
  dom.gather(0, g, gm);
  if (rank() != 0) return;
  EXPECT_GE(rebalances, 1) << "the cuts must move with the platen (Solver::set_subdomain with drives)";
  for (int r = 1; r < ranks(); ++r)
    for (std::size_t k = 0; k < mine.size(); ++k) EXPECT_EQ(all[r * mine.size() + k], mine[k]) << "rank " << r;
  mpmfrag::Setup ss = squeeze_setup(xe);
  Solver ser(ss.solver, ss.grid, std::move(ss.particles), std::move(ss.materials));
  ser.set_drives(ss.drives);
  ser.initialize();
  run_serial(ser, kEnd);
  EXPECT_EQ(dom.step_count(), ser.step_count());
  for (std::size_t k = 0; k < st.drives.size(); ++k) EXPECT_GT(st.drives[k].mass, 0.0);
  const Diff df = compare(g, gm, ser.particles(), ser.materials());
  ASSERT_TRUE(df.same_ids);
  EXPECT_LT(df.max.at("v"), 1e-12 * U);
  EXPECT_LT(df.max.at("x"), 1e-12 * H);
  double smax = 0;  // the stress scale (the squeezed block's largest)
  for (const double v : ser.particles().stress) smax = std::max(smax, std::fabs(v));
  EXPECT_LT(df.max.at("stress"), 1e-12 * smax);
  // the platens move rigidly at v_T(t_end) on every rank
  double rigid = 0;
  for (std::size_t p = 0; p < g.size(); ++p)
    for (const BodyDrive& d : st.drives)
      if (d.holds(g.id[p]))
        for (int c = 0; c < 3; ++c) rigid = std::max(rigid, std::fabs(g.v[3 * p + c] - d.velocity_at(kEnd)[c]));
  EXPECT_LT(rigid, 1e-12 * U);
  const std::vector<DriveLoad>& sl = ser.drive_loads();
  double dF = 0, dJ = 0;
  for (std::size_t k = 0; k < sl.size(); ++k) {
    ASSERT_GT(sl[k].force.norm(), 1.0) << "the block must push back on platen " << k;
    dF = std::max(dF, (loads[k].force - sl[k].force).norm() / sl[k].force.norm());
    dJ = std::max(dJ, (loads[k].impulse - sl[k].impulse).norm() / sl[k].impulse.norm());
  }
  EXPECT_LT(dF, 1e-10);
  EXPECT_LT(dJ, 1e-10);
  std::printf("%d ranks, %s, the lower platen ends at x = %.3f m: platen loads %.4g N, %.4g N (one rank %.4g, %.4g); relative diff force %.2e, "
              "impulse %.2e; v %.2e m/s, x %.2e m, stress %.2e Pa (of %.3g), platens rigid to %.2e m/s\n",
              ranks(), dom.orb().describe().c_str(), xe, loads[0].force.norm(), loads[1].force.norm(),
              sl[0].force.norm(), sl[1].force.norm(), dF, dJ, df.max.at("v"), df.max.at("x"), df.max.at("stress"), smax, rigid);
}

}  // namespace
