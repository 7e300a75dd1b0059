/// @file test_stability.cpp
/// Stability: stiff and extreme cases must stay finite or stop with a clear diagnosis
/// (SolverFailure / NumericalError -> exit code 3 with the last good state saved).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "common/particle_file.hpp"
#include "common/provenance.hpp"
#include "mpm/run.hpp"
#include "test_helpers.hpp"

using namespace mpmfrag;

namespace {

std::string impact_scene(double v, double stiff, bool av = true, double courant = 0.3) {
  auto num = [](double x) { char b[64]; std::snprintf(b, sizeof b, "%.9g", x); return std::string(b); };
  return R"(
[grid]
domain_min = [-0.05, -0.05, -0.06]
domain_max = [0.05, 0.05, 0.12]
cell_size = 0.01
[solver]
scheme = "musl"
courant = )" + num(courant) + R"(
artificial_viscosity.enabled = )" + std::string(av ? "true" : "false") + R"(
[boundary]
z_min = "fixed"
[time]
end = 1.0
[[material]]
name = "rock"
model = "tillotson"
density = 2700.0
A = )" + num(26.7e9 * stiff) + "\nB = " + num(26.7e9 * stiff) + "\nshear_modulus = " + num(22.7e9 * stiff) + R"(
[[body]]
material = "rock"
shape = "box"
min = [-0.04, -0.04, -0.05]
max = [0.04, 0.04, 0.0]
[[body]]
material = "rock"
shape = "sphere"
center = [0.0, 0.0, 0.012]
radius = 0.011
velocity = [0.0, 0.0, )" + num(-v) + R"(]
)";
}

bool all_finite(const ParticleSet& ps) {
  for (double x : ps.x) if (!std::isfinite(x)) return false;
  for (double x : ps.v) if (!std::isfinite(x)) return false;
  for (double x : ps.stress) if (!std::isfinite(x)) return false;
  for (double x : ps.energy) if (!std::isfinite(x)) return false;
  return true;
}

}  // namespace

TEST(Stability, HundredTimesStifferThanBasalt) {
  Solver base = mpmtest::solver_from(mpmtest::setup_from(impact_scene(2000, 1)));
  Solver s = mpmtest::solver_from(mpmtest::setup_from(impact_scene(2000, 100)));
  const double dt_ratio = s.stable_dt() / base.stable_dt();
  std::printf("stiff x100: dt ratio %.4f (expected (c+v)/(10c+v) = 0.1375)\n", dt_ratio);
  // c scales with sqrt(stiffness): dt ratio = (c + v)/(10 c + v) with c = 4593 m/s, v = 2 km/s
  const double c = std::sqrt((26.7e9 + 4.0 / 3.0 * 22.7e9) / 2700.0);
  EXPECT_NEAR(dt_ratio, (c + 2000.0) / (10 * c + 2000.0), 1e-3);
  const double E0 = s.diagnostics().total();
  for (int i = 0; i < 300; ++i) s.step(s.stable_dt());
  EXPECT_TRUE(all_finite(s.particles()));
  const double dE = (s.diagnostics().total() - E0) / E0;
  std::printf("stiff x100: 300 steps to t = %.3e s, dE/E0 = %.3e\n", s.time(), dE);
  EXPECT_LT(std::fabs(dE), 0.1);
}

TEST(Stability, TwentyKmPerSecondImpact) {
  Solver s = mpmtest::solver_from(mpmtest::setup_from(impact_scene(20000, 1, true, 0.2)));
  const double E0 = s.diagnostics().total();
  // until the impactor (2.2 cm) has run about 2.5 of its diameters into the target
  mpmtest::run_to(s, 3e-6);
  const Diagnostics d = s.diagnostics();
  std::printf("20 km/s: %lld steps, dt_min-ish %.3e s, E/E0 = %.4f (KE %.3e, IE %.3e)\n",
              static_cast<long long>(s.step_count()), s.stable_dt(), d.total() / E0, d.kinetic, d.internal);
  EXPECT_TRUE(all_finite(s.particles()));
  EXPECT_LT(std::fabs(d.total() / E0 - 1), 0.1);  // energy error of the explicit shock integration (C = 0.2)
  EXPECT_GT(d.internal, 0.1 * E0);  // the shock has heated the material
}

TEST(Stability, SingleParticleInACellTranslatesExactly) {
  const char* toml = R"(
[grid]
domain_min = [0.0, 0.0, 0.0]
domain_max = [1.0, 1.0, 1.0]
cell_size = 0.1
[time]
end = 1.0
[[material]]
name = "m"
model = "neo_hookean"
density = 1000.0
bulk_modulus = 1e9
shear_modulus = 1e8
[[body]]
material = "m"
shape = "sphere"
center = [0.25, 0.35, 0.45]
radius = 0.01
velocity = [1.0, -2.0, 0.5]
ppc = 1
)";
  Solver s = mpmtest::solver_from(mpmtest::setup_from(toml));
  ASSERT_EQ(s.particles().size(), 1u);
  mpmtest::run_to(s, 0.01);  // about 400 steps
  const ParticleSet& p = s.particles();
  EXPECT_NEAR(p.x[0], 0.26, 1e-12);
  EXPECT_NEAR(p.x[1], 0.33, 1e-12);
  EXPECT_NEAR(p.x[2], 0.455, 1e-12);
  EXPECT_NEAR(p.v[1], -2.0, 1e-12);
  for (int c = 0; c < 6; ++c) EXPECT_NEAR(p.stress[c], 0.0, 1e-3);  // uniform translation: L = 0
}

TEST(Stability, TwoCoincidentParticles) {
  const char* toml = R"(
[grid]
domain_min = [0.0, 0.0, 0.0]
domain_max = [1.0, 1.0, 1.0]
cell_size = 0.1
[time]
end = 1.0
[[material]]
name = "m"
model = "elastic"
density = 1000.0
bulk_modulus = 1e9
shear_modulus = 1e8
[[body]]
material = "m"
shape = "sphere"
center = [0.55, 0.55, 0.55]
radius = 0.01
ppc = 1
)";
  mpmfrag::Setup st = mpmtest::setup_from(toml);
  ParticleSet& ps = st.particles;
  ASSERT_EQ(ps.size(), 1u);
  ps.resize(2, false);
  ps.id[1] = 1;
  for (int d = 0; d < 3; ++d) {
    ps.x[3 + d] = ps.x[d];
    ps.half_width[3 + d] = ps.half_width[d];
  }
  ps.v[0] = 3.0;
  ps.v[3] = -3.0;
  ps.mass[1] = ps.mass[0];
  ps.volume[1] = ps.volume0[1] = ps.volume0[0];
  st.materials[0].end = 2;
  st.materials[0].allocate_state();
  Solver s = mpmtest::solver_from(std::move(st));
  for (int i = 0; i < 200; ++i) s.step(s.stable_dt());
  EXPECT_TRUE(all_finite(s.particles()));
  EXPECT_NEAR(s.diagnostics().momentum.norm(), 0.0, 1e-12);
  // coincident particles with opposite velocities: the grid velocity is zero, so they stay put
  EXPECT_NEAR(s.particles().x[0], s.particles().x[3], 1e-12);
}

TEST(Stability, HugeRequestedDtIsCappedToCfl) {
  mpmfrag::Setup st = mpmtest::setup_from(impact_scene(1000, 1), {"time.dt_max=1000.0"});
  Solver s = mpmtest::solver_from(std::move(st));
  const double dt = s.stable_dt();
  EXPECT_FALSE(s.dt_capped());
  // CFL: C h / (c_dil + |v|) at the reference state, with the impactor at 1 km/s
  const double c = std::sqrt(26.7e9 / 2700 + 4.0 / 3.0 * 22.7e9 / 2700);
  EXPECT_NEAR(dt, 0.3 * 0.01 / (c + 1000.0), 1e-3 * dt);
  const double E0 = s.diagnostics().total();
  for (int i = 0; i < 100; ++i) s.step(s.stable_dt());
  EXPECT_TRUE(all_finite(s.particles()));
  EXPECT_LT(std::fabs(s.diagnostics().total() / E0 - 1), 0.1);
}

TEST(Stability, ForcedHugeStepStopsWithDiagnosis) {
  // Bypassing the CFL control (calling step() with 100x the stable dt) must end in a clear
  // SolverFailure (J <= 0 or non-finite), never a silent NaN; a backup of the last good state exists.
  Solver s = mpmtest::solver_from(mpmtest::setup_from(impact_scene(5000, 1)));
  for (int i = 0; i < 5; ++i) s.step(s.stable_dt());
  s.save_backup();
  bool failed = false;
  try {
    for (int i = 0; i < 50; ++i) s.step(100 * s.stable_dt());
  } catch (const SolverFailure& f) {
    failed = true;
    std::printf("diagnosis: %s\n", f.what());
    EXPECT_FALSE(f.state_intact);
    EXPECT_NE(std::string(f.what()).find("particle id"), std::string::npos);
  }
  EXPECT_TRUE(failed);
  EXPECT_TRUE(s.backup().valid);
  EXPECT_TRUE(all_finite(s.backup().particles));
}

TEST(Stability, BodyCrossingGridEdgeStopsAndSavesState) {
  const std::string dir = (std::filesystem::temp_directory_path() / "mpm_test_grid_edge").string();
  std::filesystem::remove_all(dir);
  const std::string toml = R"(
[grid]
domain_min = [0.0, 0.0, 0.0]
domain_max = [0.2, 0.1, 0.1]
cell_size = 0.01
[time]
end = 1.0
[output]
directory = ")" + dir + R"("
prefix = "edge"
progress_interval = 100.0
[[material]]
name = "m"
model = "elastic"
density = 1000.0
bulk_modulus = 1e7
shear_modulus = 1e6
[[body]]
material = "m"
shape = "sphere"
center = [0.1, 0.05, 0.05]
radius = 0.03
velocity = [20.0, 0.0, 0.0]
)";
  static const common::Schema schema = mpm_schema();
  const common::Scene sc = common::Scene::parse(schema, toml, "edge-test");
  bool thrown = false;
  try {
    run_mpm(sc, common::Provenance{"mpm-frag", "test", "test", "test", sc.to_toml()});
  } catch (const common::NumericalError& e) {
    thrown = true;
    EXPECT_NE(std::string(e.what()).find("left the grid"), std::string::npos);
    ASSERT_FALSE(e.saved_state().empty());
    const common::ParticleSnapshot snap = common::read_particle_snapshot(e.saved_state());
    EXPECT_GT(snap.count(), 0u);
    EXPECT_GT(snap.time, 0.0);
  }
  EXPECT_TRUE(thrown);
  std::filesystem::remove_all(dir);
}
