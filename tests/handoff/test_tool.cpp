// mpm2spheres as a user runs it: exit codes, no partial output, existing results kept.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <filesystem>
#include <fstream>

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
  // A sphere file given where a snapshot is expected.
  ASSERT_EQ(run("-i " + good + " -o " + d.f("spheres.h5")), 0);

  for (const char* bad : {"nogrid.h5", "empty.h5", "outside.h5", "nan.h5", "spheres.h5", "missing.h5"}) {
    EXPECT_EQ(run("-i " + d.f(bad) + " -o " + d.f("result.h5")), 2) << bad;
    EXPECT_FALSE(fs::exists(d.f("result.h5"))) << bad;
    EXPECT_FALSE(fs::exists(d.f("result.xmf"))) << bad;
  }
  EXPECT_EQ(run("-i " + good), 2);                                         // output missing
  EXPECT_EQ(run("-i " + good + " -o " + d.f("r.h5") + " --coarsen 0"), 2);   // out of range
  EXPECT_EQ(run("-i " + good + " -o " + d.f("r.h5") + " --method magic"), 2);
  EXPECT_EQ(run("-i " + good + " -o " + d.f("r.h5") + " --set select.min_damage=0.5"), 2);  // no damage field
  EXPECT_EQ(run("-i " + good + " -o " + d.f("r.h5") + " --set bogus=1"), 2);
  EXPECT_FALSE(fs::exists(d.f("r.h5")));
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
