/// @file test_outflow.cpp
/// Hand-off of particles that left the MPM grid (outflow.hpp): ballistic positions at the snapshot
/// time, one sphere per lattice cell outside the grid, merging into an existing edge sphere,
/// mass and momentum exact, spheres never sharing a cell.
#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "common/status.hpp"
#include "handoff/run_handoff.hpp"
#include "particle_sets.hpp"

using namespace handoff;

namespace {

HandoffConfig config(int coarsen = 1) {
  HandoffConfig c;
  c.method = HandoffMethod::paper;
  c.projection.coarsen = coarsen;
  c.projection.carry_fields = {"damage"};
  c.carry_given = true;
  c.input = "snap.h5";
  c.outflow = "outflow.h5";
  return c;
}

void add_damage(common::ParticleSnapshot& s, double d) {
  s.fields.push_back({"damage", "1", 1, std::vector<double>(s.count(), d), "damage"});
}

}  // namespace

TEST(Outflow, BallisticSpheresOutsideTheGridConserveMassAndMomentum) {
  // Grid particles: 2000 random particles in cells 2..10 of a 12-cell grid (h = 1), time 5 s.
  common::ParticleSnapshot s = testsets::uniform(2000, 12, 1.0, 2.5, 9.5, 0.5);
  s.time = 5.0;
  add_damage(s, 0.1);
  // Outflow file written at t = 4 s: three particles that fly on for 1 s to the snapshot time.
  common::ParticleSnapshot o;
  o.grid = s.grid;
  o.time = 4.0;
  testsets::add(o, 900001, {20.2, 3.3, 3.3}, {1.0, 0.0, 0.0}, 2.0, 0.5);   // -> x = 21.2: cell 21
  testsets::add(o, 900002, {20.7, 3.6, 3.3}, {0.6, 0.0, 0.0}, 6.0, 0.5);   // -> x = 21.3: same cell
  testsets::add(o, 900003, {-7.5, 5.5, 5.5}, {0.0, -2.0, 0.0}, 4.0, 0.5);  // -> y = 3.5, x < 0: cell -8
  o.fields.push_back({"damage", "1", 1, {0.2, 0.5, 1.0}, "damage"});
  o.fields.push_back({"removal_time", "s", 1, {3.0, 3.5, 2.0}, "s"});

  const HandoffOutcome r = hand_off(s, config(), &o);
  const Audit& a = r.audit;
  const common::SphereSet& sp = r.result.spheres;
  EXPECT_EQ(a.outflow_particles, 3u);
  EXPECT_EQ(a.outflow_spheres, 2u);
  EXPECT_EQ(sp.count(), r.result.cell.size() + 2);
  EXPECT_EQ(a.input.count, 2003u);
  EXPECT_NEAR(a.after.mass / a.before.mass - 1.0, 0.0, 1e-14);
  EXPECT_LT(a.momentum_error_relative(), 1e-13);
  // The two particles of cell (21, 3, 3) make one sphere at its centre with their mass-weighted
  // velocity and damage; the third is alone in cell (-8, 3, 5).
  const std::size_t ns = sp.count();
  const std::size_t s1 = ns - 2, s2 = ns - 1;  // appended in lattice order: (-8,..) < (21,..)
  EXPECT_DOUBLE_EQ(sp.mass[s1], 4.0);
  EXPECT_DOUBLE_EQ(sp.position[3 * s1], -7.5);
  EXPECT_DOUBLE_EQ(sp.position[3 * s1 + 1], 3.5);
  EXPECT_DOUBLE_EQ(sp.velocity[3 * s1 + 1], -2.0);
  EXPECT_DOUBLE_EQ(sp.mass[s2], 8.0);
  EXPECT_DOUBLE_EQ(sp.position[3 * s2], 21.5);
  EXPECT_DOUBLE_EQ(sp.position[3 * s2 + 1], 3.5);
  EXPECT_DOUBLE_EQ(sp.velocity[3 * s2], (2.0 * 1.0 + 6.0 * 0.6) / 8.0);
  EXPECT_DOUBLE_EQ(sp.fields[0].values[s2], (2.0 * 0.2 + 6.0 * 0.5) / 8.0);
  EXPECT_DOUBLE_EQ(sp.radius[s2], 0.5);
  // Kinetic-energy loss of the outflow part = intra-cell spread of the merged pair only (0.12 J);
  // the grid spheres are those of the hand-off without the outflow file.
  HandoffConfig no_out = config();
  no_out.outflow.clear();
  const HandoffOutcome base = hand_off(s, no_out);
  const double spread = 0.5 * 2.0 * 1.0 + 0.5 * 6.0 * 0.36 - 0.5 * 8.0 * std::pow(5.6 / 8.0, 2);
  EXPECT_NEAR(a.kinetic_loss() - base.audit.kinetic_loss(), spread, 1e-4);
  // Every sphere in its own lattice cell, and the particle map holds every id once.
  std::set<std::tuple<long, long, long>> cells;
  for (std::size_t i = 0; i < ns; ++i)
    cells.insert({std::lround(std::floor(sp.position[3 * i])), std::lround(std::floor(sp.position[3 * i + 1])),
                  std::lround(std::floor(sp.position[3 * i + 2]))});
  EXPECT_EQ(cells.size(), ns);
  ASSERT_EQ(r.result.map.offset.size(), ns + 1);
  EXPECT_EQ(r.result.map.offset.back(), 2003u);
  std::set<std::uint64_t> ids(r.result.map.particle_id.begin(), r.result.map.particle_id.end());
  EXPECT_EQ(ids.size(), 2003u);
  EXPECT_EQ(r.result.map.particle_id[r.result.map.offset[s2]], 900001u);
}

TEST(Outflow, ParticleInAnOccupiedEdgeCellMergesIntoItsSphere) {
  common::ParticleSnapshot s = testsets::uniform(500, 12, 1.0, 2.5, 9.5, 0.5);
  add_damage(s, 0.0);
  const HandoffOutcome base = hand_off(s, [] { auto c = config(); c.outflow.clear(); return c; }());
  // An outflow particle in the cell of the first projection sphere (as happens at the grid edge
  // with coarse spheres) joins that sphere instead of making a second one there.
  const common::SphereSet& b = base.result.spheres;
  common::ParticleSnapshot o;
  o.grid = s.grid;
  o.time = s.time;
  testsets::add(o, 777, {b.position[0] + 0.1, b.position[1] - 0.2, b.position[2]}, {10.0, 0.0, 0.0}, 3.0, 0.5);
  o.fields.push_back({"damage", "1", 1, {1.0}, "damage"});
  const HandoffOutcome r = hand_off(s, config(), &o);
  const common::SphereSet& sp = r.result.spheres;
  EXPECT_EQ(sp.count(), b.count());
  EXPECT_EQ(r.audit.outflow_spheres, 0u);
  EXPECT_DOUBLE_EQ(sp.mass[0], b.mass[0] + 3.0);
  EXPECT_NEAR(sp.velocity[0], (b.mass[0] * b.velocity[0] + 30.0) / (b.mass[0] + 3.0), 1e-12);
  EXPECT_NEAR(sp.fields[0].values[0], 3.0 / (b.mass[0] + 3.0), 1e-15);
  EXPECT_LT(r.audit.momentum_error_relative(), 1e-13);
  EXPECT_EQ(r.result.map.offset[1] - r.result.map.offset[0], base.result.map.offset[1] - base.result.map.offset[0] + 1);
}

TEST(Outflow, SelectionRulesApplyAndAGridMismatchIsRejected) {
  common::ParticleSnapshot s = testsets::uniform(500, 12, 1.0, 2.5, 9.5, 0.5);
  add_damage(s, 0.5);
  common::ParticleSnapshot o;
  o.grid = s.grid;
  o.time = s.time;
  testsets::add(o, 1, {30.0, 3.0, 3.0}, {5000.0, 0.0, 0.0}, 1.0, 0.5);
  testsets::add(o, 2, {40.0, 3.0, 3.0}, {50.0, 0.0, 0.0}, 1.0, 0.5);
  o.fields.push_back({"damage", "1", 1, {1.0, 1.0}, "damage"});
  HandoffConfig c = config();
  c.select.max_speed = 4000.0;  // the uniform set's fastest particle is ~3900 m/s
  const HandoffOutcome r = hand_off(s, c, &o);
  EXPECT_EQ(r.audit.dropped.count, 1u);
  EXPECT_DOUBLE_EQ(r.audit.dropped.momentum[0], 5000.0);
  EXPECT_EQ(r.audit.outflow_particles, 1u);
  o.grid.cell_size *= 2.0;
  EXPECT_THROW(hand_off(s, config(), &o), common::InputError);
}
