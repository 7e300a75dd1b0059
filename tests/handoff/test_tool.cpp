/// @file test_tool.cpp
/// mpm2spheres as a user runs it: exit codes (2 bad input, 3 energy threshold, 4 I/O), nothing
/// written on bad input (not even the audit), no partial file on an I/O failure, existing results
/// kept, material selection audited, --version and --print-scene.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <tuple>

#include "common/h5.hpp"
#include "common/sphere_file.hpp"
#include "particle_sets.hpp"

namespace fs = std::filesystem;

namespace {
struct Dir {
  fs::path p = fs::temp_directory_path() / ("m2s_" + std::to_string(::getpid()));
  Dir() { fs::create_directories(p); }
  ~Dir() { fs::remove_all(p); }
  std::string f(const std::string& n) const { return (p / n).string(); }
};

int run(const std::string& args) {
  const std::string cmd = std::string(MPM2SPHERES_EXE) + " --quiet " + args + " 2>/dev/null";
  const int rc = std::system(cmd.c_str());
  return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}

/// Run without --quiet and return {exit code, stdout + stderr} (captured in a file named after
/// this process: ctest runs tests in parallel processes).
std::pair<int, std::string> run_capture(const std::string& args) {
  const fs::path log = fs::temp_directory_path() / ("m2s_out_" + std::to_string(::getpid()) + ".log");
  const std::string cmd = std::string(MPM2SPHERES_EXE) + " " + args + " > " + log.string() + " 2>&1";
  const int rc = std::system(cmd.c_str());
  std::ifstream f(log);
  std::string out((std::istreambuf_iterator<char>(f)), {});
  fs::remove(log);
  return {WIFEXITED(rc) ? WEXITSTATUS(rc) : -1, out};
}

std::vector<std::string> entries(const fs::path& dir) {
  std::vector<std::string> v;
  for (const auto& e : fs::recursive_directory_iterator(dir)) v.push_back(fs::relative(e.path(), dir).string());
  std::sort(v.begin(), v.end());
  return v;
}

common::Provenance prov() { return {"test", "0", "x", "test", ""}; }

std::string good_snapshot(const Dir& d, const std::string& name = "snap.h5") {
  auto s = testsets::uniform(2000, 12, 1.0, 2.5, 9.5, 0.5);
  common::write_particle_snapshot(d.f(name), s, prov());
  return d.f(name);
}
}  // namespace

TEST(Mpm2SpheresTool, SuccessWritesSpheresSidecarAuditAndSs) {
  Dir d;
  const std::string in = good_snapshot(d);
  ASSERT_EQ(run("-i " + in + " -o " + d.f("out.h5") + " --ss " + d.f("out.ss")), 0);
  for (const char* f : {"out.h5", "out.xmf", "out.audit.json", "out.ss", "out.ss.json"}) EXPECT_TRUE(fs::exists(d.f(f))) << f;
  const auto s = common::read_sphere_set(d.f("out.h5"));
  EXPECT_GT(s.count(), 100u);
  common::h5::Handle f = common::h5::open_file_read(d.f("out.h5"));
  const auto p = common::h5::read_provenance(f, d.f("out.h5"));
  EXPECT_EQ(p.tool, "mpm2spheres");
  EXPECT_NE(p.scene_toml.find("method = 'paper'"), std::string::npos);
  EXPECT_NE(p.command_line.find("--ss"), std::string::npos);
  EXPECT_TRUE(common::h5::exists(f, "/handoff/particle_id"));
  EXPECT_LT(common::h5::read_attr_double(common::h5::open_group(f, "audit", ""), "mass_rel_diff", ""), 1e-13);
  std::ifstream j(d.f("out.audit.json"));
  std::string json((std::istreambuf_iterator<char>(j)), {});
  EXPECT_NE(json.find("\"kinetic_rel_loss\""), std::string::npos);
}

TEST(Mpm2SpheresTool, BadInputsExitTwoAndWriteNothing) {
  Dir d;
  const std::string good = good_snapshot(d);
  // No grid description.
  const std::string nogrid = good_snapshot(d, "nogrid.h5");
  {
    common::h5::quiet_errors();
    common::h5::Handle f(H5Fopen(nogrid.c_str(), H5F_ACC_RDWR, H5P_DEFAULT));
    H5Ldelete(f, "/grid", H5P_DEFAULT);
  }
  // Zero particles.
  common::ParticleSnapshot empty;
  empty.grid = testsets::grid(4, 1.0);
  common::write_particle_snapshot(d.f("empty.h5"), empty, prov());
  // A particle outside the grid.
  auto outside = testsets::uniform(100, 12, 1.0, 2.5, 9.5, 0.5);
  outside.position[0] = 11.9;  // its uGIMP support reaches past the last node
  common::write_particle_snapshot(d.f("outside.h5"), outside, prov());
  // A NaN velocity.
  auto nan = testsets::uniform(100, 12, 1.0, 2.5, 9.5, 0.5);
  nan.velocity[7] = std::numeric_limits<double>::quiet_NaN();
  common::write_particle_snapshot(d.f("nan.h5"), nan, prov());
  // A snapshot of an older format version (0 predates the contract).
  const std::string old = good_snapshot(d, "old.h5");
  {
    common::h5::quiet_errors();
    common::h5::Handle f(H5Fopen(old.c_str(), H5F_ACC_RDWR, H5P_DEFAULT));
    H5Adelete(f, "format_version");
    common::h5::write_attr(f, "format_version", std::int64_t{0});
  }
  // A sphere file given where a snapshot is expected.
  ASSERT_EQ(run("-i " + good + " -o " + d.f("spheres.h5")), 0);

  for (const char* bad : {"nogrid.h5", "empty.h5", "outside.h5", "nan.h5", "old.h5", "spheres.h5", "missing.h5"}) {
    EXPECT_EQ(run("-i " + d.f(bad) + " -o " + d.f("result.h5") + " --ss " + d.f("result.ss")), 2) << bad;
    for (const char* out : {"result.h5", "result.xmf", "result.audit.json", "result.ss", "result.ss.json"})
      EXPECT_FALSE(fs::exists(d.f(out))) << bad << ": " << out;
  }
  EXPECT_EQ(run("-i " + good), 2);                                         // output missing
  EXPECT_EQ(run("-i " + good + " -o " + d.f("r.h5") + " --coarsen 0"), 2);   // out of range
  EXPECT_EQ(run("-i " + good + " -o " + d.f("r.h5") + " --method magic"), 2);
  EXPECT_EQ(run("-i " + good + " -o " + d.f("r.h5") + " --set select.min_damage=0.5"), 2);  // no damage field
  EXPECT_EQ(run("-i " + good + " -o " + d.f("r.h5") + " --set select.exclude_materials=[0]"), 2);  // drops all
  EXPECT_EQ(run("-i " + good + " -o " + d.f("r.h5") + " --set select.exclude_materials=[0.5]"), 2);
  EXPECT_EQ(run("-i " + good + " -o " + d.f("r.h5") + " --set bogus=1"), 2);
  EXPECT_FALSE(fs::exists(d.f("r.h5")));
  EXPECT_FALSE(fs::exists(d.f("r.audit.json")));
  // The message names the file and the dataset.
  const auto [rc, msg] = run_capture("-i " + d.f("nan.h5") + " -o " + d.f("r.h5"));
  EXPECT_EQ(rc, 2);
  EXPECT_NE(msg.find(d.f("nan.h5") + ": /particles/velocity: non-finite value (NaN or Inf) at row 2"),
            std::string::npos)
      << msg;
  const auto [rc_old, msg_old] = run_capture("-i " + old + " -o " + d.f("r.h5"));
  EXPECT_EQ(rc_old, 2);
  EXPECT_NE(msg_old.find(old + ": /format_version: version 0 is older than the oldest this tool reads (1)"),
            std::string::npos)
      << msg_old;
}

TEST(Mpm2SpheresTool, EnergyThresholdExitsThreeAndKeepsExistingResult) {
  Dir d;
  const std::string in = good_snapshot(d);
  ASSERT_EQ(run("-i " + in + " -o " + d.f("out.h5")), 0);
  const auto before = fs::last_write_time(d.f("out.h5"));
  const auto size = fs::file_size(d.f("out.h5"));
  EXPECT_EQ(run("-i " + in + " -o " + d.f("out.h5") + " --max-ke-loss 1e-9"), 3);
  EXPECT_EQ(fs::last_write_time(d.f("out.h5")), before);  // the earlier result is untouched
  EXPECT_EQ(fs::file_size(d.f("out.h5")), size);
  EXPECT_TRUE(fs::exists(d.f("out.audit.json")));          // the audit explains why
  EXPECT_EQ(run("-i " + in + " -o " + d.f("c.h5") + " --method conserving --max-ke-loss 1e-9"), 0);
}

TEST(Mpm2SpheresTool, ExcludedMaterialsAreDroppedAndAudited) {
  Dir d;
  auto s = testsets::uniform(3000, 12, 1.0, 2.5, 9.5, 0.5, 4);
  for (std::size_t p = 0; p < s.count(); ++p) s.material[p] = static_cast<std::int32_t>(p % 3);
  common::write_particle_snapshot(d.f("mixed.h5"), s, prov());
  ASSERT_EQ(run("-i " + d.f("mixed.h5") + " -o " + d.f("out.h5") + " --set select.exclude_materials=[2,1]"), 0);

  // What the selection must drop: materials 1 and 2 (two thirds of the particles).
  double m_drop = 0, m_keep = 0, scale = 0;
  Eigen::Vector3d p_drop = Eigen::Vector3d::Zero(), p_keep = Eigen::Vector3d::Zero();
  std::set<std::uint64_t> kept_ids;
  for (std::size_t p = 0; p < s.count(); ++p) {
    const Eigen::Vector3d mv = s.mass[p] * Eigen::Vector3d(&s.velocity[3 * p]);
    scale += mv.norm();
    if (s.material[p] == 0) {
      m_keep += s.mass[p];
      p_keep += mv;
      kept_ids.insert(s.id[p]);
    } else {
      m_drop += s.mass[p];
      p_drop += mv;
    }
  }
  namespace h5 = common::h5;
  h5::Handle f = h5::open_file_read(d.f("out.h5"));
  h5::Handle a = h5::open_group(f, "audit", "");
  EXPECT_EQ(h5::read_attr_int(a, "dropped_count", ""), 2000);
  EXPECT_EQ(h5::read_attr_int(a, "before_count", ""), 1000);
  EXPECT_NEAR(h5::read_attr_double(a, "dropped_mass", ""), m_drop, 1e-12 * m_drop);
  EXPECT_NEAR(h5::read_attr_double(a, "before_mass", ""), m_keep, 1e-12 * m_keep);
  const auto pd = h5::read_attr_doubles(a, "dropped_momentum", "");
  ASSERT_EQ(pd.size(), 3u);
  EXPECT_LT((Eigen::Vector3d(pd[0], pd[1], pd[2]) - p_drop).norm(), 1e-12 * scale);
  // The spheres carry the kept particles' mass and momentum, and only their ids.
  const auto sph = common::read_sphere_set(d.f("out.h5"));
  double m_sph = 0;
  Eigen::Vector3d p_sph = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < sph.count(); ++i) {
    m_sph += sph.mass[i];
    p_sph += sph.mass[i] * Eigen::Vector3d(&sph.velocity[3 * i]);
  }
  EXPECT_NEAR(m_sph, m_keep, 1e-12 * m_keep);
  EXPECT_LT((p_sph - p_keep).norm(), 1e-12 * scale);
  const auto ids = h5::read_u64(f, "/handoff/particle_id", -1, 1, d.f("out.h5"));
  EXPECT_EQ(std::set<std::uint64_t>(ids.begin(), ids.end()), kept_ids);
  EXPECT_EQ(ids.size(), kept_ids.size());
  // The JSON audit says the same.
  std::ifstream j(d.f("out.audit.json"));
  const std::string json((std::istreambuf_iterator<char>(j)), {});
  EXPECT_NE(json.find("\"dropped\": {\"count\": 2000, "), std::string::npos) << json;
}

TEST(Mpm2SpheresTool, IoFailureExitsFourAndLeavesNoPartialFile) {
  Dir d;
  const std::string in = good_snapshot(d);
  const auto before = entries(d.p);
  // An output directory that does not exist (the tool does not create it).
  auto [rc, msg] = run_capture("-i " + in + " -o " + d.f("no_such_dir/out.h5"));
  EXPECT_EQ(rc, 4) << msg;
  EXPECT_NE(msg.find("I/O failure: " + d.f("no_such_dir/")), std::string::npos) << msg;
  EXPECT_NE(msg.find("does not exist"), std::string::npos) << msg;
  EXPECT_EQ(entries(d.p), before);  // nothing written, no directory created
  // An output name taken by a directory: the rename fails after the file was written.
  fs::create_directory(d.f("taken.h5"));
  std::tie(rc, msg) = run_capture("-i " + in + " -o " + d.f("taken.h5"));
  EXPECT_EQ(rc, 4) << msg;
  EXPECT_NE(msg.find(d.f("taken.h5") + ": cannot rename temporary file into place"), std::string::npos) << msg;
  EXPECT_TRUE(fs::is_directory(d.f("taken.h5")));
  EXPECT_TRUE(fs::is_empty(d.f("taken.h5")));
  for (const auto& e : entries(d.p)) {
    EXPECT_EQ(e.find(".tmp."), std::string::npos) << "temporary file left behind: " << e;
    EXPECT_NE(e, "taken.xmf");
  }
}

TEST(Mpm2SpheresTool, VersionAndPrintSceneReadBack) {
  auto [rc, out] = run_capture("--version");
  EXPECT_EQ(rc, 0);
  EXPECT_TRUE(std::regex_match(out, std::regex("mpm2spheres [0-9]+\\.[0-9]+\\.[0-9]+ \\(git ([0-9a-f]{12}(\\+dirty)?|unknown)\\)\n")))
      << out;
  Dir d;
  // With a damage field: the printed scene lists the default `carry = 'damage'` as if given, and
  // a given carry field must exist (a snapshot without damage would be refused on the rerun).
  auto snap = testsets::uniform(2000, 12, 1.0, 2.5, 9.5, 0.5);
  snap.fields.push_back({"damage", "1", 1, std::vector<double>(snap.count(), 0.5), ""});
  const std::string in = d.f("damaged.h5");
  common::write_particle_snapshot(in, snap, prov());
  // The flags resolve into the scene that --print-scene prints; that scene runs as it stands.
  std::tie(rc, out) = run_capture("-i " + in + " -o " + d.f("c.h5") + " --coarsen 3 --method conserving --print-scene");
  ASSERT_EQ(rc, 0) << out;
  EXPECT_NE(out.find("coarsen = 3\n"), std::string::npos) << out;
  EXPECT_NE(out.find("method = 'conserving'\n"), std::string::npos) << out;
  EXPECT_NE(out.find("max_energy_loss = 1.0\n"), std::string::npos) << out;  // a default
  EXPECT_FALSE(fs::exists(d.f("c.h5")));                                     // printing runs nothing
  std::ofstream(d.f("printed.toml")) << out;
  const auto again = run_capture("--scene " + d.f("printed.toml") + " --print-scene");
  EXPECT_EQ(again.first, 0);
  EXPECT_EQ(again.second, out);
  ASSERT_EQ(run("--scene " + d.f("printed.toml")), 0);
  const auto s = common::read_sphere_set(d.f("c.h5"));
  ASSERT_GT(s.count(), 0u);
  EXPECT_DOUBLE_EQ(s.radius[0], 1.5);  // coarsen 3 x h = 1 m, halved
  ASSERT_NE(s.field("damage"), nullptr);
  EXPECT_DOUBLE_EQ(s.field("damage")->values[0], 0.5);
  common::h5::Handle f = common::h5::open_file_read(d.f("c.h5"));
  EXPECT_EQ(common::h5::read_attr_string(common::h5::open_group(f, "audit", ""), "method", ""), "conserving");
}

// bonds.enabled: /bonds written with the XDMF lines and the law's inputs in /handoff; refused
// (exit 2, nothing written) without bonds.kn or without a damage field.
TEST(Mpm2SpheresTool, BondsWrittenOrRefused) {
  Dir d;
  auto s = testsets::filled_box(10, 1.0, 2, 4, 1, 1.0, [](const Eigen::Vector3d&) { return Eigen::Vector3d(0, 0, 1); });
  common::write_particle_snapshot(d.f("nodamage.h5"), s, prov());
  s.fields.push_back(common::Field{"damage", "1", 1, std::vector<double>(s.count(), 0.05), ""});
  common::write_particle_snapshot(d.f("snap.h5"), s, prov());
  const std::string bonds = " --set bonds.enabled=true --set bonds.kn=2e9 --set bonds.sigma_c=3e6";
  ASSERT_EQ(run("-i " + d.f("snap.h5") + " -o " + d.f("out.h5") + bonds), 0);
  const auto sph = common::read_sphere_set(d.f("out.h5"));
  ASSERT_EQ(sph.count(), 64u);
  ASSERT_EQ(sph.bonds.size(), 3u * 4u * 3u * 4u);  // 4^3 block: 3 axes x 16 lines x 3 pairs = 144
  for (std::size_t k = 0; k < sph.bonds.size(); ++k) {
    EXPECT_NEAR(sph.bonds.kn[k], 2e9 * (1 - 0.05 / 0.125), 1e-3);
    EXPECT_NEAR(sph.bonds.sigma_c[k], 3e6 * (1 - 0.05 / 0.125), 1e-6);
  }
  std::ifstream x(d.f("out.xmf"));
  EXPECT_NE(std::string((std::istreambuf_iterator<char>(x)), {}).find("TopologyType=\"Polyline\" NumberOfElements=\"144\""),
            std::string::npos);
  common::h5::Handle f = common::h5::open_file_read(d.f("out.h5"));
  EXPECT_EQ(common::h5::read_attr_int(common::h5::open_group(f, "handoff", ""), "bonds_count", ""), 144);
  for (const auto& [args, what] : {std::pair<std::string, std::string>{"-i " + d.f("snap.h5") + " --set bonds.enabled=true", "bonds.kn"},
                                   {"-i " + d.f("nodamage.h5") + bonds, "bonds.enabled"}}) {
    const auto [rc, out] = run_capture(args + " -o " + d.f("bad.h5"));
    EXPECT_EQ(rc, 2) << out;
    EXPECT_NE(out.find(what), std::string::npos) << out;
    EXPECT_FALSE(fs::exists(d.f("bad.h5")));
    EXPECT_FALSE(fs::exists(d.f("bad.audit.json")));
  }
}
