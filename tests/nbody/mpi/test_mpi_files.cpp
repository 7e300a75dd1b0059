/// @file test_mpi_files.cpp
/// ssdem-grav's collective outputs on 2 and 3 ranks (label mpi), against one rank's Simulation on
/// a self-gravitating pile with contacts that carries a per-sphere field (damage, as a hand-off
/// does) and a per-sphere field the run keeps (dissipated): after 40 steps the ranks' series-row
/// quantities (DomainSim::diagnostics) are one rank's bits, the collective snapshot and checkpoint
/// (io_mpi.hpp) are h5diff-equal to the serial writers' files, and the checkpoint, read back,
/// continues on these ranks and on one rank fewer to one rank's state, its carried field intact.
/// With one bond on 2 and 3 ranks (a rank without bond rows) the files equal the serial ones too.
#include <gtest/gtest.h>
#include <mpi.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <filesystem>
#include <string>

#include "common/rng.hpp"
#include "ssdem/bonds.hpp"
#include "ssdem/dt_rule.hpp"
#include "ssdem/generators.hpp"
#include "ssdem/io.hpp"
#include "ssdem/mpi/domain_sim.hpp"
#include "ssdem/mpi/io_mpi.hpp"

#include "mpi_support.hpp"

using namespace ssdem;

namespace {
using ssdem_test::world;

// G = 1 pile of 0.1-radius spheres, random velocities and spins, a carried damage field.
Spheres pile() {
  Spheres sp = ssdem_test::hot_pile(0.75, 23);
  common::Field damage{"damage", "1", 1, {}, "scalar damage (hand-off)"};
  for (std::size_t i = 0; i < sp.size(); ++i) damage.values.push_back(common::KeyedRng(24, sp.id[i]).uniform());
  sp.carried = {damage};
  return sp;
}

SimConfig config(const Spheres& sp) {
  const DtAdvice adv = choose_kn_dt(sp.m[0], 0.1, 1.0, 1.0, 0.01, 30);
  SimConfig c;
  c.self_gravity = true;
  c.gravity.G = 1.0;
  c.adaptive_gravity = true;
  c.contacts = true;
  c.contact = gravel_preset(adv.kn);
  c.dt = 0.77 * adv.dt;
  return c;
}

common::Provenance prov() {
  return common::Provenance{"test_nbody_mpi_files", "1.0", "abcdef", "mpirun test", "[t]\nx = 1\n"};
}

std::string shared_dir() {
  std::string p;
  if (world().rank == 0) {
    char tmpl[] = "/tmp/nbody_mpi_files.XXXXXX";
    const char* made = ::mkdtemp(tmpl);
    if (!made) std::abort();
    p = made;
  }
  return world().bcast(p);
}

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// h5diff of the serial writers' snapshot and checkpoint (<dir>/{snap,ck}_ser.h5) against the
// collective ones (_par.h5); rank 0.
bool serial_equals_parallel(const std::string& dir) {
  bool all = true;
  for (const std::string f : {"snap", "ck"}) {
    const std::string cmd = "h5diff " + dir + "/" + f + "_ser.h5 " + dir + "/" + f + "_par.h5";
    const bool eq = std::system(cmd.c_str()) == 0;
    EXPECT_TRUE(eq) << cmd;
    all = all && eq;
  }
  return all;
}

void run_to_boundary(mpi::DomainSim& d, Simulation* s, int steps) {
  for (int k = 0; k < steps || !d.at_gravity_boundary(); ++k) {
    d.step();
    if (s) s->step();
  }
}
}  // namespace

TEST(MpiFiles, RowsSnapshotAndCheckpointEqualOneRanksWithCarriedFields) {
  const Spheres sp = pile();
  const SimConfig cfg = config(sp);
  const std::string dir = shared_dir();
  mpi::DomainSim d(world(), sp, cfg);
  std::unique_ptr<Simulation> ref;
  if (world().rank == 0) ref = std::make_unique<Simulation>(sp, cfg);
  run_to_boundary(d, ref.get(), 40);
  ASSERT_EQ(world().all(ref ? ref->step_count() == d.step_count() : true), true);

  // the series row's quantities: one rank's bits on every rank
  const Diagnostics got = d.diagnostics();
  int rows_equal = 1;
  if (ref) {
    const Diagnostics want = ref->diagnostics();
    const double a[] = {got.kinetic, got.rotational, got.potential_self, got.elastic, got.dissipated,
                        got.momentum.x(), got.momentum.y(), got.momentum.z(), got.angular_momentum.z()};
    const double b[] = {want.kinetic, want.rotational, want.potential_self, want.elastic, want.dissipated,
                        want.momentum.x(), want.momentum.y(), want.momentum.z(), want.angular_momentum.z()};
    for (int k = 0; k < 9; ++k) {
      EXPECT_TRUE(same_bits(a[k], b[k])) << "quantity " << k << ": " << a[k] << " vs " << b[k];
      rows_equal &= same_bits(a[k], b[k]);
    }
    EXPECT_EQ(got.contacts, want.contacts);
    EXPECT_GT(want.contacts, 0u);
    EXPECT_TRUE(same_bits(got.max_overlap_frac, want.max_overlap_frac));
  }
  MPI_Bcast(&rows_equal, 1, MPI_INT, 0, MPI_COMM_WORLD);
  EXPECT_TRUE(rows_equal) << world().size << " ranks";

  // collective snapshot and checkpoint against the serial writers
  const mpi::DomainSim::Local L = d.local_state();
  const StateHeader h{cfg.dt, L.st.gravity_block, cfg.contact.kn, "", cfg.self_gravity, L.has_prev, false};
  mpi::write_snapshot_mpi(world(), dir + "/snap_par.h5", d, L, prov());
  mpi::write_checkpoint_mpi(world(), dir + "/ck_par.h5", d, L, h, 12.5, prov());
  int files_equal = 1;
  if (ref) {
    SimState st = ref->state();
    st.energy0 = 12.5;
    write_snapshot(dir + "/snap_ser.h5", st.sp, st.time, st.step, prov());
    write_checkpoint(dir + "/ck_ser.h5", st, cfg.dt, st.gravity_block, prov(), cfg.contact.kn);
    files_equal = serial_equals_parallel(dir);
    const common::SphereSet back = common::read_sphere_set(dir + "/snap_par.h5");
    ASSERT_NE(back.field("damage"), nullptr);
    EXPECT_EQ(back.field("damage")->values, sp.carried[0].values);  // carried fields never move
  }
  MPI_Bcast(&files_equal, 1, MPI_INT, 0, MPI_COMM_WORLD);
  EXPECT_TRUE(files_equal);

  // the collective checkpoint continues as one rank's state does: on these ranks, and on one
  // rank fewer (N -> M), its carried field with it
  double dt = 0, kn = 0;
  int every = 0;
  SimState st = read_checkpoint(dir + "/ck_par.h5", &dt, &every, &kn);
  SimConfig c2 = cfg;
  c2.dt = dt;
  c2.contact.kn = kn;
  st.gravity_block = every;
  std::unique_ptr<Simulation> ref2;
  if (ref) ref2 = std::make_unique<Simulation>(ref->state(), cfg);  // a copy for the second continuation
  auto continued = [&](mpi::Comm& c, Simulation* r, const char* what) {
    mpi::DomainSim d2(c, st, c2);
    run_to_boundary(d2, r, 20);
    const SimState mine = d2.gather_state();
    if (!r) return;
    const SimState want = r->state();
    ASSERT_EQ(mine.sp.size(), want.sp.size());
    bool eq = true;
    for (std::size_t i = 0; i < want.sp.size(); ++i) eq = eq && mine.sp.x[i] == want.sp.x[i] && mine.sp.v[i] == want.sp.v[i];
    EXPECT_TRUE(eq) << what << ": the continuation differs from one rank's";
    ASSERT_EQ(mine.sp.carried.size(), 1u);
    EXPECT_EQ(mine.sp.carried[0].values, sp.carried[0].values) << what;
  };
  continued(world(), ref.get(), "same ranks");
  const int m = std::max(1, world().size - 1);
  MPI_Comm sub;
  MPI_Comm_split(MPI_COMM_WORLD, world().rank < m ? 0 : MPI_UNDEFINED, world().rank, &sub);
  if (sub != MPI_COMM_NULL) {
    mpi::Comm c(sub);
    continued(c, ref2.get(), "one rank fewer");
    MPI_Comm_free(&sub);
  }
  MPI_Barrier(MPI_COMM_WORLD);
  if (world().rank == 0) std::filesystem::remove_all(dir);
}

TEST(MpiFiles, FewerBondsThanRanksSnapshotAndCheckpointEqualOneRanks) {
  // one bond (a bonded pair among loose spheres): with 2 and 3 ranks a rank's block of the bond
  // rows is empty, and it must still create every /bonds dataset with the others (collective)
  Spheres sp;
  const double m = 2000.0 * 4.0 / 3.0 * M_PI * 0.125;
  for (int k = 0; k < 7; ++k) sp.push(k, Vec3(3.0 * k, 0.1 * k, 0.0), Vec3(0.0, 0.01 * k, 0.0), Vec3::Zero(), m, 0.5);
  sp.x[1] = sp.x[0] + Vec3(1.001, 0.0, 0.0);  // 0 and 1 bonded
  SimConfig cfg;
  cfg.contacts = true;
  cfg.contact = gravel_preset(1e6);
  BondParams bp;
  bp.kn = bp.ks = 1e6;
  bp.sigma_c = bp.tau_c = 1e300;
  cfg.bonds = generate_bonds(sp, bp);
  ASSERT_EQ(cfg.bonds.size(), 1u);
  cfg.dt = 0.77 * std::min(cfg.contact.contact_time(0.5 * m), shortest_bond_time(cfg.bonds, sp)) / 30.0;
  const std::string dir = shared_dir();
  mpi::DomainSim d(world(), sp, cfg);
  std::unique_ptr<Simulation> ref;
  if (world().rank == 0) ref = std::make_unique<Simulation>(sp, cfg);
  run_to_boundary(d, ref.get(), 10);
  const mpi::DomainSim::Local L = d.local_state();
  const StateHeader h{cfg.dt, L.st.gravity_block, cfg.contact.kn, "", false, L.has_prev, false};
  mpi::write_snapshot_mpi(world(), dir + "/snap_par.h5", d, L, prov());
  mpi::write_checkpoint_mpi(world(), dir + "/ck_par.h5", d, L, h, 1.0, prov());
  int files_equal = 1;
  if (ref) {
    SimState st = ref->state();
    st.energy0 = 1.0;
    write_snapshot(dir + "/snap_ser.h5", st.sp, st.time, st.step, prov(), &st.bonds);
    write_checkpoint(dir + "/ck_ser.h5", st, cfg.dt, st.gravity_block, prov(), cfg.contact.kn);
    files_equal = serial_equals_parallel(dir);
    EXPECT_EQ(common::read_sphere_set(dir + "/snap_par.h5").bonds.broken.size(), 1u);
  }
  MPI_Bcast(&files_equal, 1, MPI_INT, 0, MPI_COMM_WORLD);
  EXPECT_TRUE(files_equal) << world().size << " ranks";
  MPI_Barrier(MPI_COMM_WORLD);
  if (world().rank == 0) std::filesystem::remove_all(dir);
}
