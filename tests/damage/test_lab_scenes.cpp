/// @file test_lab_scenes.cpp
/// The lab validation scenes of pipelines/damage (issue 16) through the mpm-frag set-up path:
/// the Brazilian-disk scene builds driven platens and a basalt disk whose flaw populations follow
/// the specimen-size rule (10 mm disk: no 1 cm-80 m flaws; a 25 km body keeps them), and the
/// velocity drive brings the platens to v(t) = v t / t_ramp (body_drive.hpp).
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "mpm/scene_setup.hpp"
#include "mpm/solver.hpp"

#ifndef DAMAGE_SCENES_DIR
#error "DAMAGE_SCENES_DIR must point at pipelines/damage"
#endif

namespace {
const common::Schema& schema() {
  static const common::Schema s = mpmfrag::mpm_schema();
  return s;
}
mpmfrag::Solver solver_of(mpmfrag::Setup st) {
  mpmfrag::Solver s(st.solver, st.grid, std::move(st.particles), std::move(st.materials));
  if (st.body_force) s.set_body_force(st.body_force);
  s.initialize();
  return s;
}
/// Sum over the basalt particles of the large population's bins (25..49) of flaw_density.
double large_flaw_density(const mpmfrag::Solver& s) {
  const mpmfrag::MaterialSlot& m = s.materials()[0];
  std::size_t f = 0;
  while (m.style->state_fields[f].name != "flaw_density") ++f;
  const int nc = m.style->state_fields[f].ncomp;
  double sum = 0.0;
  for (std::size_t q = 0; q < m.end - m.begin; ++q)
    for (int k = 25; k < 50; ++k) sum += m.state[f][nc * q + k];
  return sum;
}
}  // namespace

TEST(LabScenes, BrazilianDiskScenePlatensDriveAndSpecimenRule) {
  const std::string path = std::string(DAMAGE_SCENES_DIR) + "/brazilian.toml";
  const common::Scene sc = common::Scene::load(schema(), path, {"grid.cell_size=0.0004"});
  mpmfrag::Setup st = mpmfrag::build_setup(sc);
  ASSERT_TRUE(static_cast<bool>(st.body_force));
  mpmfrag::Solver s = solver_of(std::move(st));
  const auto& mats = s.materials();
  ASSERT_EQ(mats.size(), 2u);
  EXPECT_NEAR(mats[0].extent, 10e-3, 0.6e-3);  // the disk's diameter (+- one particle)
  EXPECT_EQ(large_flaw_density(s), 0.0);      // 10 mm < 1 m: no 1 cm-80 m flaws
  // drive: at t = t_ramp / 2 the platens move at ~v/2 towards the disk (tau = 0.05 us << 2 us)
  while (s.time() < 2e-6) s.step(std::min(s.stable_dt(), 2e-6 - s.time() + 1e-12));
  const mpmfrag::ParticleSet& P = s.particles();
  double vtop = 0, n = 0;
  for (std::size_t q = mats[1].begin; q < mats[1].end; ++q)
    if (P.x[3 * q + 1] > 0) vtop += P.v[3 * q + 1], ++n;
  EXPECT_NEAR(vtop / n, -0.5, 0.05);
}

TEST(LabScenes, PlanetaryBodyKeepsTheLargeFlaws) {
  const std::string path = std::string(DAMAGE_SCENES_DIR) + "/brazilian.toml";
  // The same scene scaled to a 25 km disk of 2.5 km cells: the basalt keeps both populations.
  const common::Scene sc = common::Scene::load(
      schema(), path,
      {"grid.cell_size=2500", "grid.domain_min=[-32000,-36000,0]", "grid.domain_max=[32000,36000,8000]",
       "body[0].radius=12500", "body[0].length=5000", "body[0].center=[0,0,2500]",
       "body[1].min=[-12500,24750,0]", "body[1].max=[12500,29250,5000]",
       "body[2].min=[-12500,-29250,0]", "body[2].max=[12500,-24750,5000]"});
  mpmfrag::Solver s = solver_of(mpmfrag::build_setup(sc));
  EXPECT_GT(s.materials()[0].extent, 20e3);
  const double per_particle = large_flaw_density(s) / double(s.materials()[0].end - s.materials()[0].begin);
  EXPECT_NEAR(per_particle / 250.0, 1.0, 0.05);  // the population's density, eta = 250 m^-3
}
