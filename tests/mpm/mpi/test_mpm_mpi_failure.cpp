/// @file test_mpm_mpi_failure.cpp
/// The last good state of a failed mpm-frag run on MPI ranks (label mpi; part of test_mpm_mpi,
/// whose main() initialises MPI). A step far past the stable one (100 x the CFL step, as the
/// serial Stability.ForcedHugeStepStopsWithDiagnosis) must fail on every rank together, with the
/// state no longer intact; the ranks' backups (DomainSolver::save_backup, taken before particles
/// migrated between ranks) written together (write_snapshot_mpi, what run_mpi.cpp saves as
/// <prefix>_failed_<step>.h5) must equal, bit for bit, the snapshot of the state they copied.
/// The driver's end-to-end failure path is tests/mpm/mpi/app_mpi_failure.sh.
#include <gtest/gtest.h>

#include <cmath>

#include "common/particle_file.hpp"
#include "mpi_test_helpers.hpp"
#include "mpm/mpi/snapshot_mpi.hpp"

using namespace mpmfrag;
using namespace mpmtest;

namespace {
const common::Provenance kProv{"mpm-frag", "test", "test", "test", ""};

TEST(MpmMpi, AFailureOnEveryRankLeavesTheBackupsOfTheLastGoodStep) {
  SharedDir dir;
  const mpmfrag::Setup st = impact_setup();
  DomainSolver dom(MPI_COMM_WORLD, st, impact_options());
  dom.initialize();
  for (int i = 0; i < 5; ++i) dom.step(dom.stable_dt());
  dom.save_backup();
  const std::int64_t k = dom.step_count();
  const double t = dom.time();
  const std::string good = dir.path + "/good.h5", saved = dir.path + "/saved.h5";
  mpi::write_snapshot_mpi(dom.comm(), dom.local().particles(), dom.local().materials(), st.grid, t, k, good, kProv);
  long long moved0 = dom.stats().migrated;
  // the impactor crosses the cuts: particles change ranks after the backup
  while (dom.time() < kImpactEnd) dom.step(dom.stable_dt());
  long long moved = dom.stats().migrated - moved0;
  dom.comm().sum(&moved, 1);
  int thrown = 0, intact = 1;
  try {
    for (int i = 0; i < 50; ++i) dom.step(100 * dom.stable_dt());
  } catch (const SolverFailure& f) {
    thrown = 1;
    intact = f.state_intact ? 1 : 0;
  }
  int flags[4] = {thrown, -thrown, intact, -intact};  // min and max over the ranks
  MPI_Allreduce(MPI_IN_PLACE, flags, 4, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
  EXPECT_EQ(flags[0], 1) << "a rank did not fail";
  EXPECT_EQ(-flags[1], 1);
  EXPECT_EQ(flags[2], -flags[3]) << "the ranks disagree on whether the state is intact";
  EXPECT_EQ(flags[2], 0) << "a 100x step must fail inside the step";
  const Backup& b = dom.backup();
  ASSERT_TRUE(dom.comm().all(b.valid));
  EXPECT_EQ(b.step, k);
  EXPECT_EQ(b.time, t);
  mpi::write_snapshot_mpi(dom.comm(), b.particles, b.materials, st.grid, b.time, b.step, saved, kProv);
  if (rank() != 0) return;
  EXPECT_GT(moved, 0) << "no particle changed rank between the backup and the failure";
  const common::ParticleSnapshot g = common::read_particle_snapshot(good), s = common::read_particle_snapshot(saved);
  ASSERT_GT(g.count(), 0u);
  EXPECT_EQ(s.step, k);
  EXPECT_EQ(s.time, t);
  EXPECT_EQ(s.id, g.id);
  EXPECT_EQ(s.material, g.material);
  EXPECT_EQ(s.position, g.position);
  EXPECT_EQ(s.velocity, g.velocity);
  EXPECT_EQ(s.mass, g.mass);
  EXPECT_EQ(s.volume, g.volume);
  ASSERT_EQ(s.fields.size(), g.fields.size());
  for (std::size_t f = 0; f < g.fields.size(); ++f) {
    EXPECT_EQ(s.fields[f].name, g.fields[f].name);
    EXPECT_EQ(s.fields[f].values, g.fields[f].values) << g.fields[f].name;
  }
  std::printf("%d ranks: failure on every rank (state not intact); %lld particle moves after the backup of step %lld; "
              "its file equals the step's snapshot (%zu particles, %zu fields)\n",
              ranks(), moved, static_cast<long long>(k), g.count(), g.fields.size());
}

}  // namespace
