/// @file test_run_safety.cpp
/// A run is safe as a whole, on the real executables:
///  1. finite but extreme inputs (density 1e308, a 4.3e9 m body, velocity or spin 1e308 in an
///     input file) are refused with exit 2 naming the file/key and the allowed range, never
///     written as Inf with exit 0; outputs are checked finite before they are written;
///  2. --restart refuses the checkpoint of another run (exit 2, naming both run identities and
///     the keys that differ), leaving the directory as it was;
///  3. an output directory holds one complete run: a run killed (SIGKILL/SIGTERM) or failing
///     leaves the previous run's files byte for byte, its own output in <dir>/.staging-<pid>;
///     a second run into a directory in use is refused with exit 2 naming the holder's pid;
///  4. a full disk under the staging directory (a tmpfs filled up, when the test runs as root; a
///     file-size limit, always) ends mpm-frag and ssdem-grav with exit 4 and a message naming the
///     staging directory, the previous complete run byte for byte.
#include <gtest/gtest.h>
#include <sys/prctl.h>
#include <sys/statvfs.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <thread>

#include "common/finite.hpp"
#include "common/particle_file.hpp"
#include "common/sphere_file.hpp"
#include "common/status.hpp"
#include "test_util.hpp"
#include "tool_runner.hpp"

namespace fs = std::filesystem;
using namespace common;

namespace {

using Result = testutil::ToolResult;
Result run(const std::string& exe, const std::string& args) { return testutil::run_tool(exe, args); }
Result grav(const std::string& args) { return run(SSDEM_GRAV_EXE, args); }
Result mpm(const std::string& args) { return run(MPM_FRAG_EXE, args); }
Result handoff(const std::string& args) { return run(MPM2SPHERES_EXE, args); }

std::string slurp(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(f), {});
}
std::size_t line_count(const std::string& path) {
  std::ifstream f(path);
  std::size_t n = 0;
  for (std::string l; std::getline(f, l);) ++n;
  return n;
}
/// Every regular file directly in `dir` except the run lock, name -> content.
std::map<std::string, std::string> contents(const std::string& dir) {
  std::map<std::string, std::string> m;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.is_regular_file() && e.path().filename() != ".lock") m[e.path().filename().string()] = slurp(e.path().string());
  return m;
}
std::vector<std::string> names(const std::map<std::string, std::string>& m) {
  std::vector<std::string> v;
  for (const auto& [k, _] : m) v.push_back(k);
  return v;
}

/// Start `exe --quiet --scene scene --set ...` in the background; it dies with us.
pid_t spawn(const std::string& exe, const std::string& scene, const std::vector<std::string>& sets) {
  return testutil::spawn_tool(exe, scene, sets);
}
using testutil::wait_for;
std::string staging(const std::string& dir, pid_t pid) { return dir + "/.staging-" + std::to_string(pid); }

/// The 19-sphere pile of test_cli_tools (self-gravity + contacts), snapshots every 10 s.
std::string pile_scene(const testutil::TempDir& d, const std::string& out_dir, const std::string& extra = "") {
  const std::string p = d.file("pile.toml");
  std::ofstream(p) << "[time]\nend = 30.0\n[initial]\nsource = \"lattice_pile\"\nbody_radius = 4.0\n"
                      "sphere_radius = 1.0\ndensity = 2000.0\nangular_velocity = [0.0, 0.0, 2e-4]\n"
                      "[gravity]\nevery = 3\n[contact]\npreset = \"gravel\"\n[output]\ndirectory = \""
                   << out_dir << "\"\nsnapshot_interval = 10.0\nseries_every = 30\ncheckpoint_wall = 0.0\n"
                   << "progress_interval = 100.0\n" << extra;
  return p;
}
/// An elastic sphere in a 20 cm grid (test_cli_tools' edge scene, moving slowly).
std::string mpm_scene(const testutil::TempDir& d, const std::string& out_dir) {
  const std::string p = d.file("edge.toml");
  std::ofstream(p) << "[grid]\ndomain_min = [0.0, 0.0, 0.0]\ndomain_max = [0.2, 0.1, 0.1]\ncell_size = 0.01\n"
                      "[time]\nend = 5e-4\n[output]\ndirectory = \""
                   << out_dir << "\"\nprefix = \"edge\"\nsnapshot_interval = 1e-4\nseries_every = 5\n"
                   << "progress_interval = 100.0\n[[material]]\nname = \"m\"\nmodel = \"elastic\"\ndensity = 1000.0\n"
                      "bulk_modulus = 1e7\nshear_modulus = 1e6\n[[body]]\nmaterial = \"m\"\nshape = \"sphere\"\n"
                      "center = [0.1, 0.05, 0.05]\nradius = 0.03\nvelocity = [1.0, 0.0, 0.0]\n";
  return p;
}

}  // namespace

// ---- 1. extreme values -------------------------------------------------------------------------

TEST(RunSafety, ExtremeSceneValuesAreRefusedWithTheirRange) {
  testutil::TempDir d;
  const std::string out = d.file("o");
  const std::string scene = pile_scene(d, out);
  // density 1e308 used to give mass = Inf in every output, with exit 0
  Result r = grav("--scene " + scene + " --set initial.density=1e308");
  EXPECT_EQ(r.rc, 2) << r.out;
  EXPECT_NE(r.out.find("initial.density: out of range: allowed (0, 100000] kg/m^3, got 1e+308"), std::string::npos)
      << r.out;
  EXPECT_FALSE(fs::exists(out + "/snap_000000000.h5"));
  // a 4.3e9 m body of 1 m spheres used to spin in the generator (~1e29 spheres)
  const auto t0 = std::chrono::steady_clock::now();
  r = grav("--scene " + scene + " --set initial.body_radius=4294967296");
  EXPECT_EQ(r.rc, 2) << r.out;
  EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::seconds(20));
  EXPECT_NE(r.out.find("initial.body_radius, " + scene + ": initial.sphere_radius: the generator would create about 5.867e+28 spheres; at most 1e+08"),
            std::string::npos)
      << r.out;
  EXPECT_FALSE(fs::exists(out + "/snap_000000000.h5"));
  r = grav("--scene " + scene + " --set initial.velocity=[1e308,0,0]");
  EXPECT_EQ(r.rc, 2) << r.out;
  EXPECT_NE(r.out.find("initial.velocity"), std::string::npos) << r.out;
  // mpm-frag: a body at 1e308 m/s
  r = mpm("--scene " + mpm_scene(d, d.file("m")) + " --set body[0].velocity=[1e308,0,0]");
  EXPECT_EQ(r.rc, 2) << r.out;
  EXPECT_NE(r.out.find("velocity"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("each in [-10000000, 10000000] m/s"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(d.file("m/edge_000000.h5")));
}

TEST(RunSafety, ExtremeValuesInInputFilesAreRefused) {
  testutil::TempDir d;
  // ssdem-grav: a sphere spinning at 1e308 rad/s in its input file
  SphereSet s = testutil::sample_spheres(10);
  s.spin[4] = 1e308;
  write_sphere_set(d.file("spin.h5"), s, testutil::sample_provenance());
  const std::string scene = d.file("file.toml");
  std::ofstream(scene) << "[time]\nend = 1.0\n[initial]\nsource = \"file\"\nfile = \"" << d.file("spin.h5")
                       << "\"\n[gravity]\nself = false\n[contact]\nnormal.kn = 1e3\n[output]\ndirectory = \""
                       << d.file("out") << "\"\n";
  Result r = grav("--scene " + scene);
  EXPECT_EQ(r.rc, 2) << r.out;
  EXPECT_NE(r.out.find(d.file("spin.h5") + ": /spheres/spin: magnitude 1e+308 rad/s at index 1 exceeds the allowed maximum 10000 rad/s"),
            std::string::npos)
      << r.out;
  EXPECT_FALSE(fs::exists(d.file("out/snap_000000000.h5")));

  // mpm2spheres: a particle at 1e308 m/s gave Inf sphere velocities, kinetic_rel_loss 0, exit 0
  ParticleSnapshot p = testutil::sample_particles(400);
  ASSERT_EQ(handoff("--quiet -i " + [&] {
              write_particle_snapshot(d.file("good.h5"), p, testutil::sample_provenance());
              return d.file("good.h5");
            }() + " -o " + d.file("good_spheres.h5") + " --max-ke-loss 1.0").rc,
            0);
  p.velocity[3] = 1e308;
  write_particle_snapshot(d.file("fast.h5"), p, testutil::sample_provenance());
  r = handoff("-i " + d.file("fast.h5") + " -o " + d.file("spheres.h5") + " --max-ke-loss 0.5");
  EXPECT_EQ(r.rc, 2) << r.out;
  EXPECT_NE(r.out.find(d.file("fast.h5") + ": /particles/velocity: magnitude 1e+308 m/s at index 1 exceeds the allowed maximum 10000000 m/s"),
            std::string::npos)
      << r.out;
  EXPECT_FALSE(fs::exists(d.file("spheres.h5")));
}

TEST(RunSafety, NonFiniteOutputsAreNeverWritten) {
  testutil::TempDir d;
  SphereSet s = testutil::sample_spheres(5);
  s.velocity[2] = 1e200;  // finite, but 1/2 m v^2 is not
  EXPECT_THROW(check_output_spheres(s, d.file("x.h5")), NumericalError);
  s.velocity[2] = 0;
  s.spin[0] = INFINITY;
  try {
    check_output_spheres(s, d.file("x.h5"));
    FAIL() << "no NumericalError";
  } catch (const NumericalError& e) {
    EXPECT_NE(std::string(e.what()).find("spin[0] = inf is not finite"), std::string::npos) << e.what();
  }
  ParticleSnapshot p = testutil::sample_particles(5);
  p.mass[1] = NAN;
  EXPECT_THROW(check_output_particles(p, d.file("p.h5")), NumericalError);
}

// ---- 2. restart from another run's checkpoint ------------------------------------------------

TEST(RunSafety, RestartRefusesTheCheckpointOfAnotherRun) {
  testutil::TempDir d;
  const std::string out = d.file("o");
  const std::string scene = pile_scene(d, out);
  ASSERT_EQ(grav("--quiet --scene " + scene).rc, 0);  // run A
  const auto a = contents(out);
  ASSERT_TRUE(a.count("checkpoint.h5"));
  // Run B (another density) into the same directory, killed before its first checkpoint.
  const pid_t pid = spawn(SSDEM_GRAV_EXE, scene, {"time.end=1e7", "initial.density=3000.0"});
  ASSERT_GT(pid, 0);
  const bool started = wait_for([&] { return line_count(staging(out, pid) + "/series.csv.partial") >= 3; });
  kill(pid, SIGKILL);
  int status = 0;
  waitpid(pid, &status, 0);
  ASSERT_TRUE(started);
  // B's restart finds A's checkpoint: refused, naming both identities and the differing key.
  const Result r = grav("--scene " + scene + " --set initial.density=3000.0 --restart " + out + "/checkpoint.h5");
  EXPECT_EQ(r.rc, 2) << r.out;
  EXPECT_NE(r.out.find(out + "/checkpoint.h5: checkpoint of another run (run identity "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("than this scene's (run identity "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("they differ in initial.density: this run 3000.0, checkpoint 2000.0"), std::string::npos)
      << r.out;
  EXPECT_EQ(contents(out), a);  // A's run untouched
  // A's own restart (a later end time) is accepted.
  const Result ok = grav("--quiet --scene " + scene + " --set time.end=40.0 --restart " + out + "/checkpoint.h5");
  EXPECT_EQ(ok.rc, 0) << ok.out;
  // A cost setting, the tree's sink group size, may change on restart (a long run continues with
  // a new default); the opening angle, which sets the force error, may not.
  const Result group = grav("--quiet --scene " + scene + " --set time.end=45.0 --set gravity.group=16 --restart " +
                            out + "/checkpoint.h5");
  EXPECT_EQ(group.rc, 0) << group.out;
  const Result theta = grav("--scene " + scene + " --set time.end=50.0 --set gravity.theta=0.5 --restart " + out +
                            "/checkpoint.h5");
  EXPECT_EQ(theta.rc, 2) << theta.out;
  EXPECT_NE(theta.out.find("they differ in gravity.theta: this run 0.5, checkpoint 0.25"), std::string::npos)
      << theta.out;
}

// ---- 3. one complete run per directory ------------------------------------------------------

TEST(RunSafety, SsdemGravKilledOrInterruptedRunLeavesThePreviousRunIntact) {
  testutil::TempDir d;
  const std::string out = d.file("o");
  const std::string scene = pile_scene(d, out);
  ASSERT_EQ(grav("--quiet --scene " + scene).rc, 0);  // the previous, complete run
  const auto before = contents(out);
  ASSERT_TRUE(before.count("snap_000000114.h5"));
  for (const int sig : {SIGKILL, SIGTERM}) {
    const pid_t pid = spawn(SSDEM_GRAV_EXE, scene, {"time.end=1e7", "output.snapshot_interval=1.0"});
    ASSERT_GT(pid, 0);
    const bool started = wait_for([&] { return line_count(staging(out, pid) + "/series.csv.partial") >= 5; });
    kill(pid, sig);
    int status = 0;
    waitpid(pid, &status, 0);
    ASSERT_TRUE(started);
    if (sig == SIGTERM) {
      ASSERT_TRUE(WIFEXITED(status));
      EXPECT_EQ(WEXITSTATUS(status), 128 + SIGTERM);
      EXPECT_TRUE(fs::exists(staging(out, pid) + "/checkpoint.h5"));  // where --restart expects it
    }
    EXPECT_EQ(contents(out), before) << "signal " << sig;  // byte for byte, no stray .partial
    EXPECT_TRUE(fs::exists(staging(out, pid) + "/snap_000000000.h5"));
  }
  // The next complete run replaces the directory's content and clears the dead runs' staging.
  ASSERT_EQ(grav("--quiet --scene " + scene + " --set output.snapshot_interval=0.0").rc, 0);
  const auto after = contents(out);
  EXPECT_EQ(names(after), (std::vector<std::string>{".run-manifest", "checkpoint.h5", "checkpoint.xmf", "run_info.txt",
                                                    "series.csv", "snap_000000000.h5", "snap_000000000.xmf",
                                                    "snap_000000114.h5", "snap_000000114.xmf"}));
  for (const auto& e : fs::directory_iterator(out)) EXPECT_FALSE(e.is_directory()) << e.path();
}

TEST(RunSafety, MpmFragKilledRunLeavesThePreviousRunIntact) {
  testutil::TempDir d;
  const std::string out = d.file("o");
  const std::string scene = mpm_scene(d, out);
  ASSERT_EQ(mpm("--quiet --scene " + scene).rc, 0);
  const auto before = contents(out);
  ASSERT_TRUE(before.count("edge_series.csv"));
  const pid_t pid = spawn(MPM_FRAG_EXE, scene, {"time.end=1.0", "output.snapshot_interval=2e-5"});
  ASSERT_GT(pid, 0);
  const bool started = wait_for([&] { return fs::exists(staging(out, pid) + "/edge_000010.h5"); });
  kill(pid, SIGKILL);
  int status = 0;
  waitpid(pid, &status, 0);
  ASSERT_TRUE(started);
  EXPECT_EQ(contents(out), before);  // the earlier run's snapshots and series, byte for byte
  // A failing run (the sphere leaves the grid: exit 3) keeps the earlier run too, and says
  // where its own output (its series, the last good state) is.
  const Result r3 = mpm("--scene " + scene + " --set body[0].velocity=[20.0,0.0,0.0] --set time.end=1.0");
  ASSERT_EQ(r3.rc, 3) << r3.out;
  EXPECT_NE(r3.out.find("the run did not complete; " + out + " is unchanged and this run's partial output is in " + out +
                        "/.staging-"),
            std::string::npos)
      << r3.out;
  EXPECT_EQ(contents(out), before);
}

TEST(RunSafety, SecondRunIntoADirectoryInUseIsRefused) {
  testutil::TempDir d;
  const std::string out = d.file("o");
  const std::string scene = pile_scene(d, out);
  const pid_t pid = spawn(SSDEM_GRAV_EXE, scene, {"time.end=1e7"});
  ASSERT_GT(pid, 0);
  const bool started = wait_for([&] { return line_count(staging(out, pid) + "/series.csv.partial") >= 3; });
  const Result g = grav("--scene " + scene);
  const Result m = mpm("--scene " + mpm_scene(d, out));
  kill(pid, SIGKILL);
  int status = 0;
  waitpid(pid, &status, 0);
  ASSERT_TRUE(started);
  const std::string msg = out + ": output directory is in use by another run (pid " + std::to_string(pid) + ", lock ";
  EXPECT_EQ(g.rc, 2) << g.out;
  EXPECT_NE(g.out.find(msg), std::string::npos) << g.out;
  EXPECT_EQ(m.rc, 2) << m.out;
  EXPECT_NE(m.out.find(msg), std::string::npos) << m.out;
  // nothing of either refused run, and the running one had published nothing
  for (const auto& e : fs::directory_iterator(out)) {
    const std::string n = e.path().filename().string();
    EXPECT_TRUE(n == ".lock" || n == ".staging-" + std::to_string(pid)) << n;
  }
  // once the holder is gone the directory is free again
  EXPECT_EQ(grav("--quiet --scene " + scene).rc, 0);
}

// ---- 4. disk full under the staging directory -----------------------------------------------

namespace {
/// Run `tool` once into `out` (complete), then again with `sets` after `fill` ran: exit 4, the
/// first run kept byte for byte, the message names the staging directory.
void expect_disk_full_keeps_previous_run(const std::string& exe, const std::string& scene, const std::string& out,
                                         const std::string& sets, const std::function<std::string()>& fill) {
  ASSERT_EQ(run(exe, "--quiet --scene " + scene).rc, 0);
  const auto before = contents(out);
  const std::string prefix = fill();
  const Result r = run("true; " + prefix, std::string(exe) + " --scene " + scene + " " + sets);
  EXPECT_EQ(r.rc, 4) << r.out;
  EXPECT_NE(r.out.find("the run did not complete; " + out + " is unchanged and this run's partial output is in " + out +
                       "/.staging-"),
            std::string::npos)
      << r.out;
  EXPECT_EQ(contents(out), before);
}
}  // namespace

TEST(RunSafety, FileSizeLimitDuringARunKeepsThePreviousRun) {
  // RLIMIT_FSIZE (ulimit -f, in KB) makes a write fail like a full disk; SIGXFSZ ignored.
  const auto limit = [] { return std::string("trap '' XFSZ; ulimit -f 8;"); };
  testutil::TempDir d;
  const std::string out_m = d.file("m"), out_g = d.file("g");
  expect_disk_full_keeps_previous_run(MPM_FRAG_EXE, mpm_scene(d, out_m), out_m, "--set output.snapshot_interval=5e-5",
                                      limit);
  expect_disk_full_keeps_previous_run(SSDEM_GRAV_EXE, pile_scene(d, out_g), out_g,
                                      "--set output.snapshot_interval=5.0 --set initial.sphere_radius=0.5", limit);
}

TEST(RunSafety, FullTmpfsDuringARunKeepsThePreviousRun) {
  if (::geteuid() != 0) GTEST_SKIP() << "mounting a tmpfs needs root";
  testutil::TempDir d;
  const std::string mnt = d.file("mnt");
  fs::create_directories(mnt);
  if (std::system(("mount -t tmpfs -o size=4m tmpfs " + mnt + " 2>/dev/null").c_str()) != 0)
    GTEST_SKIP() << "mount -t tmpfs refused (no CAP_SYS_ADMIN in this container?)";
  struct Unmount {
    std::string m;
    ~Unmount() { (void)std::system(("umount " + m).c_str()); }
  } unmount{mnt};
  // fill the tmpfs up to 48 KB of free space after the first run
  const std::string filler = mnt + "/filler";
  auto fill = [&] {
    struct statvfs v {};
    ::statvfs(mnt.c_str(), &v);
    const long long free_b = static_cast<long long>(v.f_bavail) * static_cast<long long>(v.f_frsize);
    std::ofstream(filler, std::ios::binary | std::ios::app) << std::string(std::max(0LL, free_b - 48 * 1024), 'x');
    return std::string();
  };
  const std::string out_m = mnt + "/m", out_g = mnt + "/g";
  expect_disk_full_keeps_previous_run(MPM_FRAG_EXE, mpm_scene(d, out_m), out_m, "--set output.snapshot_interval=5e-5",
                                      fill);
  fs::remove(filler);
  expect_disk_full_keeps_previous_run(SSDEM_GRAV_EXE, pile_scene(d, out_g), out_g,
                                      "--set output.snapshot_interval=5.0 --set initial.sphere_radius=0.5", fill);
}
