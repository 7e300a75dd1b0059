/// @file test_outflow.cpp
/// Outflow (grid.outflow = "remove"): particles that leave the grid are taken out of the MPM
/// computation, fly ballistically, are written to <prefix>_outflow.h5 and stay in the conserved
/// totals; the remaining particles keep their own state (compaction inside a material range).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <map>

#include "common/particle_file.hpp"
#include "common/provenance.hpp"
#include "mpm/run.hpp"
#include "mpm/scene_setup.hpp"

using namespace mpmfrag;

namespace {

// A resting sphere and a small sphere of the same material flying at 100 m/s towards x_max,
// separated by more than a stencil, so the flyer moves as a free rigid body until it leaves.
std::string scene(const std::string& dir, const std::string& outflow) {
  return R"(
[grid]
domain_min = [0.0, 0.0, 0.0]
domain_max = [0.3, 0.1, 0.1]
cell_size = 0.01
outflow = ")" + outflow + R"("
[time]
end = 0.0015
[output]
directory = ")" + dir + R"("
prefix = "out"
progress_interval = 100.0
[[material]]
name = "rock"
model = "tonge_ramesh"
density = 2700.0
[[body]]
material = "rock"
shape = "sphere"
center = [0.06, 0.05, 0.05]
radius = 0.03
[[body]]
material = "rock"
shape = "sphere"
center = [0.24, 0.05, 0.05]
radius = 0.015
velocity = [100.0, 0.0, 0.0]
)";
}

std::map<std::uint64_t, double> damage_by_id(const common::ParticleSnapshot& s) {
  std::map<std::uint64_t, double> m;
  const common::Field* d = s.field("damage");
  for (std::size_t p = 0; p < s.count(); ++p) m[s.id[p]] = d ? d->values[p] : -1.0;
  return m;
}

}  // namespace

TEST(Outflow, RemovedParticlesFlyBallisticallyAndStayInTheTotals) {
  const std::string dir = (std::filesystem::temp_directory_path() / "mpm_test_outflow").string();
  std::filesystem::remove_all(dir);
  static const common::Schema schema = mpm_schema();
  const common::Scene sc = common::Scene::parse(schema, scene(dir, "remove"), "outflow-test");
  const RunSummary sum = run_mpm(sc, common::Provenance{"mpm-frag", "test", "test", "test", sc.to_toml()});
  EXPECT_NEAR(sum.time, 0.0015, 1e-12);

  const common::ParticleSnapshot first = common::read_particle_snapshot(dir + "/out_000000.h5");
  const common::ParticleSnapshot last = common::read_particle_snapshot(sum.last_snapshot);
  const common::ParticleSnapshot out = common::read_particle_snapshot(dir + "/out_outflow.h5");
  // Every flyer particle (initially x > 0.2) left; no resting particle did.
  std::size_t flyers = 0;
  for (std::size_t p = 0; p < first.count(); ++p) flyers += first.position[3 * p] > 0.2 ? 1 : 0;
  ASSERT_GT(flyers, 50u);
  EXPECT_EQ(out.count(), flyers);
  EXPECT_EQ(last.count() + out.count(), first.count());
  // Ballistic: each removed particle is where its initial position + 100 m/s * t puts it (the flyer
  // is a free unstressed body, so its velocity never changes), at the file's time.
  std::map<std::uint64_t, std::size_t> idx0;
  for (std::size_t p = 0; p < first.count(); ++p) idx0[first.id[p]] = p;
  const common::Field* tr = out.field("removal_time");
  ASSERT_NE(tr, nullptr);
  EXPECT_NEAR(out.time, 0.0015, 1e-12);
  for (std::size_t p = 0; p < out.count(); ++p) {
    const std::size_t q = idx0.at(out.id[p]);
    EXPECT_NEAR(out.position[3 * p], first.position[3 * q] + 100.0 * out.time, 1e-9);
    EXPECT_NEAR(out.position[3 * p + 1], first.position[3 * q + 1], 1e-9);
    EXPECT_NEAR(out.velocity[3 * p], 100.0, 1e-9);
    EXPECT_GT(tr->values[p], 0.0);
    EXPECT_LT(tr->values[p], 0.0015);
  }
  // Conserved totals include the removed particles: mass exact, momentum and kinetic energy to
  // round-off (the flyer's momentum is 100 m/s * its mass).
  EXPECT_NEAR(sum.final.mass / sum.initial.mass, 1.0, 1e-14);
  EXPECT_NEAR(sum.final.momentum[0] / sum.initial.momentum[0], 1.0, 1e-12);
  EXPECT_NEAR(sum.final.kinetic / sum.initial.kinetic, 1.0, 1e-9);
  EXPECT_EQ(sum.final.removed, flyers);
  // State fields follow their particles through the compaction: the resting sphere is unloaded,
  // so every remaining particle still has its own initial damage, and every removed one carries
  // the damage it was sampled with.
  const auto d0 = damage_by_id(first), d1 = damage_by_id(last), dout = damage_by_id(out);
  for (const auto& [id, d] : d1) EXPECT_EQ(d, d0.at(id)) << "particle " << id;
  for (const auto& [id, d] : dout) EXPECT_EQ(d, d0.at(id)) << "particle " << id;
  std::filesystem::remove_all(dir);
}

TEST(Outflow, StopIsTheDefaultAndNamesTheParticle) {
  const std::string dir = (std::filesystem::temp_directory_path() / "mpm_test_outflow_stop").string();
  std::filesystem::remove_all(dir);
  static const common::Schema schema = mpm_schema();
  const common::Scene sc = common::Scene::parse(schema, scene(dir, "stop"), "outflow-test");
  try {
    run_mpm(sc, common::Provenance{"mpm-frag", "test", "test", "test", sc.to_toml()});
    FAIL() << "expected a NumericalError";
  } catch (const common::NumericalError& e) {
    EXPECT_NE(std::string(e.what()).find("left the grid"), std::string::npos);
    EXPECT_FALSE(std::filesystem::exists(dir + "/out_outflow.h5"));
  }
  std::filesystem::remove_all(dir);
}
