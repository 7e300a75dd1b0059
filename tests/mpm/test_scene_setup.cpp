/// @file test_scene_setup.cpp
/// Scene construction: body primitives -> particles, input errors, snapshot fields only for the
/// models a scene enables, exact P2G conservation.
#include <gtest/gtest.h>

#include <cmath>

#include "mpm/materials/builtin.hpp"
#include "mpm/output.hpp"
#include "test_helpers.hpp"

using namespace mpmfrag;

namespace {
std::string scene(const std::string& bodies, const std::string& extra_material = "") {
  return R"(
[grid]
domain_min = [-0.5, -0.5, -0.5]
domain_max = [0.5, 0.5, 0.5]
cell_size = 0.05
[time]
end = 1.0
[[material]]
name = "m"
model = "elastic"
density = 2000.0
bulk_modulus = 1e9
shear_modulus = 1e9
)" + extra_material + bodies;
}
}  // namespace

TEST(SceneSetup, PrimitivesFillTheirVolume) {
  const double h = 0.05, ppc = 2, dv = std::pow(h / ppc, 3);
  {
    const mpmfrag::Setup st = mpmtest::setup_from(scene("[[body]]\nmaterial = \"m\"\nshape = \"sphere\"\ncenter = [0.01, 0.0, -0.02]\nradius = 0.3\n"));
    const double V = st.particles.size() * dv, exact = 4.0 / 3.0 * M_PI * 0.027;
    EXPECT_NEAR(V / exact, 1.0, 0.01);
    EXPECT_NEAR(st.particles.mass[0], 2000.0 * st.particles.volume0[0], 1e-12);  // exact body: scaled, rho0 kept
    EXPECT_NEAR(st.particles.mass[0] / (2000.0 * dv), exact / V, 1e-12);
    const mpmfrag::Setup raw = mpmtest::setup_from(scene("[[body]]\nmaterial = \"m\"\nshape = \"sphere\"\ncenter = [0.01, 0.0, -0.02]\nradius = 0.3\nexact = false\n"));
    EXPECT_NEAR(raw.particles.mass[0], 2000.0 * dv, 1e-12);  // the raw lattice
    EXPECT_NEAR(st.particles.half_width[0], h / 4, 1e-15);
  }
  {
    const mpmfrag::Setup st = mpmtest::setup_from(scene("[[body]]\nmaterial = \"m\"\nshape = \"box\"\nmin = [-0.2, -0.1, 0.0]\nmax = [0.2, 0.1, 0.1]\n"));
    EXPECT_EQ(st.particles.size(), 16u * 8u * 4u);
  }
  {
    const mpmfrag::Setup st = mpmtest::setup_from(scene("[[body]]\nmaterial = \"m\"\nshape = \"cylinder\"\ncenter = [0.0, 0.0, 0.0]\naxis = \"x\"\nradius = 0.2\nlength = 0.4\nppc = 3\n"));
    const double V = st.particles.size() * std::pow(h / 3, 3), exact = M_PI * 0.04 * 0.4;
    EXPECT_NEAR(V / exact, 1.0, 0.02);
    double xmax = 0, rmax = 0;
    for (std::size_t p = 0; p < st.particles.size(); ++p) {
      xmax = std::max(xmax, std::fabs(st.particles.x[3 * p]));
      rmax = std::max(rmax, std::hypot(st.particles.x[3 * p + 1], st.particles.x[3 * p + 2]));
    }
    EXPECT_LE(xmax, 0.2);
    EXPECT_LE(rmax, 0.2);
  }
  {  // rigid rotation initial velocity: v = v0 + w x (x - c)
    const mpmfrag::Setup st = mpmtest::setup_from(scene("[[body]]\nmaterial = \"m\"\nshape = \"sphere\"\ncenter = [0.0, 0.0, 0.0]\nradius = 0.1\nvelocity = [1.0, 0.0, 0.0]\nangular_velocity = [0.0, 0.0, 2.0]\n"));
    for (std::size_t p = 0; p < st.particles.size(); ++p) {
      EXPECT_NEAR(st.particles.v[3 * p], 1.0 - 2.0 * st.particles.x[3 * p + 1], 1e-12);
      EXPECT_NEAR(st.particles.v[3 * p + 1], 2.0 * st.particles.x[3 * p], 1e-12);
    }
  }
}

TEST(SceneSetup, InputErrorsNameTheProblem) {
  const std::string s1 = "[[body]]\nmaterial = \"m\"\nshape = \"sphere\"\ncenter = [0.0, 0.0, 0.0]\nradius = 0.2\n";
  const std::string s2 = "[[body]]\nmaterial = \"m\"\nshape = \"sphere\"\ncenter = [0.1, 0.0, 0.0]\nradius = 0.2\n";
  EXPECT_THROW(mpmtest::setup_from(scene(s1 + s2)), common::InputError);  // overlap
  EXPECT_THROW(mpmtest::setup_from(scene("[[body]]\nmaterial = \"m\"\nshape = \"sphere\"\ncenter = [0.45, 0.0, 0.0]\nradius = 0.2\n")),
               common::InputError);  // outside the domain
  EXPECT_THROW(mpmtest::setup_from(scene("[[body]]\nmaterial = \"nope\"\nshape = \"sphere\"\ncenter = [0.0, 0.0, 0.0]\nradius = 0.2\n")),
               common::InputError);  // unknown material
  EXPECT_THROW(mpmtest::setup_from(scene(s1), {"body[0].bogus=1"}), common::InputError);  // unknown key
}

namespace {
// A test style with one output state field (stands in for a damage model).
class WithState final : public Material {
 public:
  WithState() : e_(make_linear_elastic(2000.0, 1e9, 1e9)) {}
  double density() const override { return 2000.0; }
  double reference_wave_speed() const override { return e_->reference_wave_speed(); }
  BatchResult update(const MaterialBatch& b) const override {
    for (std::size_t k = 0; k < b.n; ++k) b.state[0][k] = 0.25;
    return e_->update(b);
  }

 private:
  std::unique_ptr<Material> e_;
};
}  // namespace

TEST(SceneSetup, StateFieldsOnlyForEnabledModels) {
  MaterialRegistry reg;
  register_elastic(reg);
  StyleInfo si;
  si.name = "with_state";
  si.state_fields = {{"damage", 1, "1", 0.0, true, "test damage"}};
  si.create = [](const common::Scene&) -> std::unique_ptr<Material> { return std::make_unique<WithState>(); };
  reg.add(si);
  const common::Schema schema = mpm_schema(reg);
  const std::string body_a = "[[body]]\nmaterial = \"m\"\nshape = \"sphere\"\ncenter = [-0.2, 0.0, 0.0]\nradius = 0.1\n";
  const std::string body_b = "[[body]]\nmaterial = \"d\"\nshape = \"sphere\"\ncenter = [0.2, 0.0, 0.0]\nradius = 0.1\n";
  {  // elastic only: no damage arrays, no damage dataset
    mpmfrag::Setup st = build_setup(common::Scene::parse(schema, scene(body_a), "t"), reg);
    Solver s(st.solver, st.grid, std::move(st.particles), std::move(st.materials));
    s.initialize();
    s.step(s.stable_dt());
    const common::ParticleSnapshot snap = make_snapshot(s.particles(), s.materials(), s.grid(), s.time(), 1);
    EXPECT_EQ(snap.field("damage"), nullptr);
    ASSERT_NE(snap.field("stress"), nullptr);
    EXPECT_EQ(snap.field("stress")->ncomp, 6u);
    EXPECT_NEAR(s.bytes_per_particle(), 260.0, 1e-9);  // incl. 3 energy-budget doubles (energy_budget.hpp)
  }
  {  // with the state style: damage allocated for its particles only, written for all
    const std::string mat = "[[material]]\nname = \"d\"\nmodel = \"with_state\"\ndensity = 2000.0\n";
    mpmfrag::Setup st = build_setup(common::Scene::parse(schema, scene(body_a + body_b, mat), "t"), reg);
    Solver s(st.solver, st.grid, std::move(st.particles), std::move(st.materials));
    s.initialize();
    s.step(s.stable_dt());
    const common::ParticleSnapshot snap = make_snapshot(s.particles(), s.materials(), s.grid(), s.time(), 1);
    const common::Field* d = snap.field("damage");
    ASSERT_NE(d, nullptr);
    std::size_t n_d = 0;
    for (std::size_t p = 0; p < snap.count(); ++p) {
      EXPECT_EQ(d->values[p], snap.material[p] == 1 ? 0.25 : 0.0);
      n_d += snap.material[p] == 1;
    }
    EXPECT_EQ(s.materials()[1].state[0].size(), n_d);
    EXPECT_GT(s.bytes_per_particle(), 260.0);
  }
}

TEST(SceneSetup, P2GConservesMassAndMomentumExactly) {
  // one step of a translating, rotating sphere on a free grid: mass, momentum and (no contact,
  // no stress) angular momentum are conserved to round-off by the transfers
  Solver s = mpmtest::solver_from(mpmtest::setup_from(scene(
      "[[body]]\nmaterial = \"m\"\nshape = \"sphere\"\ncenter = [0.0, 0.0, 0.0]\nradius = 0.2\nvelocity = [3.0, -1.0, 0.5]\n")));
  const Diagnostics d0 = s.diagnostics();
  for (int i = 0; i < 10; ++i) s.step(s.stable_dt());
  const Diagnostics d1 = s.diagnostics();
  EXPECT_NEAR(d1.mass, d0.mass, 1e-13 * d0.mass);
  EXPECT_NEAR((d1.momentum - d0.momentum).norm(), 0.0, 1e-13 * d0.momentum.norm());
  EXPECT_NEAR(d1.kinetic, d0.kinetic, 1e-12 * d0.kinetic);  // rigid translation: no strain
}
