/// @file test_mpm_mpi_setup.cpp
/// The distributed set-up of mpm-frag on MPI ranks (label mpi; part of test_mpm_mpi): every rank
/// generating the scene itself and keeping its own box (distributed_setup) must give, on every
/// rank, the same particles in the same order, the same material state arrays and the same tree
/// as the full set-up split by DomainSolver(comm, build_setup(scene)), bit for bit; and the
/// bodies' totals (mass, centre of mass: exact bodies shifted and scaled over all their
/// particles) and the drives' id ranges of the whole scene. Scene: a Tonge–Ramesh sphere and an
/// elastic sphere (exact bodies, the default) and a driven platen. And the cuts' rule
/// (nearest_cut): each cut is the plane boundary nearest its target; the ORB (orb_cuts).
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
  const std::pair<mpmfrag::Setup, mpi::Orb> part = mpi::distributed_setup(MPI_COMM_WORLD, scene);
  DomainSolver b(MPI_COMM_WORLD, part.first, part.second);
  // the collectives first (an assertion that fails on some ranks only must not leave the others
  // waiting in one)
  long long n[2] = {static_cast<long long>(b.local().particles().size()), static_cast<long long>(part.first.particles.size())};
  b.comm().sum(n, 2);
  const std::pair<mpmfrag::Setup, mpi::Orb> none = mpi::distributed_setup(MPI_COMM_WORLD, scene, false);
  EXPECT_EQ(none.first.particles.size(), 0u) << "a restart's set-up holds no particles";
  EXPECT_EQ(none.first.materials.size(), full.materials.size());
  EXPECT_EQ(n[0], static_cast<long long>(full.particles.size()));
  EXPECT_EQ(n[1], static_cast<long long>(full.particles.size())) << "each particle generated on exactly one rank";
  // on every rank: the same tree, particles (every array, bit for bit) and material ranges
  EXPECT_TRUE(part.second == a.orb());
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
    std::printf("%d ranks: distributed set-up of %zu particles equals the full set-up split (%s)\n", ranks(),
                full.particles.size(), part.second.describe().c_str());
}

}  // namespace

namespace {

// A small body at one end of a long domain: the boxes balance particles, so the last rank holds
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

TEST(MpmMpi, EachRankChecksTheMemoryOfItsOwnBoxBeforeTheGrid) {
  static const common::Schema schema = mpm_schema();
  const common::Scene scene = common::Scene::parse(schema, kLopsided, "lopsided");
  const std::pair<mpmfrag::Setup, mpi::Orb> part = mpi::distributed_setup(MPI_COMM_WORLD, scene);
  // every rank's need, as check_memory computes it (box nodes and particles)
  std::vector<double> need(ranks());
  for (int r = 0; r < ranks(); ++r) need[r] = 88.0 * static_cast<double>(part.second.held(r).size());
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
  // the first check's share (total / P) would let this limit pass; the box's own need does not
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
  EXPECT_NE(what.find("MPI rank " + std::to_string(worst) + "'s box"), std::string::npos) << "rank " << rank() << ": '" << what << "'";
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
  EXPECT_NE(what.find("'s box"), std::string::npos) << "rank " << rank() << ": '" << what << "'";
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
  mpi::Orb slabs;  // slabs along x as a tree of cuts
  slabs.shape = full.grid.shape;
  slabs.min_width = W;
  ASSERT_TRUE(slabs.set(mpi::Orb::slabs(0, cut)));
  const double plane = 88.0 * full.grid.shape[1] * full.grid.shape[2];
  mpi::DomainOptions opt;
  opt.rebalance_every = 1;
  opt.imbalance_threshold = 1.01;
  opt.node_memory = 1e18;
  // the last rank may hold twice its present box, far less than the empty planes balancing hands it
  opt.process_memory = rank() == ranks() - 1 ? 2.0 * (W + 2) * plane : 1e18;
  {
    DomainSolver d(MPI_COMM_WORLD, mine, slabs, opt);
    for (int k = 0; k < 3; ++k) d.step(0.1 * d.stable_dt());
    EXPECT_EQ(d.stats().rebalances, 0);
    EXPECT_EQ(d.stats().rebalances_skipped, 2);  // steps 1 and 2 (none at step 0)
    EXPECT_TRUE(d.orb() == slabs);
    long long n = static_cast<long long>(d.local().particles().size());
    d.comm().sum(&n, 1);
    EXPECT_EQ(n, static_cast<long long>(full.particles.size()));
  }
  opt.process_memory = 1e18;  // room: the boxes balance the particles
  DomainSolver d(MPI_COMM_WORLD, mine, slabs, opt);
  for (int k = 0; k < 3; ++k) d.step(0.1 * d.stable_dt());
  EXPECT_GE(d.stats().rebalances, 1);
  EXPECT_EQ(d.stats().rebalances_skipped, 0);
  EXPECT_FALSE(d.orb() == slabs);
}

}  // namespace

// The cut of a node of the tree (nearest_cut, orb.cpp): the plane boundary whose cumulative count
// is nearest its target N n_l / n. A heavy plane just past the half (a thin shocked shell on a
// coarse grid): counts 1 1 1 10 1 1 (N = 15) are cut before it (3 | 12), not after it (13 | 2, the
// first crossing, the rule before 2026-12-07). For halves that is the cut with the smallest
// larger side: checked against every cut on random counts with heavy planes (the first-crossing
// rule fails this). Uniform counts are cut evenly, a tie keeps the first crossing, the narrowest
// side binds, a third takes its own nearest boundary.
TEST(MpmMpiCuts, EachCutIsTheBoundaryNearestItsTarget) {
  using W = std::vector<long long>;
  EXPECT_EQ(mpi::nearest_cut({1, 1, 1, 10, 1, 1}, 1, 2, 1, 5), 3);
  EXPECT_EQ(mpi::nearest_cut(W(12, 5), 1, 2, 1, 11), 6);
  EXPECT_EQ(mpi::nearest_cut(W(12, 5), 1, 3, 1, 11), 4);
  EXPECT_EQ(mpi::nearest_cut({1, 4, 1, 4}, 1, 2, 1, 3), 2);               // 5 | 5
  EXPECT_EQ(mpi::nearest_cut({2, 2, 2, 2, 2}, 1, 2, 1, 4), 3);            // 6 | 4 or 4 | 6: the first
  EXPECT_EQ(mpi::nearest_cut({10, 1, 1, 1, 1, 1, 1, 1}, 1, 2, 3, 5), 3);  // nearest is 1: W = 3 binds
  W c(30, 1);  // N = 108, target 36: 49 | 59 (after the heavy plane 9: 9 | 99 is farther)
  c[9] = c[19] = 40;
  EXPECT_EQ(mpi::nearest_cut(c, 1, 3, 2, 28), 10);
  std::mt19937_64 rng(5);
  for (int k = 0; k < 500; ++k) {
    const int planes = 4 + static_cast<int>(rng() % 20);
    W n(static_cast<std::size_t>(planes));
    for (auto& v : n) v = rng() % 7 == 0 ? static_cast<long long>(rng() % 1000) : static_cast<long long>(rng() % 20);
    long long total = 0;
    for (long long v : n) total += v;
    long long best = total, left = 0;
    for (int P = 1; P < planes; ++P) {
      left += n[static_cast<std::size_t>(P - 1)];
      best = std::min(best, std::max(left, total - left));
    }
    const int cut = mpi::nearest_cut(n, 1, 2, 1, planes - 1);
    long long got = 0;
    for (int q = 0; q < cut; ++q) got += n[static_cast<std::size_t>(q)];
    EXPECT_EQ(std::max(got, total - got), best) << "case " << k;
  }
}

// The ORB (orb_cuts, orb.cpp) of random weights on a 23 x 17 x 11 grid for 1 to 9 ranks: the
// boxes partition the grid (owner() agrees with the box containing every cell), each node is cut
// along its box's longest axis at the nearest_cut of its own histogram for floor(n / 2) ranks,
// every side at least W planes; the file form round-trips; slab cuts as a chain give the slabs'
// boxes; too many ranks for the grid is an input error naming the ranks.
TEST(MpmMpiCuts, OrbBoxesPartitionTheGridAndEachCutIsNearestItsShare) {
  const Eigen::Vector3i shape(23, 17, 11);
  std::mt19937_64 rng(11);
  std::vector<long long> w(static_cast<std::size_t>(shape.prod()));
  for (auto& v : w) v = rng() % 9 == 0 ? static_cast<long long>(rng() % 500) : static_cast<long long>(rng() % 4);
  auto at = [&](const Eigen::Vector3i& c) { return w[static_cast<std::size_t>(c[0] + shape[0] * (c[1] + shape[1] * c[2]))]; };
  auto weigh = [&](const std::vector<mpi::OrbRequest>& req, const std::function<int(const Eigen::Vector3i&)>& locate) {
    std::vector<std::vector<long long>> h(req.size());
    for (std::size_t q = 0; q < req.size(); ++q) h[q].assign(static_cast<std::size_t>(req[q].box.hi[req[q].axis] - req[q].box.lo[req[q].axis]), 0);
    for (int k = 0; k < shape[2]; ++k)
      for (int j = 0; j < shape[1]; ++j)
        for (int i = 0; i < shape[0]; ++i) {
          const Eigen::Vector3i c(i, j, k);
          const int q = locate(c);
          if (q >= 0) h[q][c[req[q].axis] - req[q].box.lo[req[q].axis]] += at(c);
        }
    return h;
  };
  for (int R = 1; R <= 9; ++R) {
    const mpi::Orb orb = mpi::orb_cuts(shape, R, 2, 3, weigh);
    ASSERT_EQ(orb.ranks(), R);
    ASSERT_EQ(orb.split.size(), static_cast<std::size_t>(R - 1));
    long long cells = 0;
    for (const mpi::Box& b : orb.own()) cells += b.size();
    EXPECT_EQ(cells, shape.prod()) << R;
    for (int k = 0; k < shape[2]; ++k)
      for (int j = 0; j < shape[1]; ++j)
        for (int i = 0; i < shape[0]; ++i) {
          const Eigen::Vector3i c(i, j, k);
          const int r = orb.owner(c);
          ASSERT_TRUE(r >= 0 && r < R && orb.own()[static_cast<std::size_t>(r)].contains(c)) << R << ": cell " << c.transpose();
        }
    // every split again from its node's box: walk the preorder with the boxes
    struct Item {
      mpi::Box box;
      int n;
    };
    std::vector<Item> stack{{mpi::Box{Eigen::Vector3i::Zero(), shape}, R}};
    std::size_t k = 0;
    while (!stack.empty()) {
      const Item it = stack.back();
      stack.pop_back();
      if (it.n == 1) continue;
      const mpi::Orb::Split& s = orb.split[k++];
      const Eigen::Vector3i wd = it.box.hi - it.box.lo;
      int a = 0;
      for (int d = 1; d < 3; ++d)
        if (wd[d] > wd[a]) a = d;
      EXPECT_EQ(s.axis, a) << R;
      EXPECT_EQ(s.left, it.n / 2) << R;
      std::vector<long long> h(static_cast<std::size_t>(wd[a]), 0);
      for (int z = it.box.lo[2]; z < it.box.hi[2]; ++z)
        for (int y = it.box.lo[1]; y < it.box.hi[1]; ++y)
          for (int x = it.box.lo[0]; x < it.box.hi[0]; ++x) {
            const Eigen::Vector3i c(x, y, z);
            h[static_cast<std::size_t>(c[a] - it.box.lo[a])] += at(c);
          }
      const bool roomy = wd[a] >= 3 * it.n;
      const int lo = roomy ? 3 * s.left : 3, hi = wd[a] - (roomy ? 3 * (it.n - s.left) : 3);
      EXPECT_EQ(s.cut - it.box.lo[a], mpi::nearest_cut(h, s.left, it.n, lo, hi)) << R;
      EXPECT_GE(s.cut - it.box.lo[a], 3);
      EXPECT_GE(it.box.hi[a] - s.cut, 3);
      mpi::Box lower = it.box, upper = it.box;
      lower.hi[a] = upper.lo[a] = s.cut;
      stack.push_back({upper, it.n - s.left});
      stack.push_back({lower, s.left});
    }
    mpi::Orb back;
    back.shape = shape;
    back.min_width = 3;
    ASSERT_TRUE(back.set(mpi::Orb::unflat(orb.flat())));
    EXPECT_TRUE(back == orb);
    EXPECT_EQ(back.own(), orb.own());
  }
  mpi::Orb sl;  // slab cuts along y
  sl.shape = shape;
  sl.min_width = 3;
  ASSERT_TRUE(sl.set(mpi::Orb::slabs(1, {0, 4, 9, 13, 17})));
  for (int r = 0; r < 4; ++r) {
    const int lo[] = {0, 4, 9, 13, 17};
    EXPECT_EQ(sl.own()[static_cast<std::size_t>(r)], (mpi::Box{Eigen::Vector3i(0, lo[r], 0), Eigen::Vector3i(23, lo[r + 1], 11)}));
  }
  EXPECT_FALSE(sl.set(mpi::Orb::slabs(1, {0, 4, 6, 13, 17})));  // a slab of 2 planes: too narrow
  EXPECT_EQ(sl.ranks(), 4) << "a refused tree leaves the one before";
  EXPECT_FALSE(sl.set({{0, 10, 2}}));                       // left must be in [1, n - 1]
  EXPECT_FALSE(sl.set({{3, 10, 1}}));                       // no axis 3
  EXPECT_FALSE(sl.set({{0, 10, 1}, {0, 5, 1}}));              // the second cut lies outside its node's box [10, 23)
  EXPECT_TRUE(sl.set({{0, 10, 2}, {1, 8, 1}, {1, 8, 1}}));   // 2 x 2 boxes
  EXPECT_EQ(sl.owner(Eigen::Vector3i(12, 3, 0)), 2);
  EXPECT_EQ(sl.owner(Eigen::Vector3i(12, 9, 0)), 3);
  EXPECT_EQ(sl.owner(Eigen::Vector3i(9, 9, 10)), 1);
  // all the weight in the first planes of a box narrower than W R along its longest axis: each
  // side keeps the planes its ranks need across the other two axes (24 x 8 x 6, 8 ranks of W = 4:
  // up to 12 boxes of 4 x 4 x 6 fit; the rule "W a side" left a 4 x 4 x 6 box for 2 ranks and threw)
  const Eigen::Vector3i thin(24, 8, 6);
  const mpi::Orb packed = mpi::orb_cuts(thin, 8, 2, 4, [&](const std::vector<mpi::OrbRequest>& req, const std::function<int(const Eigen::Vector3i&)>&) {
    std::vector<std::vector<long long>> h(req.size());
    for (std::size_t q = 0; q < req.size(); ++q) {
      h[q].assign(static_cast<std::size_t>(req[q].box.hi[req[q].axis] - req[q].box.lo[req[q].axis]), 1);
      if (req[q].axis == 0 && req[q].box.lo[0] == 0) h[q][0] = 1000000;
    }
    return h;
  });
  for (const mpi::Box& b : packed.own()) EXPECT_GE((b.hi - b.lo).minCoeff(), 4) << packed.describe();
  try {
    (void)mpi::orb_cuts(shape, 200, 2, 3, weigh);
    ADD_FAILURE() << "200 ranks on 23 x 17 x 11 cells of at least 3 planes";
  } catch (const common::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("200 MPI ranks"), std::string::npos) << e.what();
  }
}
