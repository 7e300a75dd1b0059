/// @file test_mpm_mpi_work.cpp
/// ORB boxes weighted by work (label mpi; part of test_mpm_mpi; mpm/mpi/domain.hpp): each
/// particle weighs w_p = round(kWorkUnit (1 + sum_f work_f s_{f,p})) over its style's cost fields
/// (StateField::work; Tonge–Ramesh's damage sub-steps), the imbalance is max_r W_r / mean_r W_r
/// and a rebalancing cuts the histogram of work, not of particles. Scene: an elastic block at
/// rest along the grid, its style given a cost field of 10 in the upper half of the block along
/// the longest axis (a shocked region): the boxes by count put the heavy half on the last ranks
/// (imbalance ~1.8 on 2 and 3 ranks); after one rebalancing the boxes are the ORB of the global
/// work, the imbalance is below 1.1 and the cost field arrived with its particles.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "common/schema.hpp"
#include "mpi_test_helpers.hpp"
#include "mpm/memory_bounds.hpp"
#include "mpm/tonge_ramesh/style.hpp"

using namespace mpmfrag;
using namespace mpmtest;

namespace {

const std::string kBlock = R"(
[grid]
domain_min = [-0.03, -0.03, -0.03]
domain_max = [0.33, 0.07, 0.07]
cell_size = 0.005
[time]
end = 1e-4
[[material]]
name = "block"
model = "elastic"
density = 2700.0
bulk_modulus = 4.67e10
shear_modulus = 2.8e10
[[body]]
material = "block"
shape = "box"
min = [0.0, 0.0, 0.0]
max = [0.3, 0.04, 0.04]
ppc = 2
)";

/// The elastic style with one cost field ("cost", work 1 per unit), alive for the whole test.
const StyleInfo& costly_elastic() {
  static const StyleInfo s = [] {
    StyleInfo e = *builtin_materials().find("elastic");
    e.name = "elastic_with_cost";
    e.state_fields.push_back({"cost", 1, "1", 0.0, false, "test cost weight", 1.0});
    return e;
  }();
  return s;
}

constexpr double kHeavyFrom = 0.15;  // x beyond which a particle costs 1 + 10 plain ones
constexpr double kCost = 10.0;

/// The block's set-up with the costly style; the cost field is kCost beyond kHeavyFrom.
Setup costly_block() {
  static const common::Schema schema = mpm_schema();
  Setup s = build_setup(common::Scene::parse(schema, kBlock, "work-test"));
  MaterialSlot& m = s.materials.at(0);
  m.style = &costly_elastic();
  m.allocate_state();
  for (std::size_t p = m.begin; p < m.end; ++p) m.state.back()[p - m.begin] = s.particles.x[3 * p] > kHeavyFrom ? kCost : 0.0;
  return s;
}

}  // namespace

TEST(MpmMpiWork, WeightsAreOnePlusTheStylesCostFields) {
  const mpmfrag::Setup s = costly_block();
  const std::vector<long long> w = mpi::work_weights(s.particles, s.materials);
  ASSERT_EQ(w.size(), s.particles.size());
  std::size_t heavy = 0;
  for (std::size_t p = 0; p < w.size(); ++p) {
    const bool h = s.particles.x[3 * p] > kHeavyFrom;
    heavy += h;
    EXPECT_EQ(w[p], h ? 11 * mpi::kWorkUnit : mpi::kWorkUnit) << p;
  }
  EXPECT_EQ(2 * heavy, w.size());  // half the block
  // a style without cost fields: one unit each
  mpmfrag::Setup plain = s;
  plain.materials[0].style = builtin_materials().find("elastic");
  plain.materials[0].state.pop_back();
  for (const long long x : mpi::work_weights(plain.particles, plain.materials)) ASSERT_EQ(x, mpi::kWorkUnit);
  // Tonge-Ramesh declares its damage sub-steps M as the cost field, 0.6 plain steps each
  // (the measured ratio of a sub-step to a particle's grid transfers, style.cpp)
  const std::vector<StateField> tr = tonge_ramesh_state_fields();
  ASSERT_EQ(tr.back().name, "damage_substeps");
  EXPECT_DOUBLE_EQ(tr.back().work, 0.6);
  EXPECT_FALSE(tr.back().output);
  for (std::size_t f = 0; f + 1 < tr.size(); ++f) EXPECT_EQ(tr[f].work, 0.0) << tr[f].name;
  mpmfrag::Setup trs = s;
  trs.materials[0].style = builtin_materials().find("tonge_ramesh");
  ASSERT_NE(trs.materials[0].style, nullptr);
  trs.materials[0].allocate_state();
  trs.materials[0].state.back()[0] = 875.0;
  const std::vector<long long> wt = mpi::work_weights(trs.particles, trs.materials);
  EXPECT_EQ(wt[0], std::llround(64.0 * (1.0 + 0.6 * 875.0)));
  EXPECT_EQ(wt[1], std::llround(64.0 * 1.6));  // M = 1: a plain update
}

TEST(MpmMpiWork, RebalancingCutsTheWorkNotTheCount) {
  const mpmfrag::Setup full = costly_block();
  mpi::DomainOptions opt;
  opt.rebalance_every = 1;
  opt.imbalance_threshold = 1.1;
  // room for the whole grid and 4 x every particle's bytes: any box by count fits, its particle
  // bytes taken as 64 x their work would not (the memory check counts particles)
  opt.node_memory = 1e18;
  opt.process_memory = 88.0 * full.grid.shape.cast<double>().prod() + 4.0 * process_bytes(0.0, full.materials);
  DomainSolver d(MPI_COMM_WORLD, full, opt);
  const mpi::Orb by_count = d.orb();
  const double before = d.imbalance();
  // the ORB of the work, from the full set-up (the particles stay at rest)
  const std::vector<long long> w = mpi::work_weights(full.particles, full.materials);
  long long total = 0;
  for (std::size_t p = 0; p < w.size(); ++p) total += w[p];
  const mpi::Orb by_work = orb_of(full.grid, ranks(), d.orb().min_width, full.particles, w);
  ASSERT_FALSE(by_work == by_count);
  EXPECT_TRUE(orb_of(full.grid, ranks(), d.orb().min_width, full.particles) == by_count);
  EXPECT_GT(before, 1.7) << "the heavy half on the last ranks";
  for (int k = 0; k < 2; ++k) d.step(0.1 * d.stable_dt());  // checks at step 1: a rebalancing
  EXPECT_EQ(d.stats().rebalances, 1);
  EXPECT_EQ(d.stats().rebalances_skipped, 0);
  EXPECT_EQ(d.stats().imbalance_checks, 1);
  EXPECT_DOUBLE_EQ(d.stats().imbalance_max, before);
  EXPECT_TRUE(d.orb() == by_work) << d.orb().describe() << " instead of " << by_work.describe();
  EXPECT_LT(d.imbalance(), 1.1);
  // the cost field moved with its particles: the same total work, and each particle's field
  // still says where it was heavy (the block is at rest: x changed by far less than a cell)
  const Solver& s = d.local();
  std::vector<long long> mine = mpi::work_weights(s.particles(), s.materials());
  long long sum = 0;
  for (const long long x : mine) sum += x;
  d.comm().sum(&sum, 1);
  EXPECT_EQ(sum, total);
  const MaterialSlot& m = s.materials().at(0);
  for (std::size_t p = m.begin; p < m.end; ++p)
    ASSERT_EQ(m.state.back()[p - m.begin], s.particles().x[3 * p] > kHeavyFrom ? kCost : 0.0) << p;
}

// A restart on another rank count (no tree in the file's layout; each rank passes its block of the
// file's rows) cuts the work, not the count.
TEST(MpmMpiWork, RestartOnAnotherRankCountCutsTheWork) {
  const mpmfrag::Setup full = costly_block();
  DomainSolver ref(MPI_COMM_WORLD, full);
  const mpi::Orb by_count = ref.orb();
  ref.rebalance();  // the tree of the work (rebalance() recomputes it unconditionally)
  const mpi::Orb by_work = ref.orb();
  ASSERT_FALSE(by_work == by_count);
  const std::size_t n = full.particles.size();
  const std::size_t lo = n * static_cast<std::size_t>(rank()) / static_cast<std::size_t>(ranks());
  const std::size_t hi = n * static_cast<std::size_t>(rank() + 1) / static_cast<std::size_t>(ranks());
  std::vector<char> keep(n, 0);
  std::fill(keep.begin() + static_cast<std::ptrdiff_t>(lo), keep.begin() + static_cast<std::ptrdiff_t>(hi), 1);
  mpmfrag::Setup part = full;
  mpi::select_particles(full.particles, full.materials, keep, part.particles, part.materials);
  mpi::Layout layout;  // no tree: written on another rank count
  layout.first = lo;
  DomainSolver d(MPI_COMM_WORLD, part, layout);
  EXPECT_TRUE(d.orb() == by_work);
  long long total = static_cast<long long>(d.local().particles().size());
  d.comm().sum(&total, 1);
  EXPECT_EQ(total, static_cast<long long>(n));
}
