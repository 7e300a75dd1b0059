/// @file test_face_bonds.cpp
/// Bonds from the hand-off (handoff/face_bonds.hpp): a 3x3x3 block with a damage gradient along x
/// whose face-adjacent pairs are counted by hand; the damage law f = 1 - max(D_a, D_b) / D_c and
/// its cut-off; the same block made of 6^3 MPM cells coarsened by 2, whose sphere damage is the
/// mass-weighted mean of unequal particles; refusals.
#include <gtest/gtest.h>

#include <map>

#include "common/status.hpp"
#include "handoff/face_bonds.hpp"
#include "handoff/run_handoff.hpp"
#include "particle_sets.hpp"

namespace {

// 3x3x3 spheres of edge e at (i + 1/2) e + offset, damage D[ix]; ids 100 + cell index (shuffled order).
common::SphereSet block(double e, const double D[3]) {
  common::SphereSet s;
  common::Field dmg{"damage", "1", 1, {}, {}};
  const int order[27] = {13, 0, 26, 5, 21, 9, 17, 2, 24, 7, 19, 11, 15, 1, 25, 4, 22, 8, 18, 3, 23, 6, 20, 10, 16, 12, 14};
  for (int c : order) {
    const int i = c % 3, j = (c / 3) % 3, k = c / 9;
    s.id.push_back(100 + static_cast<std::uint64_t>(c));
    const double x[3] = {(i + 0.5) * e + 1234.5, (j + 0.5) * e - 77.25, (k + 0.5) * e + 3.0};
    for (int d = 0; d < 3; ++d) {
      s.position.push_back(x[d]);
      s.velocity.push_back(0.0);
      s.spin.push_back(0.0);
    }
    s.mass.push_back(1.0);
    s.radius.push_back(0.5 * e);
    dmg.values.push_back(D[i]);
  }
  s.fields.push_back(dmg);
  return s;
}

handoff::HandoffBondParams params() {
  handoff::HandoffBondParams p;
  p.enabled = true;
  p.kn = 3.7e9;
  p.ks = 1.3e9;
  p.sigma_c = 2.9e6;
  p.tau_c = 4.1e6;
  p.radius_ratio = 0.8;
  p.damage_critical = 0.125;
  return p;
}

// Bonds per damage factor (rounded to 1e-12): the hand count of the 3x3x3 block.
std::map<long long, int> by_factor(const common::BondTable& b, double kn) {
  std::map<long long, int> m;
  for (double k : b.kn) ++m[std::llround(k / kn * 1e12)];
  return m;
}
long long key(double f) { return std::llround(f * 1e12); }

}  // namespace

TEST(FaceBonds, DamageFactorIsLinearToTheCutOff) {
  EXPECT_DOUBLE_EQ(handoff::bond_damage_factor(0.0, 0.125), 1.0);
  EXPECT_NEAR(handoff::bond_damage_factor(0.0731, 0.125), 1.0 - 0.0731 / 0.125, 1e-15);
  EXPECT_EQ(handoff::bond_damage_factor(0.125, 0.125), 0.0);  // fully damaged: no bond
  EXPECT_EQ(handoff::bond_damage_factor(0.2, 0.125), 0.0);
  EXPECT_NEAR(handoff::bond_damage_factor(0.2, 1.0), 0.8, 1e-15);
  EXPECT_EQ(handoff::bond_damage_factor(-0.3, 0.5), 1.0);  // clamped to [0, 1]
}

// 3x3x3 block: 54 face-adjacent pairs (3 axes x 9 lines x 2). Damage along x: 0.0137, 0.0731 and
// 0.125 (= D_c, fully damaged). Every pair touching the x = 2 plane goes: 9 x-pairs (1-2) and the
// 12 pairs inside the plane, leaving 33: 12 in plane 0 at f0 = 1 - 0.0137/0.125 and 9 x-pairs
// (0-1) plus 12 in plane 1 at f1 = 1 - 0.0731/0.125 (the larger damage of the two spheres).
TEST(FaceBonds, BlockWithDamageGradientCountedByHand) {
  const double e = 3000.0, D[3] = {0.0137, 0.0731, 0.125};
  const common::SphereSet s = block(e, D);
  const auto p = params();
  const common::BondTable b = handoff::face_bonds(s, p, "block.h5");
  ASSERT_EQ(b.size(), 33u);
  const double f0 = 1.0 - 0.0137 / 0.125, f1 = 1.0 - 0.0731 / 0.125;
  const auto m = by_factor(b, p.kn);
  ASSERT_EQ(m.size(), 2u);
  EXPECT_EQ(m.at(key(f0)), 12);
  EXPECT_EQ(m.at(key(f1)), 21);
  std::map<std::uint64_t, int> cell_of;  // id -> cell index
  for (std::size_t r = 0; r < s.count(); ++r) cell_of[s.id[r]] = static_cast<int>(s.id[r] - 100);
  int x_pairs = 0;
  for (std::size_t k = 0; k < b.size(); ++k) {
    const int ca = cell_of.at(b.id_a[k]), cb = cell_of.at(b.id_b[k]);
    const int d = cb - ca;  // +1, +3, +9: the neighbour in +x, +y, +z
    EXPECT_TRUE(d == 1 || d == 3 || d == 9) << ca << " " << cb;
    if (d == 1) {
      ++x_pairs;
      EXPECT_EQ(ca % 3, 0);  // only 0-1 along x survives
    }
    EXPECT_NE(ca % 3, 2);
    EXPECT_NE(cb % 3, 2);
    const double f = std::max(ca % 3, cb % 3) == 0 ? f0 : f1;
    EXPECT_NEAR(b.kn[k], f * 3.7e9, 1e-6);
    EXPECT_NEAR(b.ks[k], f * 1.3e9, 1e-6);
    EXPECT_NEAR(b.sigma_c[k], f * 2.9e6, 1e-9);
    EXPECT_NEAR(b.tau_c[k], f * 4.1e6, 1e-9);
    EXPECT_DOUBLE_EQ(b.radius[k], 0.8 * 1500.0);
    EXPECT_DOUBLE_EQ(b.length0[k], 3000.0);
  }
  EXPECT_EQ(x_pairs, 9);
  // D_c = 1 reads D as an area fraction: all 54 pairs, the x = 2 ones at 1 - 0.125.
  auto p1 = p;
  p1.damage_critical = 1.0;
  const common::BondTable all = handoff::face_bonds(s, p1, "block.h5");
  EXPECT_EQ(all.size(), 54u);
  const auto m1 = by_factor(all, p.kn);
  EXPECT_EQ(m1.at(key(1.0 - 0.0137)), 12);
  EXPECT_EQ(m1.at(key(1.0 - 0.0731)), 9 + 12);
  EXPECT_EQ(m1.at(key(1.0 - 0.125)), 9 + 12);
}

TEST(FaceBonds, RefusesSpheresWithoutDamageOrOffTheLattice) {
  const double D[3] = {0.0, 0.0, 0.0};
  common::SphereSet s = block(2.0, D);
  s.fields.clear();
  try {
    handoff::face_bonds(s, params(), "in.h5");
    FAIL();
  } catch (const common::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("in.h5"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("bonds.enabled"), std::string::npos);
  }
  s = block(2.0, D);
  s.position[3 * 5] += 0.01;  // 0.5 % of the edge off its cell centre
  EXPECT_THROW(handoff::face_bonds(s, params(), "in.h5"), common::InputError);
}

// The same block through the hand-off: 6^3 MPM cells (h = 1, cells 2..7) coarsened by 2 into 3^3
// spheres of 8 particles; the lower-x half of each coarse cell has mass 1 and damage a, the upper
// half mass 3 and damage b, so the sphere damage is (a + 3 b) / 4: 0.05, 0.085 and 0.1425 along x.
TEST(FaceBonds, CoarsenedHandOffAveragesDamageByMass) {
  common::ParticleSnapshot s = testsets::filled_box(10, 1.0, 2, 6, 1, 1.0, [](const Eigen::Vector3d&) {
    return Eigen::Vector3d(0.0, 0.0, 0.0);
  });
  const double a[3] = {0.02, 0.04, 0.12}, b[3] = {0.06, 0.10, 0.15};
  common::Field dmg{"damage", "1", 1, {}, {}};
  for (std::size_t p = 0; p < s.count(); ++p) {
    const int cx = static_cast<int>(std::floor(s.position[3 * p])) - 2;  // MPM cell 0..5 in the box
    const int I = cx / 2;
    const bool upper = cx % 2 == 1;
    s.mass[p] = upper ? 3.0 : 1.0;
    dmg.values.push_back(upper ? b[I] : a[I]);
  }
  s.fields.push_back(dmg);
  handoff::HandoffConfig cfg;
  cfg.input = "synthetic.h5";
  cfg.projection.coarsen = 2;
  cfg.projection.carry_fields = {"damage"};
  cfg.bonds = params();
  const handoff::HandoffOutcome out = handoff::hand_off(s, cfg);
  const common::SphereSet& sph = out.result.spheres;
  ASSERT_EQ(sph.count(), 27u);
  const common::BondTable& bt = sph.bonds;
  ASSERT_EQ(bt.size(), 33u);
  const double D0 = (0.02 + 3 * 0.06) / 4, D1 = (0.04 + 3 * 0.10) / 4;
  const auto m = by_factor(bt, cfg.bonds.kn);
  ASSERT_EQ(m.size(), 2u);
  EXPECT_EQ(m.at(key(1.0 - D0 / 0.125)), 12);
  EXPECT_EQ(m.at(key(1.0 - D1 / 0.125)), 21);
  for (std::size_t k = 0; k < bt.size(); ++k) {
    EXPECT_DOUBLE_EQ(bt.length0[k], 2.0);
    EXPECT_DOUBLE_EQ(bt.radius[k], 0.8 * 1.0);
  }
  // without bonds.enabled the sphere set has no bonds (and the file no /bonds group)
  cfg.bonds.enabled = false;
  EXPECT_TRUE(handoff::hand_off(s, cfg).result.spheres.bonds.empty());
}
