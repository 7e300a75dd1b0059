/// @file test_cli_hardening.cpp
/// The four executables on inputs and outputs found by fault injection: a path component over 255
/// bytes (was exit 1 "internal error (please report): filesystem error" for an input; exit 2 now,
/// exit 4 for an output that cannot be created, as for an output directory), an output that is a FIFO
/// or a device node (was replaced by a regular file), an input that is a FIFO (blocked forever).
/// Each must end with a documented exit code, a message naming the path, and nothing written.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "../handoff/particle_sets.hpp"
#include "common/particle_file.hpp"
#include "test_util.hpp"
#include "tool_runner.hpp"

namespace fs = std::filesystem;

namespace {

using Result = testutil::ToolResult;
/// Run `exe args` (one OpenMP thread, 60 s at most: a FIFO must not block it).
Result run(const std::string& exe, const std::string& args, const testutil::TempDir&) {
  return testutil::run_tool(exe, args, 60);
}

std::vector<std::string> names_in(const fs::path& dir) {
  std::vector<std::string> v;
  for (const auto& e : fs::directory_iterator(dir)) v.push_back(e.path().filename().string());
  std::sort(v.begin(), v.end());
  return v;
}

std::string src(const std::string& rel) { return std::string(SUITE_SOURCE_DIR) + "/" + rel; }

}  // namespace

TEST(CliHardening, OverlongPathComponentIsExit2InAllFourTools) {
  testutil::TempDir dir;
  const std::string lng = dir.file(std::string(300, 'x'));
  struct Case {
    const char* exe;
    std::string args;
    int rc;  // 2: an input path; 4: an output that cannot be created
  };
  const std::vector<Case> cases = {
      {MPM2SPHERES_EXE, "-i " + lng + ".h5 -o " + dir.file("o.h5"), 2},
      {SSDEM_ANALYSE_EXE, lng + ".h5 -o " + dir.file("a"), 2},
      {MPM2SPHERES_EXE, "-i " + lng + ".h5 -o " + lng + ".out.h5", 4},
      {MPM_FRAG_EXE, "--scene " + src("mpm/scenes/elastic_sphere.toml") + " --set output.directory='\"" + lng + "\"'", 4},
      {SSDEM_GRAV_EXE, "--scene " + src("nbody/scenes/two_bodies.toml") + " --set output.dir='\"" + lng + "\"'", 4},
  };
  for (const auto& c : cases) {
    const Result r = run(c.exe, c.args, dir);
    SCOPED_TRACE(c.exe);
    EXPECT_EQ(r.rc, c.rc) << r.out;
    EXPECT_NE(r.out.find(std::string(300, 'x')), std::string::npos) << r.out;  // names the path
    EXPECT_NE(r.out.find("File name too long"), std::string::npos) << r.out;
    EXPECT_EQ(r.out.find("internal error"), std::string::npos) << r.out;
    EXPECT_TRUE(names_in(dir.path).empty()) << "left: " << names_in(dir.path).front();
  }
}

TEST(CliHardening, Mpm2SpheresRefusesFifoAndDeviceOutputsAndFifoInput) {
  testutil::TempDir dir;
  const std::string in = dir.file("snap.h5");
  common::write_particle_snapshot(in, testsets::uniform(2000, 12, 1.0, 2.5, 9.5, 0.5), testutil::sample_provenance());
  fs::remove(dir.file("snap.xmf"));
  std::vector<std::string> outs = {dir.file("fifo.h5")};
  ASSERT_EQ(::mkfifo(outs[0].c_str(), 0600), 0);
  if (::geteuid() == 0) {  // as root the tool replaced the node (so `-o /dev/null` destroyed /dev/null)
    outs.push_back(dir.file("null.h5"));
    ASSERT_EQ(::mknod(outs[1].c_str(), S_IFCHR | 0666, makedev(1, 3)), 0);
  }
  const auto before = names_in(dir.path);
  for (const auto& out : outs) {
    const Result r = run(MPM2SPHERES_EXE, "-i " + in + " -o " + out, dir);
    EXPECT_EQ(r.rc, 2) << r.out;
    EXPECT_NE(r.out.find(out + ": output exists and is not a regular file"), std::string::npos) << r.out;
    struct stat st {};
    ASSERT_EQ(::stat(out.c_str(), &st), 0);
    EXPECT_FALSE(S_ISREG(st.st_mode)) << out << " was replaced by a regular file";
  }
  EXPECT_EQ(names_in(dir.path), before);
  const Result r = run(MPM2SPHERES_EXE, "-i " + outs[0] + " -o " + dir.file("o.h5"), dir);  // FIFO as input
  EXPECT_EQ(r.rc, 2) << r.out;
  EXPECT_NE(r.out.find(outs[0] + ": not a regular file"), std::string::npos) << r.out;
  EXPECT_EQ(names_in(dir.path), before);
}
