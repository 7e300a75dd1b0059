/// @file test_mpm_mpi_setup.cpp
/// The distributed set-up of mpm-frag on MPI ranks (label mpi; part of test_mpm_mpi): every rank
/// generating the scene itself and keeping its own slab (distributed_setup) must give, on every
/// rank, the same particles in the same order, the same material state arrays and the same cuts
/// as the full set-up split by DomainSolver(comm, build_setup(scene)), bit for bit; and the
/// bodies' totals (mass, centre of mass: exact bodies shifted and scaled over all their
/// particles) and the drives' id ranges of the whole scene. Scene: a Tonge–Ramesh sphere and an
/// elastic sphere (exact bodies, the default) and a driven platen. And the cuts' rule
/// (balanced_cuts): each cut is the plane boundary nearest its target.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

#include "common/schema.hpp"
#include "mpi_test_helpers.hpp"
#include "mpm/memory_bounds.hpp"

using namespace mpmfrag;
using namespace mpmtest;

namespace {

const std::string kScene = R"(
[grid]
domain_min = [0.0, 0.0, 0.0]
domain_max = [0.3, 0.1, 0.1]
cell_size = 0.01
[time]
end = 1e-4
)" + kRockAndSoft + R"(
[[body]]
material = "rock"
shape = "sphere"
center = [0.1, 0.05, 0.05]
radius = 0.031
velocity = [150.0, 0.0, 0.0]
[[body]]
material = "soft"
shape = "sphere"
center = [0.171, 0.05, 0.05]
radius = 0.0123
velocity = [-300.0, 0.0, 0.0]
[[body]]
material = "soft"
shape = "box"
min = [0.22, 0.02, 0.02]
max = [0.28, 0.08, 0.08]
drive.enabled = true
drive.velocity = [-1.0, 0.0, 0.0]
)";

TEST(MpmMpi, DistributedSetupEqualsTheFullSetupSplit) {
  static const common::Schema schema = mpm_schema();
  const common::Scene scene = common::Scene::parse(schema, kScene, "setup-test");
  const mpmfrag::Setup full = build_setup(scene);
  DomainSolver a(MPI_COMM_WORLD, full);
  const std::pair<mpmfrag::Setup, std::vector<int>> part = mpi::distributed_setup(MPI_COMM_WORLD, scene);
  DomainSolver b(MPI_COMM_WORLD, part.first, part.second);
  // the collectives first (an assertion that fails on some ranks only must not leave the others
  // waiting in one)
  long long n[2] = {static_cast<long long>(b.local().particles().size()), static_cast<long long>(part.first.particles.size())};
  b.comm().sum(n, 2);
  const std::pair<mpmfrag::Setup, std::vector<int>> none = mpi::distributed_setup(MPI_COMM_WORLD, scene, false);
  EXPECT_EQ(none.first.particles.size(), 0u) << "a restart's set-up holds no particles";
  EXPECT_EQ(none.first.materials.size(), full.materials.size());
  EXPECT_EQ(n[0], static_cast<long long>(full.particles.size()));
  EXPECT_EQ(n[1], static_cast<long long>(full.particles.size())) << "each particle generated on exactly one rank";
  // on every rank: the same cuts, particles (every array, bit for bit) and material ranges
  EXPECT_EQ(part.second, a.slabs().cut);
  const ParticleSet &pa = a.local().particles(), &pb = b.local().particles();
  ASSERT_EQ(pa.size(), pb.size());
  ParticleSet::for_each_array([&](const auto& arr) { EXPECT_TRUE(pa.*arr.member == pb.*arr.member) << arr.info.name; });
  ASSERT_EQ(a.local().materials().size(), b.local().materials().size());
  for (std::size_t m = 0; m < a.local().materials().size(); ++m) {
    const MaterialSlot &ma = a.local().materials()[m], &mb = b.local().materials()[m];
    EXPECT_EQ(ma.begin, mb.begin);
    EXPECT_EQ(ma.end, mb.end);
    EXPECT_TRUE(ma.state == mb.state) << ma.name;
  }
  // the whole scene's bodies and drives on every rank: each body's mass the sum of its particles
  // in id order (as one process sums them), the driven body's M_k the same bits
  ASSERT_EQ(part.first.bodies.size(), full.bodies.size());
  std::vector<std::size_t> by_id(full.particles.size());
  for (std::size_t p = 0; p < full.particles.size(); ++p) by_id[full.particles.id[p]] = p;
  std::uint64_t first = 0;
  for (std::size_t i = 0; i < full.bodies.size(); ++i) {
    const BodyInfo& bi = part.first.bodies[i];
    double mass = 0;
    for (std::uint64_t id = first; id < first + bi.particles; ++id) mass += full.particles.mass[by_id[id]];
    first += bi.particles;
    EXPECT_EQ(bi.particles, full.bodies[i].particles);
    EXPECT_EQ(bi.mass, mass) << "body " << i;
    EXPECT_EQ(bi.mass_center, full.bodies[i].mass_center);
    EXPECT_EQ(bi.lattice_center, full.bodies[i].lattice_center);
  }
  ASSERT_EQ(part.first.drives.size(), 1u);
  EXPECT_EQ(part.first.drives[0].id_begin, full.drives[0].id_begin);
  EXPECT_EQ(part.first.drives[0].id_end, full.drives[0].id_end);
  EXPECT_EQ(part.first.drives[0].mass, part.first.bodies[2].mass);
  if (rank() == 0)
    std::printf("%d ranks: distributed set-up of %zu particles equals the full set-up split (cuts", ranks(),
                full.particles.size());
  if (rank() == 0) {
    for (int c : part.second) std::printf(" %d", c);
    std::printf(")\n");
  }
}

}  // namespace

namespace {

// A small body at one end of a long domain: the slabs balance particles, so the last rank holds
// nearly all the empty planes, far more than 1/P of the grid.
const std::string kLopsided = R"(
[grid]
domain_min = [0.0, 0.0, 0.0]
domain_max = [3.0, 0.1, 0.1]
cell_size = 0.01
[time]
end = 1e-4
)" + kRockAndSoft + R"(
[[body]]
material = "soft"
shape = "box"
min = [0.0, 0.02, 0.02]
max = [0.12, 0.08, 0.08]
)";

TEST(MpmMpi, EachRankChecksItsOwnSlabsMemoryBeforeTheGrid) {
  static const common::Schema schema = mpm_schema();
  const common::Scene scene = common::Scene::parse(schema, kLopsided, "lopsided");
  const std::pair<mpmfrag::Setup, std::vector<int>> part = mpi::distributed_setup(MPI_COMM_WORLD, scene);
  // every rank's need, as check_memory computes it (box nodes and particles)
  const std::vector<int>& cut = part.second;
  const common::GridInfo& g = part.first.grid;
  const int a = 0;  // the longest axis
  std::vector<double> need(ranks());
  for (int r = 0; r < ranks(); ++r) {
    const int lo = std::max(0, cut[r] - 2), hi = std::min(g.shape[a], cut[r + 1] + 2);
    need[r] = 88.0 * (hi - lo) * g.shape[1] * g.shape[2];
  }
  double mine = process_bytes(0.0, part.first.materials);  // this rank's particles
  std::vector<double> parts(ranks(), 0.0);
  parts[rank()] = mine;
  MPI_Allreduce(MPI_IN_PLACE, parts.data(), ranks(), MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
  for (int r = 0; r < ranks(); ++r) need[r] += parts[r];
  const double largest = *std::max_element(need.begin(), need.end());
  double total_need = 0;
  for (double n : need) total_need += n;
  const int worst = static_cast<int>(std::max_element(need.begin(), need.end()) - need.begin());
  EXPECT_EQ(worst, ranks() - 1) << "the rank beside the empty space needs the most";
  // the first check's share (total / P) would let this limit pass; the slab's own need does not
  const double limit = 0.97 * largest;
  EXPECT_LT(estimate_memory(scene).total() / ranks(), limit);
  mpi::DomainOptions opt;
  opt.process_memory = limit;
  opt.node_memory = 1e18;
  std::string what;
  try {
    DomainSolver d(MPI_COMM_WORLD, part.first, part.second, opt);
  } catch (const common::InputError& e) {
    what = e.what();
  }
  EXPECT_NE(what.find("MPI rank " + std::to_string(worst) + "'s slab"), std::string::npos) << "rank " << rank() << ": '" << what << "'";
  EXPECT_NE(what.find("grid.cell_size"), std::string::npos);
  // the node's ranks together (all on this machine) against the node's memory, each rank within
  // its own limit
  opt.process_memory = 1e18;
  opt.node_memory = 0.99 * total_need;
  what.clear();
  try {
    DomainSolver d(MPI_COMM_WORLD, part.first, part.second, opt);
  } catch (const common::InputError& e) {
    what = e.what();
  }
  EXPECT_NE(what.find("'s slab"), std::string::npos) << "rank " << rank() << ": '" << what << "'";
  // enough memory: the solver is built
  opt.node_memory = 1.01 * total_need;
  opt.process_memory = 1.01 * largest;
  EXPECT_NO_THROW(DomainSolver(MPI_COMM_WORLD, part.first, part.second, opt));
}

}  // namespace

namespace {

// Every particle on rank 0 of cuts that give the other ranks min_width empty planes each at the
// far end; `limit_last`: the last rank's process memory (others unlimited).
mpmfrag::Setup rank0_holds_all(const mpmfrag::Setup& full) {
  mpmfrag::Setup mine = full;
  std::vector<char> keep(full.particles.size(), rank() == 0 ? 1 : 0);
  mine.particles = ParticleSet();
  mine.materials.clear();
  mpi::select_particles(full.particles, full.materials, keep, mine.particles, mine.materials);
  return mine;
}

TEST(MpmMpi, RebalancingThatWouldOverfillARankIsLeftOut) {
  static const common::Schema schema = mpm_schema();
  const common::Scene scene = common::Scene::parse(schema, kLopsided, "lopsided");
  const mpmfrag::Setup full = build_setup(scene);
  const mpmfrag::Setup mine = rank0_holds_all(full);
  const int S = full.grid.shape[0], W = 4;
  std::vector<int> cut(ranks() + 1);
  for (int r = 1; r < ranks(); ++r) cut[r] = S - (ranks() - r) * W;
  cut[0] = 0;
  cut[ranks()] = S;
  const double plane = 88.0 * full.grid.shape[1] * full.grid.shape[2];
  mpi::DomainOptions opt;
  opt.rebalance_every = 1;
  opt.imbalance_threshold = 1.01;
  opt.node_memory = 1e18;
  // the last rank may hold twice its present box, far less than the empty planes balancing hands it
  opt.process_memory = rank() == ranks() - 1 ? 2.0 * (W + 2) * plane : 1e18;
  {
    DomainSolver d(MPI_COMM_WORLD, mine, cut, opt);
    for (int k = 0; k < 3; ++k) d.step(0.1 * d.stable_dt());
    EXPECT_EQ(d.stats().rebalances, 0);
    EXPECT_EQ(d.stats().rebalances_skipped, 2);  // steps 1 and 2 (none at step 0)
    EXPECT_EQ(d.slabs().cut, cut);
    long long n = static_cast<long long>(d.local().particles().size());
    d.comm().sum(&n, 1);
    EXPECT_EQ(n, static_cast<long long>(full.particles.size()));
  }
  opt.process_memory = 1e18;  // room: the cuts balance the particles
  DomainSolver d(MPI_COMM_WORLD, mine, cut, opt);
  for (int k = 0; k < 3; ++k) d.step(0.1 * d.stable_dt());
  EXPECT_GE(d.stats().rebalances, 1);
  EXPECT_EQ(d.stats().rebalances_skipped, 0);
  EXPECT_NE(d.slabs().cut, cut);
}

}  // namespace

// The cuts (balanced_cuts, slabs.cpp): each is the plane boundary whose cumulative count is nearest
// its target r N / R. A heavy plane just past the half (a thin shocked shell on a coarse grid):
// counts 1 1 1 10 1 1 (N = 15) are cut before it (3 | 12), not after it (13 | 2, the first
// crossing, the rule before 2026-12-07). For 2 ranks that is the cut with the smallest larger
// slab: checked against every cut on random counts with heavy planes (the first-crossing rule
// fails this). Uniform counts are cut evenly, a tie keeps the first crossing, the narrowest slab
// binds, and with 3 ranks each cut takes its own nearest boundary.
TEST(MpmMpiCuts, EachCutIsTheBoundaryNearestItsTarget) {
  using V = std::vector<int>;
  EXPECT_EQ(mpi::balanced_cuts({1, 1, 1, 10, 1, 1}, 2, 1), (V{0, 3, 6}));
  EXPECT_EQ(mpi::balanced_cuts(std::vector<long long>(12, 5), 2, 1), (V{0, 6, 12}));
  EXPECT_EQ(mpi::balanced_cuts(std::vector<long long>(12, 5), 3, 1), (V{0, 4, 8, 12}));
  EXPECT_EQ(mpi::balanced_cuts({1, 4, 1, 4}, 2, 1), (V{0, 2, 4}));              // 5 | 5
  EXPECT_EQ(mpi::balanced_cuts({2, 2, 2, 2, 2}, 2, 1), (V{0, 3, 5}));           // 6 | 4 or 4 | 6: the first
  EXPECT_EQ(mpi::balanced_cuts({10, 1, 1, 1, 1, 1, 1, 1}, 2, 3), (V{0, 3, 8}));  // nearest is 1: W = 3 binds
  std::vector<long long> c(30, 1);  // N = 108, targets 36 and 72: 49 | 9 | 50
  c[9] = c[19] = 40;
  EXPECT_EQ(mpi::balanced_cuts(c, 3, 2), (V{0, 10, 19, 30}));
  std::mt19937_64 rng(5);
  for (int k = 0; k < 500; ++k) {
    const int planes = 4 + static_cast<int>(rng() % 20);
    std::vector<long long> n(static_cast<std::size_t>(planes));
    for (auto& v : n) v = rng() % 7 == 0 ? static_cast<long long>(rng() % 1000) : static_cast<long long>(rng() % 20);
    long long total = 0;
    for (long long v : n) total += v;
    long long best = total, left = 0;
    for (int P = 1; P < planes; ++P) {
      left += n[static_cast<std::size_t>(P - 1)];
      best = std::min(best, std::max(left, total - left));
    }
    const V cut = mpi::balanced_cuts(n, 2, 1);
    long long got = 0;
    for (int q = 0; q < cut[1]; ++q) got += n[static_cast<std::size_t>(q)];
    EXPECT_EQ(std::max(got, total - got), best) << "case " << k;
  }
}
