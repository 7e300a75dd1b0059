/// @file test_bonds_file.cpp
/// Bonds from a sphere file in ssdem-grav (common/bond_file.hpp, bonds.from_file): the file's
/// bonds become the bond set; a bond pulled apart breaks and its stored energy appears in
/// series.csv (bond_released_J, total_J + bond_released_J conserved) and run_info.txt; snapshots
/// carry /bonds with the broken flags; a bad /bonds exits 2 naming the file and dataset and writes
/// nothing; the dt rule resolves stiff file bonds; no bonds: no bond arrays and no bond columns.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "common/sphere_file.hpp"
#include "ssdem/io.hpp"
#include "ssdem/scene_setup.hpp"

using namespace ssdem;
namespace fs = std::filesystem;

namespace {
const std::string kExe = SSDEM_GRAV_EXE;

std::string tmpdir(const std::string& name) {
  const fs::path p = fs::temp_directory_path() / ("ssdem_bf_" + name + "_" + std::to_string(getpid()));
  fs::remove_all(p);
  fs::create_directories(p);
  return p.string();
}
std::pair<int, std::string> run_capture(const std::string& args, const std::string& dir) {
  const std::string log = dir + "/log.txt";
  const std::string cmd = "OMP_NUM_THREADS=1 " + kExe + " " + args + " > " + log + " 2>&1";
  const int rc = std::system(cmd.c_str());
  std::ifstream f(log);
  return {WIFEXITED(rc) ? WEXITSTATUS(rc) : -1, std::string((std::istreambuf_iterator<char>(f)), {})};
}
std::vector<std::vector<std::string>> csv(const std::string& path) {
  std::ifstream f(path);
  std::vector<std::vector<std::string>> rows;
  for (std::string line; std::getline(f, line);) {
    std::vector<std::string> r;
    std::stringstream ss(line);
    for (std::string c; std::getline(ss, c, ',');) r.push_back(c);
    rows.push_back(r);
  }
  return rows;
}
std::size_t col(const std::vector<std::string>& header, const std::string& name) {
  for (std::size_t i = 0; i < header.size(); ++i)
    if (header[i] == name) return i;
  return header.size();
}

// Two unit spheres (m = 1 kg, r = 1 m, ids 5 and 9) touching at the origin, moving apart at
// 0.5 m/s each; one bond of radius 1 m (A = pi) with k_n A = 100 N/m and sigma_c = k_n * 0.04,
// i.e. it breaks at a stretch of 0.04 m (the free oscillation would reach v_rel / omega =
// 1 / sqrt(200) = 0.0707 m). Released energy 1/2 k_n A 0.04^2 = 0.08 J of the 0.25 J.
common::SphereSet pair_with_bond(bool bond = true) {
  common::SphereSet s;
  s.id = {5, 9};
  s.position = {-1.0, 0.0, 0.0, 1.0, 0.0, 0.0};
  s.velocity = {-0.5, 0.0, 0.0, 0.5, 0.0, 0.0};
  s.spin.assign(6, 0.0);
  s.mass = {1.0, 1.0};
  s.radius = {1.0, 1.0};
  const double kn = 100.0 / M_PI;
  if (bond) s.bonds.add(5, 9, kn, 0.4 * kn, kn * 0.04, 1e300, 1.0, 2.0);
  return s;
}
const char* kPairScene = R"(
[time]
end = 0.5
dt = 5e-5
[initial]
source = "file"
[gravity]
self = false
[contact]
parts = "normal"
normal.kn = 100.0
[output]
series_every = 200
checkpoint_wall = 0.0
snapshot_interval = 0.25
)";
}  // namespace

TEST(BondsFromFile, BrokenBondEnergyIsReportedInSeriesAndRunInfo) {
  const std::string d = tmpdir("pair");
  common::write_sphere_set(d + "/in.h5", pair_with_bond(), {"t", "0", "x", "t", ""});
  std::ofstream(d + "/s.toml") << kPairScene;
  const auto [rc, log] = run_capture("--scene " + d + "/s.toml --set initial.file=\\\"" + d +
                                         "/in.h5\\\" --set output.directory=\\\"" + d + "/o\\\"",
                                     d);
  ASSERT_EQ(rc, 0) << log;
  const auto rows = csv(d + "/o/series.csv");
  ASSERT_GT(rows.size(), 3u);
  const auto& h = rows[0];
  const std::size_t tot = col(h, "total_J"), rel = col(h, "bond_released_J"), be = col(h, "bond_elastic_J"),
                    el = col(h, "elastic_J"), in = col(h, "bonds_intact"), br = col(h, "bonds_broken");
  ASSERT_LT(std::max({rel, be, in, br}), h.size());
  EXPECT_EQ(h.back(), "bonds_broken");
  const double E0 = std::stod(rows[1][tot]);
  EXPECT_NEAR(E0, 0.25, 1e-15);
  EXPECT_EQ(rows[1][in], "1");
  EXPECT_EQ(rows[1][br], "0");
  bool seen_stretched = false;
  for (std::size_t r = 1; r < rows.size(); ++r) {
    const double total = std::stod(rows[r][tot]), released = std::stod(rows[r][rel]);
    // Nothing is lost: before the break to the leapfrog's O((omega h)^2) level; after it, to the
    // half kick of the breaking step that is not applied, at most F_c v_rel h / 2 = 4 N * 1 m/s * h / 2.
    const double tol = rows[r][in] == "1" ? 1e-6 * E0 : 4.0 * 1.0 * 5e-5 / 2.0;
    EXPECT_NEAR(total + released, E0, tol) << "row " << r;
    EXPECT_NEAR(std::stod(rows[r][be]), std::stod(rows[r][el]), 1e-15);  // no contact in between
    if (rows[r][in] == "1" && std::stod(rows[r][be]) > 0.01) seen_stretched = true;
  }
  EXPECT_TRUE(seen_stretched);
  const auto& last = rows.back();
  EXPECT_EQ(last[in], "0");
  EXPECT_EQ(last[br], "1");
  const double released = std::stod(last[rel]);
  EXPECT_GE(released, 0.08);  // it breaks in the first step past the strength
  EXPECT_LT(released, 0.08 * 1.005);
  std::ifstream ri(d + "/o/run_info.txt");
  const std::string info((std::istreambuf_iterator<char>(ri)), {});
  EXPECT_NE(info.find("1 bonds from " + d + "/in.h5 (0 of them broken)"), std::string::npos) << info;
  EXPECT_NE(info.find("bonds: 1 in all, 1 broken, 0 intact"), std::string::npos) << info;
  // the snapshots carry the bond with its flag: intact at t = 0, broken at the end
  const common::SphereSet s0 = common::read_sphere_set(d + "/o/snap_000000000.h5");
  ASSERT_EQ(s0.bonds.size(), 1u);
  EXPECT_EQ(s0.bonds.broken, std::vector<double>{0.0});
  EXPECT_EQ(s0.bonds.id_a[0], 5u);
  EXPECT_EQ(s0.bonds.kn[0], 100.0 / M_PI);
  const common::SphereSet s1 = common::read_sphere_set(d + "/o/snap_000010000.h5");
  EXPECT_EQ(s1.bonds.broken, std::vector<double>{1.0});
  std::ifstream x(d + "/o/snap_000010000.xmf");
  EXPECT_NE(std::string((std::istreambuf_iterator<char>(x)), {}).find("Polyline"), std::string::npos);
  // bonds.from_file = false: no bonds, and the series has no bond columns
  const auto [rc2, log2] = run_capture("--scene " + d + "/s.toml --set initial.file=\\\"" + d +
                                           "/in.h5\\\" --set output.directory=\\\"" + d + "/o2\\\" --set bonds.from_file=false",
                                       d);
  ASSERT_EQ(rc2, 0) << log2;
  const auto rows2 = csv(d + "/o2/series.csv");
  EXPECT_EQ(rows2[0].back(), "wall_s");
  EXPECT_EQ(col(rows2[0], "bond_released_J"), rows2[0].size());
  EXPECT_NEAR(std::stod(rows2.back()[col(rows2[0], "kinetic_J")]), 0.25, 1e-12);  // free flight
  fs::remove_all(d);
}

TEST(BondsFromFile, BadBondsExitTwoNamingFileAndDatasetAndWriteNothing) {
  const std::string d = tmpdir("bad");
  common::SphereSet s = pair_with_bond();
  s.bonds.add(9, 5, 1.0, 1.0, 1.0, 1.0, 0.5, 2.0);  // the same pair twice
  common::write_sphere_set(d + "/in.h5", s, {"t", "0", "x", "t", ""});
  std::ofstream(d + "/s.toml") << kPairScene;
  const auto [rc, log] = run_capture("--scene " + d + "/s.toml --set initial.file=\\\"" + d +
                                         "/in.h5\\\" --set output.directory=\\\"" + d + "/o\\\"",
                                     d);
  EXPECT_EQ(rc, 2);
  EXPECT_NE(log.find(d + "/in.h5"), std::string::npos) << log;
  EXPECT_NE(log.find("/bonds/id_a"), std::string::npos) << log;
  EXPECT_NE(log.find("bonded twice"), std::string::npos) << log;
  EXPECT_FALSE(fs::exists(d + "/o/series.csv"));
  // bonds.generate together with a file's bonds is refused, naming both
  common::write_sphere_set(d + "/in.h5", pair_with_bond(), {"t", "0", "x", "t", ""});
  const auto [rc2, log2] = run_capture("--scene " + d + "/s.toml --set initial.file=\\\"" + d +
                                           "/in.h5\\\" --set output.directory=\\\"" + d + "/o\\\" --set bonds.generate=true",
                                       d);
  EXPECT_EQ(rc2, 2);
  EXPECT_NE(log2.find("bonds.generate"), std::string::npos) << log2;
  EXPECT_NE(log2.find("bonds.from_file"), std::string::npos) << log2;
  fs::remove_all(d);
}

// time.dt = 0: a file bond 100x stiffer than the contacts sets the step (its axial half-period
// pi sqrt(mu / (k_n A)) over time.steps_per_contact) instead of being refused.
TEST(BondsFromFile, DtRuleResolvesStiffFileBonds) {
  const std::string d = tmpdir("dt");
  common::SphereSet s = pair_with_bond();
  s.bonds.kn[0] *= 100.0;
  s.bonds.ks[0] = 0.0;
  common::write_sphere_set(d + "/in.h5", s, {"t", "0", "x", "t", ""});
  const common::Schema schema = ssdem_schema();
  const common::Scene sc = common::Scene::parse(
      schema,
      "[time]\nend = 1.0\nsteps_per_contact = 30.0\n[initial]\nsource = \"file\"\nfile = \"" + d +
          "/in.h5\"\n[gravity]\nself = false\n[contact]\nparts = \"normal\"\nnormal.kn = 100.0\n",
      "t");
  BondSet fb;
  Spheres sp = initial_spheres(sc, &fb);
  ASSERT_EQ(fb.size(), 1u);
  const SimConfig c = sim_config(sc, sp, nullptr, &fb);
  ASSERT_EQ(c.bonds.size(), 1u);
  // axial: mu = 0.5 kg, k_n A = 1e4 N/m; bending pi sqrt(I_r / (k_n I)) with I_r = 0.2, k_n I = 1e4/4
  const double tau_axial = M_PI * std::sqrt(0.5 / 1e4), tau_bend = M_PI * std::sqrt(0.2 / 2500.0);
  EXPECT_NEAR(c.dt, std::min(tau_axial, tau_bend) / 30.0, 1e-15);
  Simulation sim(sp, c);  // not refused
  EXPECT_NE(sim.bond_system(), nullptr);
  fs::remove_all(d);
}

// No bonds, no cost: a file without /bonds and a file with bonds read with bonds.from_file =
// false build no bond system and the same bytes per sphere; with the bond, the difference is
// the bond arrays (161 B per bond) and nothing else.
TEST(BondsFromFile, NoBondsNoArraysNoCost) {
  const std::string d = tmpdir("cost");
  common::write_sphere_set(d + "/with.h5", pair_with_bond(true), {"t", "0", "x", "t", ""});
  common::write_sphere_set(d + "/without.h5", pair_with_bond(false), {"t", "0", "x", "t", ""});
  const common::Schema schema = ssdem_schema();
  auto make = [&](const std::string& file, const std::string& extra) {
    const common::Scene sc = common::Scene::parse(
        schema,
        "[time]\nend = 1.0\ndt = 1e-3\n[initial]\nsource = \"file\"\nfile = \"" + file +
            "\"\n[gravity]\nself = false\n[contact]\nparts = \"normal\"\nnormal.kn = 100.0\n" + extra,
        "t");
    BondSet fb;
    Spheres sp = initial_spheres(sc, &fb);
    return std::make_unique<Simulation>(sp, sim_config(sc, sp, nullptr, &fb));
  };
  const auto none = make(d + "/without.h5", "");
  const auto off = make(d + "/with.h5", "[bonds]\nfrom_file = false\n");
  const auto on = make(d + "/with.h5", "");
  EXPECT_EQ(none->bond_system(), nullptr);
  EXPECT_EQ(off->bond_system(), nullptr);
  ASSERT_NE(on->bond_system(), nullptr);
  EXPECT_EQ(none->bytes_per_sphere(), off->bytes_per_sphere());
  EXPECT_DOUBLE_EQ(on->bytes_per_sphere() - none->bytes_per_sphere(), 161.0 / 2.0);
  fs::remove_all(d);
}

// A run whose bonds came from its input file, stopped while the bond is intact and continued from
// its checkpoint, ends bit-identical to the uninterrupted run (bond state from /ssdem_state/bonds,
// dt from the checkpoint: no "differ from the checkpoint" warning).
TEST(BondsFromFile, RestartWithFileBondsIsBitIdentical) {
  const std::string d = tmpdir("restart");
  common::write_sphere_set(d + "/in.h5", pair_with_bond(), {"t", "0", "x", "t", ""});
  std::ofstream(d + "/s.toml") << kPairScene;
  const std::string base = "--scene " + d + "/s.toml --set initial.file=\\\"" + d + "/in.h5\\\"";
  ASSERT_EQ(run_capture(base + " --set output.directory=\\\"" + d + "/full\\\"", d).first, 0);
  ASSERT_EQ(run_capture(base + " --set output.directory=\\\"" + d + "/part\\\" --set time.end=0.02", d).first, 0);
  const auto [rc, log] = run_capture(base + " --set output.directory=\\\"" + d + "/part\\\" --restart " + d +
                                         "/part/checkpoint.h5",
                                     d);
  ASSERT_EQ(rc, 0) << log;
  EXPECT_EQ(log.find("differ from the checkpoint"), std::string::npos) << log;
  const common::SphereSet a = common::read_sphere_set(d + "/full/snap_000010000.h5");
  const common::SphereSet b = common::read_sphere_set(d + "/part/snap_000010000.h5");
  EXPECT_EQ(a.position, b.position);
  EXPECT_EQ(a.velocity, b.velocity);
  EXPECT_EQ(b.bonds.broken, std::vector<double>{1.0});
  const auto ra = csv(d + "/full/series.csv"), rb = csv(d + "/part/series.csv");
  const std::size_t rel = col(ra[0], "bond_released_J");
  EXPECT_EQ(ra.back()[rel], rb.back()[rel]);
  // run_info.txt of the continuation names the checkpoint as the bonds' source, with the bond
  // still intact at the stop (it breaks later), not the initial file
  std::ifstream ri(d + "/part/run_info.txt");
  const std::string info((std::istreambuf_iterator<char>(ri)), std::istreambuf_iterator<char>());
  EXPECT_NE(info.find("1 bonds from checkpoint " + d + "/part/checkpoint.h5 (0 of them broken)"), std::string::npos)
      << info;
  EXPECT_EQ(info.find("bonds from " + d + "/in.h5"), std::string::npos) << info;
  fs::remove_all(d);
}
