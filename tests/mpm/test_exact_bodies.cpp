/// @file test_exact_bodies.cpp
/// Exact bodies (scene_setup.hpp): each body's particle mass equals rho0 x its true volume, its
/// centre of mass is the centre asked for and Q from the particles equals the nominal Q, at
/// awkward cell sizes, ppc and offsets; bodies touching at a point (the seed paper's impactor on
/// its target) are accepted at every cell size from 50 m to 1 km; real overlaps are still refused.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "mpm/scene_setup.hpp"
#include "test_helpers.hpp"

using namespace mpmfrag;

namespace {

constexpr double kRho = 2000.0;

std::string two_spheres(double h, int ppc, const Eigen::Vector3d& c, double R, double r, bool exact, double gap = 0.0) {
  char buf[2048];
  std::snprintf(buf, sizeof buf, R"(
[grid]
domain_min = [-0.5, -0.5, -0.5]
domain_max = [0.5, 0.5, 0.5]
cell_size = %.17g
[time]
end = 1.0
[[material]]
name = "m"
model = "elastic"
density = %.17g
bulk_modulus = 1e9
shear_modulus = 1e9
[[body]]
name = "target"
material = "m"
shape = "sphere"
center = [%.17g, %.17g, %.17g]
radius = %.17g
ppc = %d
exact = %s
[[body]]
name = "impactor"
material = "m"
shape = "sphere"
center = [%.17g, %.17g, %.17g]
radius = %.17g
velocity = [0.0, 0.0, -3.7]
ppc = %d
exact = %s
)", h, kRho, c[0], c[1], c[2], R, ppc, exact ? "true" : "false", c[0], c[1], c[2] + R + r + gap, r, ppc,
                exact ? "true" : "false");
  return buf;
}

}  // namespace

TEST(ExactBodies, MassCentreMomentumAndQExactAtSeveralCellSizesPpcAndOffsets) {
  const double R = 0.3, r = 0.061;
  double worst_lattice = 0.0;
  for (const double h : {0.05, 0.0437, 0.0613})
    for (const int ppc : {1, 2, 3})
      for (const Eigen::Vector3d& c : {Eigen::Vector3d(0, 0, -0.1), Eigen::Vector3d(0.0123, -0.0071, -0.0689)}) {
        SCOPED_TRACE("h = " + std::to_string(h) + ", ppc = " + std::to_string(ppc) + ", centre x = " + std::to_string(c[0]));
        const mpmfrag::Setup st = mpmtest::setup_from(two_spheres(h, ppc, c, R, r, true));
        ASSERT_EQ(st.bodies.size(), 2u);
        const ParticleSet& ps = st.particles;
        // per body from the particles themselves (ids are generation order: target first)
        const std::size_t nt = st.bodies[0].particles;
        double m[2] = {0, 0}, V[2] = {0, 0};
        Eigen::Vector3d mx[2] = {Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
        Eigen::Vector3d mv[2] = {Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
        for (std::size_t p = 0; p < ps.size(); ++p) {
          const int b = ps.id[p] < nt ? 0 : 1;
          m[b] += ps.mass[p];
          V[b] += ps.volume0[p];
          mx[b] += ps.mass[p] * Eigen::Vector3d(ps.x[3 * p], ps.x[3 * p + 1], ps.x[3 * p + 2]);
          mv[b] += ps.mass[p] * Eigen::Vector3d(ps.v[3 * p], ps.v[3 * p + 1], ps.v[3 * p + 2]);
          EXPECT_NEAR(ps.mass[p] / ps.volume0[p], kRho, 1e-9);  // density rho0: stress-free start
          EXPECT_DOUBLE_EQ(ps.half_width[3 * p], 0.5 * h / ppc);
        }
        const double Mt = kRho * 4.0 / 3.0 * M_PI * R * R * R, mi = kRho * 4.0 / 3.0 * M_PI * r * r * r;
        EXPECT_NEAR(m[0] / Mt, 1.0, 1e-12);
        EXPECT_NEAR(m[1] / mi, 1.0, 1e-12);
        EXPECT_NEAR(V[0] * kRho / Mt, 1.0, 1e-12);
        EXPECT_NEAR((mx[0] / m[0] - c).norm(), 0.0, 1e-12);
        EXPECT_NEAR((mx[1] / m[1] - (c + Eigen::Vector3d(0, 0, R + r))).norm(), 0.0, 1e-12);
        EXPECT_NEAR((mv[1] - mi * Eigen::Vector3d(0, 0, -3.7)).norm() / (mi * 3.7), 0.0, 1e-12);
        const double Q = 0.5 * m[1] * 3.7 * 3.7 / m[0], Qn = 0.5 * mi * 3.7 * 3.7 / Mt;
        EXPECT_NEAR(Q / Qn, 1.0, 1e-12);
        EXPECT_NEAR(impact_energy(st.bodies, true) / Qn, 1.0, 1e-12);
        EXPECT_NEAR(impact_energy(st.bodies, false) / Qn, 1.0, 1e-14);
        worst_lattice = std::max(worst_lattice, std::fabs(st.bodies[1].lattice_mass / mi - 1.0));
        // the raw lattice (exact = false) is the body the old set-up made: rho0 (h/ppc)^3 each
        const mpmfrag::Setup raw = mpmtest::setup_from(two_spheres(h, ppc, c, R, r, false));
        EXPECT_EQ(raw.particles.size(), ps.size());
        EXPECT_NEAR(raw.bodies[1].mass, raw.bodies[1].lattice_mass, 1e-9 * mi);
      }
  EXPECT_GT(worst_lattice, 0.05);  // the correction matters: the lattice alone is > 5 % off here
}

TEST(ExactBodies, PapersTouchingImpactorAcceptedAtEveryCellSizeFrom50mTo1km) {
  // El Mir et al. (2019) geometry as pipelines/impact/rules.mk builds it: target R = 12.5 km at
  // the origin, impactor r = 605 m touching it at (0, 0, 12500), domain half-width
  // (int(3.2 R / h) + 0.5) h, so lattice points lie on multiples of h and one lies exactly on the
  // tangent point whenever h divides 12500 m.
  const std::string scene_fmt = R"(
[grid]
domain_min = [-%.17g, -%.17g, -%.17g]
domain_max = [%.17g, %.17g, %.17g]
cell_size = %.17g
[time]
end = 1.0
[[material]]
name = "basalt"
model = "elastic"
density = 2700.0
bulk_modulus = 5e10
shear_modulus = 3e10
[[body]]
name = "target"
material = "basalt"
shape = "sphere"
center = [0.0, 0.0, 0.0]
radius = 12500.0
ppc = 1
[[body]]
name = "impactor"
material = "basalt"
shape = "sphere"
center = [0.0, 0.0, 13105.0]
radius = 605.0
ppc = 1
velocity = [0.0, 0.0, -5000.0]
)";
  static const common::Schema schema = mpm_schema();
  int on_tangent = 0;
  for (const double h : {1000.0, 750.0, 625.0, 500.0, 400.0, 375.0, 300.0, 250.0, 200.0, 150.0, 125.0, 100.0, 75.0,
                         62.5, 60.0, 50.0}) {
    SCOPED_TRACE("h = " + std::to_string(h));
    const double half = (std::floor(3.2 * 12500.0 / h) + 0.5) * h;
    char buf[2048];
    std::snprintf(buf, sizeof buf, scene_fmt.c_str(), half, half, half, half, half, half, h);
    const common::Scene sc = common::Scene::parse(schema, buf, "paper-geometry");
    // The ownership of every lattice point of the impactor's box: the only place where both bodies
    // can hold points (a full set-up at 50 m would be 65 million particles).
    const std::vector<BodyPrimitive> target{make_body_primitive(sc.element("body", 0), "body[0]")};
    const BodyPrimitive imp = make_body_primitive(sc.element("body", 1), "body[1]");
    int mine = 0, theirs = 0;
    for (double z = -half + 0.5 * h; z < half; z += h) {
      if (z < imp.lo[2] - h || z > imp.hi[2] + h) continue;
      for (double y = -half + 0.5 * h; y < half; y += h) {
        if (y < imp.lo[1] - h || y > imp.hi[1] + h) continue;
        for (double x = -half + 0.5 * h; x < half; x += h) {
          if (x < imp.lo[0] - h || x > imp.hi[0] + h) continue;
          int owner = -2;
          ASSERT_NO_THROW(owner = lattice_owner(target, imp, Eigen::Vector3d(x, y, z), kSurfaceTolerance * h, "body[1]"));
          if (owner == 1) ++mine;
          if (owner == 0) {
            ++theirs;
            EXPECT_NEAR(Eigen::Vector3d(x, y, z).norm(), 12500.0, 1e-6);  // only the tangent point
          }
        }
      }
    }
    on_tangent += theirs;
    EXPECT_GE(mine, 1);
    if (std::fmod(12500.0, h) == 0.0) {
      EXPECT_EQ(theirs, 1);  // the point on the contact: the target's
    }
    if (h >= 375.0) {  // the whole set-up, bodies exact, at the coarser cells (<= 155 000 particles)
      mpmfrag::Setup st;
      ASSERT_NO_THROW(st = build_setup(sc));
      EXPECT_GT(st.particles.size(), static_cast<std::size_t>(0.9 * 4.0 / 3.0 * M_PI * std::pow(12500.0 / h, 3)));
      EXPECT_NEAR(st.bodies[1].mass / (2700.0 * 4.0 / 3.0 * M_PI * std::pow(605.0, 3)), 1.0, 1e-12);
      EXPECT_NEAR(impact_energy(st.bodies, true) / impact_energy(st.bodies, false), 1.0, 1e-12);
    }
  }
  EXPECT_GE(on_tangent, 5);  // 500, 250, 125, 100, 62.5 and 50 m put a lattice point on the contact
}

TEST(ExactBodies, RealOverlapsAreStillRefusedAndFaceContactsAccepted) {
  const double h = 0.05;
  // spheres overlapping by 1 % of a cell: refused (analytic test), touching: accepted
  EXPECT_THROW(mpmtest::setup_from(two_spheres(h, 2, Eigen::Vector3d(0, 0, -0.1), 0.3, 0.061, true, -0.01 * h)),
               common::InputError);
  EXPECT_NO_THROW(mpmtest::setup_from(two_spheres(h, 2, Eigen::Vector3d(0, 0, -0.1), 0.3, 0.061, true, 0.0)));
  const std::string boxes = R"(
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
[[body]]
material = "m"
shape = "box"
min = [-0.2, -0.2, -0.2]
max = [0.2, 0.2, 0.0125]
ppc = 2
[[body]]
material = "m"
shape = "box"
min = [-0.1, -0.1, 0.0125]
max = [0.1, 0.1, %s]
ppc = 2
)";
  // face contact exactly on a lattice plane (z = 0.0125 = (k + 1/2) h/2): the plane's points go to
  // body 0, body 1 is scaled up to its mass
  char buf[2048];
  std::snprintf(buf, sizeof buf, boxes.c_str(), "0.1125");
  mpmfrag::Setup st;
  ASSERT_NO_THROW(st = mpmtest::setup_from(buf));
  EXPECT_NEAR(st.bodies[0].mass, 2000.0 * 0.4 * 0.4 * 0.2125, 1e-9);
  EXPECT_NEAR(st.bodies[1].mass, 2000.0 * 0.2 * 0.2 * 0.1, 1e-9);
  EXPECT_EQ(st.bodies[1].particles, 8u * 8u * 4u);  // 5 planes of 8 x 8 in z (both faces), the first taken by body 0
  // boxes overlapping by one particle layer: refused
  std::snprintf(buf, sizeof buf, boxes.c_str(), "0.1125");
  std::string overlap(buf);
  overlap.replace(overlap.rfind("min = [-0.1, -0.1, 0.0125]"), 26, "min = [-0.1, -0.1, -0.0250]");
  EXPECT_THROW(mpmtest::setup_from(overlap), common::InputError);
}
