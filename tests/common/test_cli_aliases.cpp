/// @file test_cli_aliases.cpp
/// One vocabulary on the real executables (ssdem-grav, mpm-frag): renamed scene keys are still
/// read for one release. Each old name, in the scene file or by --set, gives the same resolved
/// scene as its new name, with a warning naming the file and both keys; old and new together is
/// an error (exit 2); --help-params lists the old names as deprecated.
#include <gtest/gtest.h>

#include <cctype>
#include <fstream>
#include <sstream>
#include <string>

#include "test_util.hpp"
#include "tool_runner.hpp"

namespace {

using Result = testutil::ToolResult;
Result grav(const std::string& args) { return testutil::run_tool(SSDEM_GRAV_EXE, args); }
Result mpm(const std::string& args) { return testutil::run_tool(MPM_FRAG_EXE, args); }

/// A minimal ssdem-grav scene with `initial` in [initial] and `output` in [output].
std::string grav_scene(const testutil::TempDir& d, const std::string& initial, const std::string& output) {
  const std::string p = d.file("grav.toml");
  std::ofstream(p) << "[time]\nend = 1.0\n[initial]\nsource = \"lattice_pile\"\nbody_radius = 3.0\n" << initial
                   << "[output]\n" << output;
  return p;
}

/// A minimal mpm-frag scene with `output` in [output] and `run` in [run].
std::string mpm_scene(const testutil::TempDir& d, const std::string& output, const std::string& run) {
  const std::string p = d.file("frag.toml");
  std::ofstream(p) << "[grid]\ndomain_min = [0.0, 0.0, 0.0]\ndomain_max = [0.2, 0.1, 0.1]\ncell_size = 0.01\n"
                      "[time]\nend = 5e-4\n[output]\n"
                   << output << "[run]\n" << run
                   << "[[material]]\nname = \"m\"\nmodel = \"elastic\"\ndensity = 1000.0\nbulk_modulus = 1e7\n"
                      "shear_modulus = 1e6\n[[body]]\nmaterial = \"m\"\nshape = \"sphere\"\n"
                      "center = [0.1, 0.05, 0.05]\nradius = 0.03\n";
  return p;
}

/// The printed scene part of `--print-scene` output (log lines start with "[hh:mm:ss]").
std::string printed_scene(const std::string& out) {
  std::istringstream in(out);
  std::string s;
  for (std::string l; std::getline(in, l);)
    if (!(l.size() > 1 && l[0] == '[' && std::isdigit(static_cast<unsigned char>(l[1])))) s += l + "\n";
  return s;
}

void expect_renamed(const Result& old_run, const Result& new_run, const std::string& source, const std::string& old_key,
                    const std::string& new_key) {
  ASSERT_EQ(old_run.rc, 0) << old_run.out;
  ASSERT_EQ(new_run.rc, 0) << new_run.out;
  EXPECT_NE(old_run.out.find(source + ": '" + old_key + "' is deprecated, use '" + new_key + "'"), std::string::npos)
      << old_run.out;
  EXPECT_EQ(new_run.out.find("deprecated"), std::string::npos) << new_run.out;
  EXPECT_EQ(printed_scene(old_run.out), printed_scene(new_run.out));  // the value is applied to the new key
}

}  // namespace

TEST(CliToolsAlias, SsdemGravOutputDirIsOutputDirectory) {
  testutil::TempDir d;
  const Result o = grav("--print-scene --scene " + grav_scene(d, "", "dir = \"somewhere\"\n"));
  const Result n = grav("--print-scene --scene " + grav_scene(d, "", "directory = \"somewhere\"\n"));
  expect_renamed(o, n, d.file("grav.toml"), "output.dir", "output.directory");
  EXPECT_NE(n.out.find("directory = 'somewhere'"), std::string::npos) << n.out;
  // the pipelines' scripts pass it with --set
  const Result s = grav("--print-scene --scene " + grav_scene(d, "", "") + " --set output.dir=\\\"somewhere\\\"");
  expect_renamed(s, n, "--set", "output.dir", "output.directory");
}

TEST(CliToolsAlias, SsdemGravOutputSnapshotEveryIsOutputSnapshotInterval) {
  testutil::TempDir d;
  const Result o = grav("--print-scene --scene " + grav_scene(d, "", "snapshot_every = 2.5\n"));
  const Result n = grav("--print-scene --scene " + grav_scene(d, "", "snapshot_interval = 2.5\n"));
  expect_renamed(o, n, d.file("grav.toml"), "output.snapshot_every", "output.snapshot_interval");
  EXPECT_NE(n.out.find("snapshot_interval = 2.5"), std::string::npos) << n.out;
}

TEST(CliToolsAlias, SsdemGravInitialSeedIsRunSeed) {
  testutil::TempDir d;
  const Result o = grav("--print-scene --scene " + grav_scene(d, "seed = 77\n", ""));
  const Result n = grav("--print-scene --scene " + grav_scene(d, "", "") + " --set run.seed=77");
  expect_renamed(o, n, d.file("grav.toml"), "initial.seed", "run.seed");
  EXPECT_NE(n.out.find("[run]\nseed = 77"), std::string::npos) << n.out;
}

TEST(CliToolsAlias, MpmFragRunProgressIntervalIsOutputProgressInterval) {
  testutil::TempDir d;
  const Result o = mpm("--print-scene --scene " + mpm_scene(d, "", "progress_interval = 42.0\n"));
  const Result n = mpm("--print-scene --scene " + mpm_scene(d, "progress_interval = 42.0\n", ""));
  expect_renamed(o, n, d.file("frag.toml"), "run.progress_interval", "output.progress_interval");
  EXPECT_NE(n.out.find("progress_interval = 42.0"), std::string::npos) << n.out;
}

TEST(CliToolsAlias, MpmFragSolverGravityIsGravityUniform) {
  testutil::TempDir d;
  const std::string scene = mpm_scene(d, "", "");
  const Result o = mpm("--print-scene --scene " + scene + " --set 'solver.gravity=[0.0, 0.0, -9.5]'");
  const Result n = mpm("--print-scene --scene " + scene + " --set 'gravity.uniform=[0.0, 0.0, -9.5]'");
  expect_renamed(o, n, "--set", "solver.gravity", "gravity.uniform");
  EXPECT_NE(n.out.find("[gravity]\nuniform = [ 0.0, 0.0, -9.5 ]"), std::string::npos) << n.out;
}

TEST(CliToolsAlias, OldAndNewNameTogetherIsExit2NamingBoth) {
  testutil::TempDir d;
  const Result g = grav("--scene " + grav_scene(d, "", "dir = \"a\"\ndirectory = \"b\"\n"));
  EXPECT_EQ(g.rc, 2) << g.out;
  EXPECT_NE(g.out.find("output.dir"), std::string::npos) << g.out;
  EXPECT_NE(g.out.find("'output.directory'"), std::string::npos) << g.out;
  const Result s = grav("--scene " + grav_scene(d, "seed = 1\n", "") + " --set run.seed=2 --set initial.seed=3");
  EXPECT_EQ(s.rc, 2) << s.out;
  const Result m = mpm("--scene " + mpm_scene(d, "progress_interval = 1.0\n", "progress_interval = 2.0\n"));
  EXPECT_EQ(m.rc, 2) << m.out;
  EXPECT_NE(m.out.find("run.progress_interval"), std::string::npos) << m.out;
  EXPECT_NE(m.out.find("'output.progress_interval'"), std::string::npos) << m.out;
}

TEST(CliToolsAlias, HelpParamsListsDeprecatedKeys) {
  const Result g = grav("--help-params");
  ASSERT_EQ(g.rc, 0);
  for (const char* k : {"output.dir  DEPRECATED: use output.directory", "output.snapshot_every  DEPRECATED: use "
                        "output.snapshot_interval", "initial.seed  DEPRECATED: use run.seed"})
    EXPECT_NE(g.out.find(k), std::string::npos) << k;
  const Result m = mpm("--help-params");
  EXPECT_NE(m.out.find("run.progress_interval  DEPRECATED: use output.progress_interval"), std::string::npos);
  EXPECT_NE(m.out.find("solver.gravity  DEPRECATED: use gravity.uniform"), std::string::npos);
}
