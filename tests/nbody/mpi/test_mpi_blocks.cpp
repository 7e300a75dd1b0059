/// @file test_mpi_blocks.cpp
/// ssdem-grav started from blocks of rows (nbody/include/ssdem/mpi/domain_sim.hpp, "Input in
/// blocks"): each rank holds only its rows of the input, and the run must be the one-rank run bit
/// for bit. Run under `mpirun -np 2` and `-np 3` (label mpi).
/// - the summary of the blocks (sphere_summary_mpi.hpp) equals the serial summary of all the
///   spheres bit for bit, with rank 0 holding no rows, ties at the smallest mass and the median;
///   the collective k-th smallest equals the sorted value at every k tried (negatives too);
/// - a fresh start from blocks equals one rank after 300 steps (tree, adaptive cadence, contacts);
/// - a multi-rate restart from a checkpoint file, each rank reading only its rows of the spheres
///   and of the contact history, equals the uninterrupted one-rank run (tolerance 0);
/// - a duplicate id in two different blocks gives the one-rank reader's message (rows named);
///   a history record naming an id absent from every block gives the one-rank message.
#include <gtest/gtest.h>
#include <mpi.h>
#include <unistd.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "common/rng.hpp"
#include "common/sorted_rows.hpp"
#include "common/sphere_file.hpp"
#include "common/status.hpp"
#include "mpi_support.hpp"
#include "ssdem/generators.hpp"
#include "ssdem/io.hpp"
#include "ssdem/mpi/domain_sim.hpp"
#include "ssdem/mpi/sphere_summary_mpi.hpp"
#include "ssdem/simulation.hpp"

using namespace ssdem;

namespace {
using ssdem_test::pile_config;
using ssdem_test::state_diff;
using ssdem_test::world;

// G = 1 pile of 0.1-radius spheres with random velocities (0.3 v_esc) and spins.
Spheres pile(double R) { return ssdem_test::hot_pile(R, 29); }

// Rows [lo, hi) of every array of `all` (a rank's block).
Spheres rows(const Spheres& all, std::size_t lo, std::size_t hi) {
  Spheres b;
  for (std::size_t i = lo; i < hi; ++i) b.push(all.id[i], all.x[i], all.v[i], all.w[i], all.m[i], all.s[i]);
  return b;
}

struct Range {
  std::size_t lo, hi;
};
// This rank's dense block of n rows (the driver's blocks).
Range dense(std::size_t n) {
  return {common::mpi::dense_first(n, world().size, world().rank), common::mpi::dense_first(n, world().size, world().rank + 1)};
}

void expect_same(const SphereSummary& a, const SphereSummary& b) {
  EXPECT_EQ(a.n, b.n);
  auto same = [](double x, double y, const char* what) {
    EXPECT_EQ(std::bit_cast<std::uint64_t>(x), std::bit_cast<std::uint64_t>(y)) << what << ": " << x << " vs " << y;
  };
  same(a.m1, b.m1, "m1");
  same(a.m2, b.m2, "m2");
  same(a.mmax, b.mmax, "mmax");
  same(a.m_median, b.m_median, "median");
  same(a.smin, b.smin, "smin");
  same(a.smax, b.smax, "smax");
  same(a.M, b.M, "M");
  for (int c = 0; c < 3; ++c) same(a.com[c], b.com[c], "com");
  same(a.R, b.R, "R");
  same(a.vmax, b.vmax, "vmax");
}
}  // namespace

TEST(MpiBlocks, SummaryOfBlocksEqualsTheSerialSummaryBitForBit) {
  Spheres all = pile(0.8);
  const std::size_t n = all.size();
  for (std::size_t i = 0; i < n; ++i) {  // masses spread over 3 decades, radii over one
    common::KeyedRng rng(5, all.id[i]);
    all.m[i] = std::exp(3.0 * rng.uniform());
    all.s[i] = 0.05 + 0.05 * rng.uniform();
  }
  all.m[7] = all.m[n - 3] = 0.5;  // the two smallest tie, in different blocks
  const SphereSummary want = summarise(all);
  ASSERT_EQ(want.m1, 0.5);
  ASSERT_EQ(want.m2, 0.5);
  // rank 0 holds no rows; the others split them
  const int P = world().size, r = world().rank;
  const std::size_t lo = r == 0 ? 0 : common::mpi::dense_first(n, P - 1, r - 1);
  const std::size_t hi = r == 0 ? 0 : common::mpi::dense_first(n, P - 1, r);
  const SphereSummary got = mpi::summarise(world(), rows(all, lo, hi));
  expect_same(got, want);
  // the median lies in one block, the extremes in others
  std::vector<double> v;
  for (std::size_t i = lo; i < hi; ++i) v.push_back(all.x[i].x() - 0.1);  // negatives and positives
  std::vector<double> sorted;
  for (std::size_t i = 0; i < n; ++i) sorted.push_back(all.x[i].x() - 0.1);
  std::sort(sorted.begin(), sorted.end());
  for (std::uint64_t k : {std::uint64_t{0}, std::uint64_t{1}, std::uint64_t{n / 3}, std::uint64_t{n / 2}, std::uint64_t{n - 1}})
    EXPECT_EQ(mpi::kth_smallest(world(), v, k), sorted[k]) << "k = " << k;
  if (r == 0) std::printf("summary of %zu spheres on %d ranks (rank 0 empty): equal to the serial one\n", n, P);
}

TEST(MpiBlocks, FreshStartFromBlocksEqualsOneRank) {
  const Spheres all = pile(0.75);
  const SimConfig cfg = pile_config(all, std::sqrt(2 * total_mass(all) / 0.75), true, true);
  const Range b = dense(all.size());
  SimState block;
  block.sp = rows(all, b.lo, b.hi);
  const SphereSummary sum = mpi::summarise(world(), block.sp);
  mpi::DomainSim d(world(), block, mpi::DomainSim::Block{b.lo, sum, false, "pile"}, cfg);
  std::unique_ptr<Simulation> ref;
  if (world().rank == 0) ref = std::make_unique<Simulation>(all, cfg);
  for (int k = 0; k < 300; ++k) {
    d.step();
    if (ref) ref->step();
  }
  const SimState got = d.gather_state();
  // no rank evaluated the pairs of two ghosts (ContactSystem::set_owned); there were some
  long long foreign = d.stats().foreign_pairs;
  world().sum(&foreign, 1);
  if (world().size > 1) {
    EXPECT_GT(foreign, 0);
  }
  // pairs across two ranks are evaluated on both (counted, so their share can be reported)
  long long counts[2] = {d.stats().kernel_pairs, d.stats().shared_pairs};
  world().sum(counts, 2);
  EXPECT_GT(counts[0], 0);
  if (world().size > 1) {
    EXPECT_GT(counts[1], 0);
  }
  EXPECT_LT(counts[1], counts[0]);
  if (ref) {
    const double diff = state_diff(got, ref->state());
    std::printf("ghost-ghost pairs skipped over 300 steps, all ranks: %lld\n", foreign);
    std::printf("fresh start from blocks of <= %zu of %zu spheres, %d ranks, 300 steps: max |difference| %.3g, %zu contacts\n",
                b.hi - b.lo, all.size(), world().size, diff, got.history.size());
    EXPECT_EQ(diff, 0.0);
    EXPECT_GT(got.history.size(), 10u);
  }
}

TEST(MpiBlocks, MultirateRestartFromCheckpointBlocksEqualsOneRank) {
  // two piles closing at 1.5 (G = 1), 0.005 apart: in contact at the checkpoint
  Spheres all = pile(0.6);
  Spheres other = pile(0.6);
  for (Spheres* b : {&all, &other})  // cold piles: they collapse into contact under their own gravity
    for (std::size_t i = 0; i < b->size(); ++i) b->v[i] = b->w[i] = Vec3::Zero();
  double gap = INFINITY;  // between the bodies' spheres at an offset of 1.3
  for (std::size_t i = 0; i < all.size(); ++i)
    for (std::size_t j = 0; j < other.size(); ++j)
      gap = std::min(gap, (other.x[j] + Vec3(1.3, 0.1, 0.0) - all.x[i]).norm() - all.s[i] - other.s[j]);
  append_body(all, other, Vec3(1.3 - gap + 0.005, 0.1, 0.0), Vec3(-1.5, 0.0, 0.0));
  SimConfig cfg = pile_config(all, 2.0, true, true);
  cfg.multirate = true;
  cfg.pair_steps_per_contact = 30.0;
  cfg.gravity_max_every = 16;
  // rank 0: the one-rank run to a gravity block boundary past step 3000, its checkpoint file
  std::string dir;
  std::unique_ptr<Simulation> ref;
  if (world().rank == 0) {
    char tmpl[] = "/tmp/nbody_mpi_blocks.XXXXXX";
    dir = ::mkdtemp(tmpl);
    ref = std::make_unique<Simulation>(all, cfg);
    while (ref->step_count() < 3000 || !ref->at_gravity_boundary()) ref->step();
    const SimState st = ref->state();
    write_checkpoint(dir + "/checkpoint.h5", st, cfg.dt, st.gravity_block,
                     common::Provenance{"test_nbody_mpi_blocks", "1.0", "abcdef", "mpirun test", "[t]\n"},
                     cfg.contact.kn);
  }
  dir = world().bcast(dir);
  const std::string path = dir + "/checkpoint.h5";
  const CheckpointShape shape = checkpoint_shape(path);
  ASSERT_FALSE(shape.bonds);
  ASSERT_GE(shape.history, 10u);  // 16: the bodies' interface (the jittered lattices do not touch inside)
  const Range sb = dense(shape.spheres), hb = dense(shape.history);
  double dt0 = 0, kn0 = 0;
  int every0 = 0;
  SimState block = read_checkpoint_rows(path, common::h5::RowRange{sb.lo, sb.hi - sb.lo},
                                        common::h5::RowRange{hb.lo, hb.hi - hb.lo}, &dt0, &every0, &kn0);
  // each rank holds its rows only
  EXPECT_EQ(block.sp.size(), sb.hi - sb.lo);
  EXPECT_EQ(block.history.size(), hb.hi - hb.lo);
  EXPECT_EQ(block.level.size(), sb.hi - sb.lo);
  EXPECT_EQ(dt0, cfg.dt);
  EXPECT_EQ(kn0, cfg.contact.kn);
  block.gravity_block = every0;
  const SphereSummary sum = mpi::summarise(world(), block.sp);
  mpi::DomainSim d(world(), block, mpi::DomainSim::Block{sb.lo, sum, true, path}, cfg);
  const std::int64_t total = d.step_count() + 400;
  while (d.step_count() < total) d.step();
  const SimState got = d.gather_state();
  if (ref) {
    while (ref->step_count() < total) ref->step();
    const double diff = state_diff(got, ref->state());
    std::printf("multi-rate restart from checkpoint blocks (<= %zu of %zu spheres, <= %zu of %zu history records "
                "per rank), %d ranks, to step %lld: max |difference| %.3g\n",
                sb.hi - sb.lo, shape.spheres, hb.hi - hb.lo, shape.history, world().size,
                static_cast<long long>(total), diff);
    EXPECT_EQ(diff, 0.0);
    EXPECT_EQ(got.level, ref->state().level);
    std::filesystem::remove_all(dir);
  }
}

TEST(MpiBlocks, DuplicateIdAcrossBlocksAndUnknownHistoryIdGiveTheOneRankMessages) {
  Spheres all = pile(0.5);
  const std::size_t n = all.size();
  const SimConfig cfg = pile_config(all, 1.0, false, false);
  all.id[n - 2] = all.id[1];  // rows 1 and n - 2: in the first and the last block
  const Range b = dense(n);
  SimState block;
  block.sp = rows(all, b.lo, b.hi);
  const SphereSummary sum = mpi::summarise(world(), block.sp);
  const std::string want = "f.h5: /spheres/id: duplicate id " + std::to_string(all.id[1]) + " at rows 1 and " +
                           std::to_string(n - 2) + " (ids must be unique)";
  try {
    mpi::DomainSim d(world(), block, mpi::DomainSim::Block{b.lo, sum, false, "f.h5"}, cfg);
    ADD_FAILURE() << "no error";
  } catch (const common::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("duplicate id " + std::to_string(all.id[1]) + " at rows 1 and " +
                                         std::to_string(n - 2)), std::string::npos)
        << e.what() << " (one rank: " << want << ")";
  }
  // a restart whose history names a sphere that is in no block
  all.id[n - 2] = 1000000;
  block.sp = rows(all, b.lo, b.hi);
  HistoryRecord r;
  r.id_a = all.id[0];
  r.id_b = 999999;
  if (world().rank == world().size - 1) block.history.push_back(r);
  block.a.assign(block.sp.size(), Vec3::Zero());
  block.alpha = block.ag = block.a;
  try {
    mpi::DomainSim d(world(), block, mpi::DomainSim::Block{b.lo, mpi::summarise(world(), block.sp), true, "f.h5"}, cfg);
    ADD_FAILURE() << "no error";
  } catch (const common::InputError& e) {
    EXPECT_EQ(std::string(e.what()), "checkpoint contact history names an unknown sphere id");
  }
}
