/// @file test_mpm_mpi_outflow.cpp
/// Outflow removal on MPI ranks (grid.outflow = "remove"; label mpi, part of test_mpm_mpi):
/// two flyers (Tonge–Ramesh rock and an elastic material) side by side along the split axis
/// leave the grid through y+ at 400 m/s next to a resting rock bar, so every rank removes
/// particles and the ranks' records hold different state fields (merged by name on gathering).
/// Against one rank: the same particles removed at the same times, their record (ballistic
/// positions, velocities, damage, removal times) and the remaining particles within the
/// cross-rank tolerances of test_mpm_mpi.cpp; totals including the removed particles. A checkpoint
/// taken while half of the flyers have left continues bit-identically on as many ranks. The
/// outflow file written by every rank together equals the one of the gathered record.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <map>
#include <unistd.h>

#include "common/particle_file.hpp"
#include "mpi_test_helpers.hpp"
#include "mpm/mpi/checkpoint_mpi.hpp"
#include "mpm/mpi/snapshot_mpi.hpp"
#include "mpm/output.hpp"

using namespace mpmfrag;
using namespace mpmtest;

namespace {

constexpr double kHalf = 7.5e-5, kEnd = 1e-4;  // removals at 6.9e-5 and 8.2e-5 s: half / all have left
constexpr double U = 400.0, H = 0.01;

/// Removal time and row of every particle of an outflow snapshot, by id.
std::map<std::uint64_t, std::size_t> rows_by_id(const common::ParticleSnapshot& s) {
  std::map<std::uint64_t, std::size_t> m;
  for (std::size_t p = 0; p < s.count(); ++p) m[s.id[p]] = p;
  return m;
}

}  // namespace

TEST(MpmMpiOutflow, EveryRankRemovesParticlesAsOneRank) {
  DomainSolver dom(MPI_COMM_WORLD, outflow_setup());
  dom.initialize();
  const Diagnostics d0 = dom.diagnostics();
  run_domain(dom, kEnd);
  const Diagnostics d1 = dom.diagnostics();
  long long removed_here = static_cast<long long>(dom.local().outflow_count()), ranks_removing = removed_here > 0;
  dom.comm().sum(&ranks_removing, 1);
  const mpi::OutflowRecord rec = dom.gather_outflow(0);
  ParticleSet g;
  std::vector<MaterialSlot> gm;
  dom.gather(0, g, gm);
  if (rank() != 0) return;
  Solver ser = solver_from(outflow_setup());
  run_serial(ser, kEnd);
  const Diagnostics s1 = ser.diagnostics();
  const common::ParticleSnapshot so = ser.outflow_snapshot();
  const common::ParticleSnapshot mo = make_outflow_snapshot(rec.ps, rec.time, rec.fields, ser.grid(), dom.time(), dom.step_count());
  ASSERT_EQ(mo.count(), so.count());
  ASSERT_GT(so.count(), 100u);
  EXPECT_EQ(ranks_removing, ranks()) << "every rank must remove particles";
  EXPECT_EQ(d1.removed, so.count());
  const auto rs = rows_by_id(so);
  double dx = 0, dv = 0, dt = 0, dd = 0;
  const common::Field *mt = mo.field("removal_time"), *st = so.field("removal_time");
  const common::Field *md = mo.field("damage"), *sd = so.field("damage");
  ASSERT_TRUE(mt && st && md && sd);
  for (std::size_t p = 0; p < mo.count(); ++p) {
    const auto it = rs.find(mo.id[p]);
    ASSERT_NE(it, rs.end()) << "particle " << mo.id[p] << " removed on MPI only";
    const std::size_t q = it->second;
    for (int d = 0; d < 3; ++d) {
      dx = std::max(dx, std::fabs(mo.position[3 * p + d] - so.position[3 * q + d]));
      dv = std::max(dv, std::fabs(mo.velocity[3 * p + d] - so.velocity[3 * q + d]));
    }
    dt = std::max(dt, std::fabs(mt->values[p] - st->values[q]));
    dd = std::max(dd, std::fabs(md->values[p] - sd->values[q]));
    if (p > 0) {
      EXPECT_LE(mt->values[p - 1], mt->values[p]) << "record sorted by removal time";
    }
  }
  const Diff df = compare(g, gm, ser.particles(), ser.materials());
  ASSERT_TRUE(df.same_ids);
  std::printf("%d ranks: %zu particles removed (by %lld ranks) between t = %.3g and %.3g s; record vs one rank: x %.3e m, v %.3e m/s, removal time %.3e s, damage %.3e; remaining: v %.3e m/s, stress %.3e Pa\n",
              ranks(), mo.count(), ranks_removing, st->values.front(), st->values.back(), dx, dv, dt, dd, df.max.at("v"), df.max.at("stress"));
  EXPECT_LT(dx, 1e-12 * H);
  EXPECT_LT(dv, 1e-12 * U);
  EXPECT_LT(dt, 1e-12 * kEnd);
  EXPECT_LT(dd, 1e-9);
  EXPECT_LT(df.max.at("v"), 1e-12 * U);
  EXPECT_LT(df.max.at("stress"), 1e-12 * 2700.0 * U * 6000.0);
  const double M = d0.mass, eps = 2.2e-16 * static_cast<double>(g.size() + mo.count());
  EXPECT_NEAR(d1.mass, M, eps * M);
  EXPECT_NEAR(d1.removed_mass, s1.removed_mass, eps * M);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(d1.momentum[k], s1.momentum[k], 1e-12 * M * U) << k;
}

TEST(MpmMpiOutflow, CheckpointWithRemovedParticlesContinuesBitIdentically) {
  long long pid = getpid();
  MPI_Bcast(&pid, 1, MPI_LONG_LONG, 0, MPI_COMM_WORLD);
  const std::string path = (std::filesystem::temp_directory_path() / ("mpm_mpi_outflow_" + std::to_string(pid) + ".h5")).string();
  const common::Provenance prov{"mpm-frag", "test", "test", "test", ""};
  struct End {
    mpi::OutflowRecord rec;
    Diagnostics d;
    ParticleSet ps;
    std::size_t removed_at_check = 0;
  };
  End a, b;
  {
    DomainSolver dom(MPI_COMM_WORLD, outflow_setup());
    dom.initialize();
    run_domain(dom, kHalf);
    mpi::write_checkpoint_mpi(dom, path, DriverState{}, prov, "");
    a.removed_at_check = static_cast<std::size_t>(dom.diagnostics().removed);
    run_domain(dom, kEnd);
    a.d = dom.diagnostics();
    a.rec = dom.gather_outflow(0);
    std::vector<MaterialSlot> m;
    dom.gather(0, a.ps, m);
  }
  {
    mpi::Comm comm(MPI_COMM_WORLD);
    mpi::RestartData rd = mpi::read_checkpoint_mpi(comm, path, common::RunIdentity{});
    mpmfrag::Setup st = outflow_setup();
    apply_materials(rd.ck, st.materials, path);  // each rank its part of the file's rows
    st.particles = std::move(rd.ck.particles);
    DomainSolver dom(MPI_COMM_WORLD, st, rd.layout);
    mpi::resume(dom, rd);
    b.removed_at_check = static_cast<std::size_t>(dom.diagnostics().removed);
    run_domain(dom, kEnd);
    b.d = dom.diagnostics();
    b.rec = dom.gather_outflow(0);
    std::vector<MaterialSlot> m;
    dom.gather(0, b.ps, m);
  }
  if (rank() != 0) return;
  std::filesystem::remove(path);
  const auto same = [](const std::vector<double>& x, const std::vector<double>& y) {
    return x.size() == y.size() && std::memcmp(x.data(), y.data(), 8 * x.size()) == 0;
  };
  std::printf("%d ranks: %zu removed at the checkpoint, %zu at the end\n", ranks(), a.removed_at_check, a.rec.ps.size());
  EXPECT_GT(a.removed_at_check, 20u);
  EXPECT_GT(a.rec.ps.size(), a.removed_at_check + 20);
  EXPECT_EQ(b.removed_at_check, a.removed_at_check);
  ASSERT_EQ(a.rec.ps.size(), b.rec.ps.size());
  EXPECT_EQ(a.rec.ps.id, b.rec.ps.id);
  EXPECT_TRUE(same(a.rec.ps.x, b.rec.ps.x) && same(a.rec.ps.v, b.rec.ps.v) && same(a.rec.time, b.rec.time));
  ASSERT_EQ(a.rec.fields.size(), b.rec.fields.size());
  for (std::size_t f = 0; f < a.rec.fields.size(); ++f) EXPECT_TRUE(same(a.rec.fields[f].values, b.rec.fields[f].values)) << a.rec.fields[f].name;
  EXPECT_TRUE(same(a.ps.x, b.ps.x) && same(a.ps.v, b.ps.v) && same(a.ps.stress, b.ps.stress));
  EXPECT_EQ(a.d.mass, b.d.mass);
  EXPECT_EQ(a.d.total(), b.d.total());
  for (int k = 0; k < 3; ++k) EXPECT_EQ(a.d.momentum[k], b.d.momentum[k]) << k;
}

// The outflow file written by every rank together (write_outflow_mpi, the MPI driver's) equals
// the file the serial writer makes of the gathered record (h5diff, provenance aside): the same
// rows in (removal time, id) order, the field lists of the ranks merged in the same order, a
// field missing on a rank's particles at its initial value. Every rank removed particles, and
// their records hold different fields (Tonge–Ramesh and elastic).
TEST(MpmMpiOutflow, TheFileWrittenTogetherEqualsTheGatheredFile) {
  const common::Provenance prov{"mpm-frag", "test", "test", "test", ""};
  SharedDir dir;
  DomainSolver dom(MPI_COMM_WORLD, outflow_setup());
  dom.initialize();
  run_domain(dom, kEnd);
  const mpi::OutflowRecord local = dom.local_outflow();
  long long rows[2] = {static_cast<long long>(local.ps.size()), local.ps.size() > 0 ? 1 : 0};
  dom.comm().sum(rows, 2);
  // each rank's own field list (before the merge), as a count: the ranks' lists must differ
  double own = static_cast<double>(dom.local().resume_state().outflow_fields.size());
  const std::vector<double> lists = dom.comm().allgather(&own, 1);
  const std::string par = dir.path + "/together.h5", ser = dir.path + "/gathered.h5";
  mpi::write_outflow_mpi(dom.comm(), local, dom.local().grid(), dom.time(), dom.step_count(), par, prov);
  const mpi::OutflowRecord all = dom.gather_outflow(0);
  if (rank() != 0) return;
  EXPECT_EQ(rows[1], ranks()) << "every rank must hold removed particles";
  EXPECT_NE(*std::min_element(lists.begin(), lists.end()), *std::max_element(lists.begin(), lists.end()))
      << "the ranks' records must hold different fields (merged by name)";
  ASSERT_EQ(all.ps.size(), static_cast<std::size_t>(rows[0]));
  ASSERT_EQ(local.fields.size(), all.fields.size());
  for (std::size_t f = 0; f < all.fields.size(); ++f) EXPECT_EQ(local.fields[f].name, all.fields[f].name);
  common::write_particle_snapshot(
      ser, make_outflow_snapshot(all.ps, all.time, all.fields, dom.local().grid(), dom.time(), dom.step_count()), prov);
  const std::string cmd = "h5diff --exclude-path /provenance " + ser + " " + par;
  EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd;
  std::printf("%d ranks: the outflow file of %lld particles written together equals the gathered one\n", ranks(),
              rows[0]);
}
