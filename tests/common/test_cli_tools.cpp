/// @file test_cli_tools.cpp
/// The command-line contract as a user meets it, on the real executables (ssdem-grav, mpm-frag):
/// exit code 2 and a message naming the file and dataset for malformed sphere input,
/// --version / --help-params / --print-scene, and time-series CSVs that a failed rerun never
/// destroys (a run writes into <dir>/.staging-<pid>, rows to <series>.partial renamed into place
/// when the run ends, stops on a numerical failure or on a signal, and publishes into <dir> only
/// when it completes; a --restart continues the series, also after a crash). Renamed keys:
/// test_cli_aliases.cpp.
#include <gtest/gtest.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cctype>
#include <chrono>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <regex>
#include <sstream>
#include <thread>

#include "common/h5.hpp"
#include "common/sphere_file.hpp"
#include "test_util.hpp"
#include "tool_runner.hpp"

namespace fs = std::filesystem;
using namespace common;

namespace {

using Result = testutil::ToolResult;
Result run(const std::string& exe, const std::string& args) { return testutil::run_tool(exe, args); }
Result grav(const std::string& args) { return run(SSDEM_GRAV_EXE, args); }
Result mpm(const std::string& args) { return run(MPM_FRAG_EXE, args); }

std::string slurp(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(f), {});
}
std::vector<std::string> lines_of(const std::string& path) {
  std::vector<std::string> v;
  std::ifstream f(path);
  for (std::string l; std::getline(f, l);) v.push_back(l);
  return v;
}
/// The staging directory a run that did not complete names in its log ("... partial output is in <dir>").
std::string staging_in_log(const std::string& out) {
  std::smatch m;
  return std::regex_search(out, m, std::regex("partial output is in (\\S+)")) ? m[1].str() : std::string();
}
/// A series row without its last column (wall_s, the only one that differs between runs).
std::string without_wall(const std::string& row) { return row.substr(0, row.rfind(',')); }

/// A small self-gravitating pile for ssdem-grav (19 spheres, dt 0.27 s, ~4 steps per second).
std::string pile_scene(const testutil::TempDir& d, const std::string& out_dir, const std::string& extra = "") {
  const std::string p = d.file("pile.toml");
  std::ofstream(p) << "[time]\nend = 30.0\n[initial]\nsource = \"lattice_pile\"\nbody_radius = 4.0\n"
                      "sphere_radius = 1.0\ndensity = 2000.0\nangular_velocity = [0.0, 0.0, 2e-4]\n"
                      "[gravity]\nevery = 3\n[contact]\npreset = \"gravel\"\n[output]\ndirectory = \""
                   << out_dir << "\"\nseries_every = 30\ncheckpoint_wall = 0.0\nprogress_interval = 100.0\n"
                   << extra;
  return p;
}

/// A scene reading `spheres` as the initial condition.
std::string file_scene(const testutil::TempDir& d, const std::string& spheres) {
  const std::string p = d.file("from_file.toml");
  std::ofstream(p) << "[time]\nend = 1.0\n[initial]\nsource = \"file\"\nfile = \"" << spheres
                   << "\"\n[gravity]\nself = false\n[contact]\nnormal.kn = 1e3\n[output]\ndirectory = \""
                   << d.file("out") << "\"\n";
  return p;
}

/// Two spheres (r = 1 m, 1000 kg) `gap` apart on the x axis, approaching at `speed` m/s.
SphereSet two_spheres(double gap, double speed) {
  SphereSet s;
  s.id = {0, 1};
  s.position = {-1.0 - 0.5 * gap, 0, 0, 1.0 + 0.5 * gap, 0, 0};
  s.velocity = {0.5 * speed, 0, 0, -0.5 * speed, 0, 0};
  s.spin.assign(6, 0.0);
  s.mass = {1000.0, 1000.0};
  s.radius = {1.0, 1.0};
  return s;
}

/// Checkpoint time and step (the checkpoint is a sphere set with extra groups).
std::pair<double, std::int64_t> checkpoint_time(const std::string& path) {
  const SphereSet s = read_sphere_set(path);
  return {s.time, s.step};
}

}  // namespace

// ---- malformed input through the tool: exit 2, message names the file and the dataset ------

TEST(CliTools, SsdemGravRejectsMalformedSphereInputWithExit2) {
  struct Case {
    const char* name;
    std::function<void(hid_t)> edit;
    const char* dataset;  // must appear in the message
  };
  const std::vector<Case> cases = {
      {"NaN mass", [](hid_t f) {
         h5::Handle ds(H5Dopen2(f, "/spheres/mass", H5P_DEFAULT));
         std::vector<double> m(10);
         H5Dread(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, m.data());
         m[4] = std::numeric_limits<double>::quiet_NaN();
         H5Dwrite(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, m.data());
       }, "/spheres/mass: non-finite value (NaN or Inf) at row 4"},
      {"position N x 2", [](hid_t f) {
         H5Ldelete(f, "/spheres/position", H5P_DEFAULT);
         std::vector<double> x(20, 0.0);
         h5::write_dataset(f, "/spheres/position", x.data(), 10, 2, "m");
       }, "/spheres/position: wrong shape (10, 2), expected (10, 3)"},
      {"int64 id", [](hid_t f) {
         H5Ldelete(f, "/spheres/id", H5P_DEFAULT);
         std::vector<std::int64_t> id(10, 1);
         h5::write_dataset(f, "/spheres/id", id.data(), 10, 1, "1");
       }, "/spheres/id: wrong dtype: expected uint64"},
      {"newer version", [](hid_t f) {
         H5Adelete(f, "format_version");
         h5::write_attr(f, "format_version", std::int64_t{7});
       }, "/format_version: version 7 is newer"},
      {"older version", [](hid_t f) {
         H5Adelete(f, "format_version");
         h5::write_attr(f, "format_version", std::int64_t{0});
       }, "/format_version: version 0 is older than the oldest this tool reads (1)"},
  };
  for (const auto& c : cases) {
    testutil::TempDir d;
    const std::string path = d.file("bad_spheres.h5");
    write_sphere_set(path, testutil::sample_spheres(10), testutil::sample_provenance());
    {
      h5::quiet_errors();
      h5::Handle f(H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT));
      c.edit(f);
    }
    const Result r = grav("--scene " + file_scene(d, path));
    EXPECT_EQ(r.rc, 2) << c.name << ": " << r.out;
    EXPECT_NE(r.out.find(path + ": " + c.dataset), std::string::npos) << c.name << ": " << r.out;
    EXPECT_FALSE(fs::exists(d.file("out/series.csv"))) << c.name;
  }
}

TEST(CliTools, SsdemGravRejectsParticleFileTruncatedAndTextWithExit2) {
  testutil::TempDir d;
  const std::string particles = d.file("snapshot.h5");
  write_particle_snapshot(particles, testutil::sample_particles(50), testutil::sample_provenance());
  Result r = grav("--scene " + file_scene(d, particles));
  EXPECT_EQ(r.rc, 2) << r.out;
  EXPECT_NE(r.out.find(particles + ": /format: unknown format 'mpm-frag.particles', expected 'ssdem.spheres'"),
            std::string::npos)
      << r.out;

  const std::string good = d.file("good.h5");
  write_sphere_set(good, testutil::sample_spheres(2000), testutil::sample_provenance());
  const std::string trunc = d.file("trunc.h5");
  fs::copy_file(good, trunc);
  fs::resize_file(trunc, fs::file_size(good) * 2 / 3);
  r = grav("--scene " + file_scene(d, trunc));
  EXPECT_EQ(r.rc, 2) << r.out;
  EXPECT_NE(r.out.find(trunc + ": "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("truncated"), std::string::npos) << r.out;

  const std::string text = d.file("text.h5");
  std::ofstream(text) << "not hdf5\n";
  r = grav("--scene " + file_scene(d, text));
  EXPECT_EQ(r.rc, 2) << r.out;
  EXPECT_NE(r.out.find(text + ": not an HDF5 file"), std::string::npos) << r.out;

  r = grav("--scene " + file_scene(d, d.file("absent.h5")));
  EXPECT_EQ(r.rc, 2) << r.out;
  EXPECT_NE(r.out.find(d.file("absent.h5") + ": file does not exist"), std::string::npos) << r.out;

  // The same scene with a sound file runs.
  write_sphere_set(good, two_spheres(20.0, -1.0), testutil::sample_provenance());
  r = grav("--scene " + file_scene(d, good));
  EXPECT_EQ(r.rc, 0) << r.out;
}

// ---- --version, --help-params, --print-scene ------------------------------------------------

TEST(CliTools, VersionPrintsVersionAndGitSha) {
  // With a git checkout the SHA is 12 hex digits (+dirty); "unknown" only outside one.
  const bool git = fs::exists(fs::path(SUITE_SOURCE_DIR) / ".git");
  const std::string sha = git ? "[0-9a-f]{12}(\\+dirty)?" : "unknown";
  std::string grav_sha;
  for (const auto& [tool, exe] : {std::pair<std::string, std::string>{"ssdem-grav", SSDEM_GRAV_EXE},
                                  {"mpm-frag", MPM_FRAG_EXE}}) {
    const Result r = run(exe, "--version");
    EXPECT_EQ(r.rc, 0) << tool;
    std::smatch m;
    EXPECT_TRUE(std::regex_match(r.out, m, std::regex(tool + " " SUITE_VERSION " \\(git (" + sha + ")\\)\n")))
        << tool << ": '" << r.out << "'";
    if (tool == "ssdem-grav" && m.size() > 1) grav_sha = m[1];
  }
  // The SHA printed is the one the tool records in its files.
  testutil::TempDir d;
  ASSERT_EQ(grav("--quiet --scene " + pile_scene(d, d.file("o")) + " --set time.end=1.0").rc, 0);
  h5::Handle f = h5::open_file_read(d.file("o/snap_000000000.h5"));
  const Provenance p = h5::read_provenance(f, "");
  EXPECT_EQ(p.git_sha, grav_sha);
  EXPECT_EQ(p.tool, "ssdem-grav");
  EXPECT_EQ(p.version, SUITE_VERSION);
}

TEST(CliTools, HelpParamsListsKeysWithTypeDefaultUnitAndRange) {
  const Result r = grav("--help-params");
  ASSERT_EQ(r.rc, 0);
  // key (type) default [unit], then its range or choices, then the help text
  EXPECT_NE(r.out.find("time.end  (real)  REQUIRED  [s]\n    range: (0, inf]\n"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("time.min_steps_per_contact  (real)  default 10  [1]\n    range: [1, 1000000]\n"),
            std::string::npos);
  // physical bounds that keep every derived quantity finite (common/finite.hpp)
  EXPECT_NE(r.out.find("initial.density  (real)  default 2000  [kg/m^3]\n    range: (0, 100000]\n"), std::string::npos);
  EXPECT_NE(r.out.find("initial.source  (choice)  default \"lattice_pile\"\n    one of: file ss lattice_pile "
                       "random_pile two_bodies\n"),
            std::string::npos);
  EXPECT_NE(r.out.find("output.series_every  (integer)  default 100  [1]\n"), std::string::npos);
  const Result m = mpm("--help-params");
  ASSERT_EQ(m.rc, 0);
  EXPECT_NE(m.out.find("output.series_every  (integer)  default 10  [1]\n    range: [1, 1000000000]\n"),
            std::string::npos)
      << m.out;
}

TEST(CliTools, PrintSceneIsAResolvedSceneThatReadsBack) {
  testutil::TempDir d;
  const std::string scene = pile_scene(d, d.file("o"));
  const Result r = grav("--scene " + scene + " --set time.end=7.5 --set contact.damping.en=0.25 --print-scene");
  ASSERT_EQ(r.rc, 0) << r.out;
  // Resolved: the overrides, the scene's values and the schema defaults are all there.
  EXPECT_NE(r.out.find("end = 7.5"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("en = 0.25"), std::string::npos);
  EXPECT_NE(r.out.find("body_radius = 4.0"), std::string::npos);
  EXPECT_NE(r.out.find("steps_per_contact = 30.0"), std::string::npos);  // a default
  EXPECT_EQ(r.out.find("output.directory"), std::string::npos);          // nested tables, not dotted keys
  // Read back: the printed scene is a fixed point and runs as it stands.
  const std::string printed = d.file("printed.toml");
  std::ofstream(printed) << r.out;
  const Result again = grav("--scene " + printed + " --print-scene");
  ASSERT_EQ(again.rc, 0) << again.out;
  EXPECT_EQ(again.out, r.out);
  ASSERT_EQ(grav("--quiet --scene " + printed).rc, 0);
  const auto [t, step] = checkpoint_time(d.file("o/checkpoint.h5"));
  EXPECT_EQ(step % 3, 0);                 // gravity.every = 3 from the scene
  EXPECT_NEAR(t, 7.5, 3 * 0.27);          // time.end = 7.5 from the override
}

// ---- time series: a failed rerun keeps the earlier series; restart continues it -------------

TEST(CliTools, SsdemGravSeriesSurvivesFailedRerun) {
  testutil::TempDir d;
  const std::string out = d.file("o");
  const std::string scene = pile_scene(d, out);
  ASSERT_EQ(grav("--quiet --scene " + scene).rc, 0);
  const std::string series = out + "/series.csv";
  const std::string before = slurp(series);
  ASSERT_GE(lines_of(series).size(), 5u);
  EXPECT_FALSE(fs::exists(series + ".partial"));

  // Rerun that fails with exit 4 when it publishes its output: the t = 0 snapshot cannot be
  // renamed into place (a directory has its name); nothing of it reaches the directory.
  fs::remove(out + "/snap_000000000.h5");
  fs::create_directory(out + "/snap_000000000.h5");
  const Result r4 = grav("--scene " + scene);
  EXPECT_EQ(r4.rc, 4) << r4.out;
  EXPECT_EQ(slurp(series), before);
  EXPECT_FALSE(fs::exists(series + ".partial"));
  // the failed run's own series is kept aside, in its staging directory
  const std::string staged = staging_in_log(r4.out);
  ASSERT_FALSE(staged.empty()) << r4.out;
  EXPECT_EQ(lines_of(staged + "/series.csv").size(), lines_of(series).size());

  // Rerun that fails with exit 2 (unresolvable dt).
  EXPECT_EQ(grav("--quiet --scene " + scene + " --set time.dt=0.07 --set contact.normal.kn=1e6").rc, 2);
  EXPECT_EQ(slurp(series), before);
}

TEST(CliTools, SsdemGravExit3CommitsTheSeriesUpToTheFailure) {
  testutil::TempDir d;
  // Two spheres 20 m apart closing at 50 m/s, far too soft for it: runaway overlap, exit 3.
  write_sphere_set(d.file("in.h5"), two_spheres(20.0, 50.0), testutil::sample_provenance());
  const std::string scene = file_scene(d, d.file("in.h5"));
  fs::create_directories(d.file("out"));
  std::ofstream(d.file("out/series.csv")) << "step,time_s\n0,0\n";  // an earlier run's
  const Result r = grav("--scene " + scene + " --set time.end=3.0 --set output.series_every=1");
  ASSERT_EQ(r.rc, 3) << r.out;
  EXPECT_NE(r.out.find("last good state (step "), std::string::npos) << r.out;
  // The earlier run's series stays; the failed run's series, up to the failure, is committed
  // in its staging directory next to the saved state, which the log names.
  EXPECT_EQ(slurp(d.file("out/series.csv")), "step,time_s\n0,0\n");
  const std::string staged = staging_in_log(r.out);
  ASSERT_FALSE(staged.empty()) << r.out;
  EXPECT_FALSE(fs::exists(staged + "/series.csv.partial"));
  const auto rows = lines_of(staged + "/series.csv");
  ASSERT_GE(rows.size(), 4u) << slurp(staged + "/series.csv");
  EXPECT_EQ(rows[0].rfind("step,time_s,kinetic_J,", 0), 0u);
  // one row per step from 0 (series_every = 1, gravity off), kinetic energy 2 * 1000 * 25^2 / 2
  for (std::size_t i = 1; i < rows.size(); ++i) EXPECT_EQ(std::atoll(rows[i].c_str()), static_cast<long long>(i - 1));
  EXPECT_EQ(rows[1].rfind("0,0,625000,", 0), 0u) << rows[1];
  // the last row is at or after the saved last good state, and before the failing step
  EXPECT_FALSE(fs::exists(d.file("out/failed_state.h5")));
  const SphereSet good = read_sphere_set(staged + "/failed_state.h5");
  EXPECT_GE(std::atoll(rows.back().c_str()), good.step);
}

namespace {
/// Start ssdem-grav in the background on `scene` (stdout/stderr discarded); it dies with us.
pid_t spawn_grav(const std::string& scene, const std::vector<std::string>& sets) {
  return testutil::spawn_tool(SSDEM_GRAV_EXE, scene, sets);
}
using testutil::wait_for;
/// The series of an uninterrupted run to `t_end` must equal `got` row by row (wall_s aside).
void expect_same_series(const testutil::TempDir& d, const std::string& scene, double t_end,
                        const std::vector<std::string>& got) {
  std::ostringstream te;
  te.precision(17);
  te << "time.end=" << t_end;
  ASSERT_EQ(grav("--quiet --scene " + scene + " --set output.directory=\\\"" + d.file("full") + "\\\" --set " + te.str()).rc,
            0);
  const auto want = lines_of(d.file("full/series.csv"));
  ASSERT_EQ(got.size(), want.size());
  ASSERT_GE(want.size(), 5u);
  for (std::size_t i = 0; i < want.size(); ++i) EXPECT_EQ(without_wall(got[i]), without_wall(want[i])) << "row " << i;
}
}  // namespace

TEST(CliTools, SsdemGravSigtermCommitsSeriesAndRestartContinuesIt) {
  testutil::TempDir d;
  const std::string out = d.file("part");
  const std::string scene = pile_scene(d, out);
  // Runs for hours unless signalled; signalled once it has 6 rows in its partial series.
  const pid_t pid = spawn_grav(scene, {"time.end=1e7"});
  ASSERT_GT(pid, 0);
  // The run writes into its staging directory <out>/.staging-<pid> until it completes.
  const std::string staged = out + "/.staging-" + std::to_string(pid);
  const bool started = wait_for([&] { return lines_of(staged + "/series.csv.partial").size() >= 6; });
  kill(pid, SIGTERM);
  int status = 0;
  waitpid(pid, &status, 0);
  ASSERT_TRUE(started);
  ASSERT_TRUE(WIFEXITED(status));
  ASSERT_EQ(WEXITSTATUS(status), 128 + SIGTERM);
  EXPECT_FALSE(fs::exists(staged + "/series.csv.partial"));
  EXPECT_FALSE(fs::exists(out + "/series.csv"));  // nothing published
  const auto interrupted = lines_of(staged + "/series.csv");
  ASSERT_GE(interrupted.size(), 6u);
  const auto [t_ck, s_ck] = checkpoint_time(staged + "/checkpoint.h5");
  EXPECT_GE(s_ck, std::atoll(interrupted.back().c_str()));

  const double t_end = t_ck + 20.0;
  std::ostringstream te;
  te.precision(17);
  te << "time.end=" << t_end;
  ASSERT_EQ(grav("--quiet --scene " + scene + " --set " + te.str() + " --restart " + staged + "/checkpoint.h5").rc, 0);
  EXPECT_FALSE(fs::exists(staged));  // published
  const auto continued = lines_of(out + "/series.csv");
  EXPECT_GT(continued.size(), interrupted.size());
  for (std::size_t i = 0; i < interrupted.size(); ++i) EXPECT_EQ(continued[i], interrupted[i]) << "row " << i;
  expect_same_series(d, scene, t_end, continued);
}

TEST(CliTools, SsdemGravRestartAfterCrashContinuesThePartialSeries) {
  testutil::TempDir d;
  const std::string out = d.file("part");
  const std::string scene = pile_scene(d, out, "checkpoint_every = 60\n");
  // An earlier, unrelated series under the final name: the crashed run's rows must win.
  fs::create_directories(out);
  std::ofstream(out + "/series.csv") << "step,time_s\n0,0\n999999,1\n";
  const pid_t pid = spawn_grav(scene, {"time.end=1e7"});
  ASSERT_GT(pid, 0);
  const std::string staged = out + "/.staging-" + std::to_string(pid);
  const bool started = wait_for([&] {
    return fs::exists(staged + "/checkpoint.h5") && lines_of(staged + "/series.csv.partial").size() >= 8;
  });
  kill(pid, SIGKILL);  // no chance to commit anything
  int status = 0;
  waitpid(pid, &status, 0);
  ASSERT_TRUE(started);
  ASSERT_TRUE(WIFSIGNALED(status));
  EXPECT_EQ(slurp(out + "/series.csv"), "step,time_s\n0,0\n999999,1\n");  // untouched by the crash
  const auto [t_ck, s_ck] = checkpoint_time(staged + "/checkpoint.h5");
  ASSERT_GT(s_ck, 0);

  const double t_end = t_ck + 20.0;
  std::ostringstream te;
  te.precision(17);
  te << "time.end=" << t_end;
  ASSERT_EQ(grav("--quiet --scene " + scene + " --set " + te.str() + " --restart " + staged + "/checkpoint.h5").rc, 0);
  EXPECT_FALSE(fs::exists(out + "/series.csv.partial"));
  expect_same_series(d, scene, t_end, lines_of(out + "/series.csv"));
}

TEST(CliTools, MpmFragSeriesSurvivesFailedRerunAndExit3CommitsIt) {
  testutil::TempDir d;
  const std::string out = d.file("o");
  // An elastic sphere (r = 3 cm) moving at 20 m/s towards the edge of a 20 cm grid.
  const std::string scene = d.file("edge.toml");
  std::ofstream(scene) << "[grid]\ndomain_min = [0.0, 0.0, 0.0]\ndomain_max = [0.2, 0.1, 0.1]\ncell_size = 0.01\n"
                          "[time]\nend = 5e-4\n[output]\ndirectory = \""
                       << out << "\"\nprefix = \"edge\"\nseries_every = 5\nprogress_interval = 100.0\n"
                       << "[[material]]\nname = \"m\"\nmodel = \"elastic\"\ndensity = 1000.0\nbulk_modulus = 1e7\n"
                          "shear_modulus = 1e6\n[[body]]\nmaterial = \"m\"\nshape = \"sphere\"\n"
                          "center = [0.1, 0.05, 0.05]\nradius = 0.03\nvelocity = [20.0, 0.0, 0.0]\n";
  ASSERT_EQ(mpm("--quiet --scene " + scene).rc, 0);
  const std::string series = out + "/edge_series.csv";
  const std::string before = slurp(series);
  const auto rows = lines_of(series);
  ASSERT_GE(rows.size(), 3u);
  EXPECT_EQ(rows[0].rfind("step,time_s,dt_s,", 0), 0u);
  EXPECT_FALSE(fs::exists(series + ".partial"));

  // Rerun failing with exit 4 when it publishes: the t = 0 snapshot name is a directory.
  fs::remove(out + "/edge_000000.h5");
  fs::create_directory(out + "/edge_000000.h5");
  const Result r4 = mpm("--scene " + scene);
  EXPECT_EQ(r4.rc, 4) << r4.out;
  EXPECT_EQ(slurp(series), before);
  EXPECT_FALSE(fs::exists(series + ".partial"));
  ASSERT_FALSE(staging_in_log(r4.out).empty()) << r4.out;
  EXPECT_EQ(lines_of(staging_in_log(r4.out) + "/edge_series.csv").size(), rows.size());  // aside
  fs::remove(out + "/edge_000000.h5");

  // A run to t = 1 s leaves the grid (exit 3): the earlier series stays; the failed run's,
  // up to the failure, is committed in its staging directory.
  const Result r3 = mpm("--scene " + scene + " --set time.end=1.0");
  ASSERT_EQ(r3.rc, 3) << r3.out;
  EXPECT_EQ(slurp(series), before);
  const std::string staged = staging_in_log(r3.out);
  ASSERT_FALSE(staged.empty()) << r3.out;
  EXPECT_FALSE(fs::exists(staged + "/edge_series.csv.partial"));
  const auto failed = lines_of(staged + "/edge_series.csv");
  EXPECT_GT(failed.size(), rows.size());
  EXPECT_EQ(failed[0], rows[0]);
  EXPECT_GT(std::atof(failed.back().c_str() + failed.back().find(',') + 1), 5e-4);  // time past the first run's end
}
