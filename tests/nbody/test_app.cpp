/// @file test_app.cpp
/// ssdem-grav end to end: restart from a checkpoint is bit-identical to an uninterrupted run
/// (also after a SIGTERM that always lands mid-run), exit codes 2 (unresolvable dt) and 3
/// (runaway overlap, state saved), per-sphere fields (damage) carried from the input file to
/// snapshots, scene-driven physics selection (no tree / no neighbour list when not needed).
#include <gtest/gtest.h>

#include <sstream>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <thread>

#include "common/sphere_file.hpp"
#include "common/status.hpp"
#include "ssdem/generators.hpp"
#include "ssdem/io.hpp"
#include "ssdem/run.hpp"
#include "ssdem/scene_setup.hpp"
#include "app_support.hpp"

using namespace ssdem;
namespace fs = std::filesystem;

namespace {
using ssdem_test::CheckpointCopy;
using ssdem_test::kExe;
using ssdem_test::last_snapshot;
using ssdem_test::read_checkpoint_copy;
using ssdem_test::run_cmd;
using ssdem_test::tmpdir;
using ssdem_test::write_scene;

/// The staging directory a run that did not complete left in `dir` (the only one).
std::string only_staging(const std::string& dir) {
  std::string found;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.is_directory() && e.path().filename().string().rfind(".staging-", 0) == 0) {
      EXPECT_TRUE(found.empty()) << "more than one staging directory in " << dir;
      found = e.path().string();
    }
  return found;
}
}  // namespace

TEST(App, RestartFromCheckpointIsBitIdentical) {
  const std::string d = tmpdir("restart");
  const std::string scene = write_scene(d);
  ASSERT_EQ(run_cmd("--scene " + scene + " --set output.directory=\\\"" + d + "/full\\\""), 0);
  ASSERT_EQ(run_cmd("--scene " + scene + " --set output.directory=\\\"" + d + "/part\\\" --set time.end=13.0"), 0);
  ASSERT_EQ(run_cmd("--scene " + scene + " --set output.directory=\\\"" + d + "/part\\\" --restart " + d +
                    "/part/checkpoint.h5"),
            0);
  const auto a = last_snapshot(d + "/full"), b = last_snapshot(d + "/part");
  ASSERT_EQ(a.step, b.step);
  ASSERT_GT(a.step, 100);
  ASSERT_EQ(a.position, b.position);
  ASSERT_EQ(a.velocity, b.velocity);
  ASSERT_EQ(a.spin, b.spin);
  // the dissipated energy per sphere, and the energy error against the same E_0 (kept in the
  // checkpoint), continue bit-identically
  auto field = [](const common::SphereSet& set, const std::string& name) {
    for (const auto& f : set.fields)
      if (f.name == name) return f.values;
    return std::vector<double>{};
  };
  const std::vector<double> da = field(a, "dissipated");
  ASSERT_FALSE(da.empty());
  EXPECT_EQ(da, field(b, "dissipated"));
  EXPECT_GT(*std::max_element(da.begin(), da.end()), 0.0);
  auto last_value = [](const std::string& path, const std::string& column) {
    std::ifstream in(path);
    std::string line, last, header;
    while (std::getline(in, line)) {
      if (line.empty() || line[0] == '#') continue;
      if (header.empty()) header = line;
      else last = line;
    }
    auto split = [](const std::string& t) {
      std::vector<std::string> out;
      std::stringstream ss(t);
      for (std::string c; std::getline(ss, c, ',');) out.push_back(c);
      return out;
    };
    const auto h = split(header), v = split(last);
    const auto it = std::find(h.begin(), h.end(), column);
    return it == h.end() || v.size() != h.size() ? std::string("missing") : v[it - h.begin()];
  };
  EXPECT_NE(last_value(d + "/full/series.csv", "energy_error_J"), "missing");
  EXPECT_EQ(last_value(d + "/full/series.csv", "energy_error_J"), last_value(d + "/part/series.csv", "energy_error_J"));
  EXPECT_EQ(last_value(d + "/full/series.csv", "dissipated_J"), last_value(d + "/part/series.csv", "dissipated_J"));
  EXPECT_GT(read_checkpoint(d + "/part/checkpoint.h5").history.size(), 100u);
  // the series file was continued, not restarted
  std::ifstream f(d + "/part/series.csv");
  std::string line, last;
  int rows = 0;
  while (std::getline(f, line)) {
    ++rows;
    last = line;
  }
  EXPECT_GT(rows, 3);
  fs::remove_all(d);
}

TEST(App, SigtermWritesCheckpointAndRestartMatches) {
  // The child runs to t = 1e7 s (~6e7 steps, hours), so the signal always lands mid-run: exit 0
  // is a failure. It is signalled once its series has 10 rows after t = 0 (step >= 300: contacts
  // with history exist): the progress marker is the row count of series.csv or, where the run
  // keeps its rows in series.csv.partial until it stops, of that file. The uninterrupted
  // reference and the restart then both run to the checkpoint's time + 30 s (~200 more steps)
  // and must agree bit for bit.
  const std::string d = tmpdir("sigterm");
  const std::string scene = write_scene(d);
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    prctl(PR_SET_PDEATHSIG, SIGKILL);  // never outlive the test (the run would take hours)
    setenv("OMP_NUM_THREADS", "1", 1);
    if (!std::freopen("/dev/null", "w", stdout) || !std::freopen("/dev/null", "w", stderr))
      _exit(98);
    const std::string od = "output.directory=\"" + d + "/part\"";
    execl(kExe.c_str(), kExe.c_str(), "--quiet", "--scene", scene.c_str(), "--set", od.c_str(),
          "--set", "time.end=1e7", static_cast<char*>(nullptr));
    _exit(99);
  }
  auto rows = [&]() {
    int best = 0;
    // the run writes into its staging directory until it completes
    const std::string st = d + "/part/.staging-" + std::to_string(pid);
    for (const char* name : {"/series.csv", "/series.csv.partial"}) {
      std::ifstream f(st + name);
      std::string l;
      int n = 0;
      while (std::getline(f, l)) ++n;
      best = std::max(best, n);
    }
    return best;
  };
  const auto t0 = std::chrono::steady_clock::now();
  bool marker = false;
  int status = 0;
  while (!marker && std::chrono::steady_clock::now() - t0 < std::chrono::seconds(20)) {
    marker = rows() >= 12;  // header + t = 0 + 10 rows
    if (!marker) {
      if (waitpid(pid, &status, WNOHANG) == pid) FAIL() << "the run ended before it was signalled";
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
  }
  if (!marker) {
    kill(pid, SIGKILL);
    waitpid(pid, &status, 0);
    FAIL() << "no progress marker (10 series rows) within 20 s";
  }
  kill(pid, SIGTERM);
  waitpid(pid, &status, 0);
  ASSERT_TRUE(WIFEXITED(status));
  ASSERT_EQ(WEXITSTATUS(status), 128 + SIGTERM) << "the signal must land mid-run";
  // the interrupted run's checkpoint is in its staging directory (part/ holds no run yet)
  const std::string ckpt = d + "/part/.staging-" + std::to_string(pid) + "/checkpoint.h5";
  ASSERT_TRUE(fs::exists(ckpt));
  EXPECT_FALSE(fs::exists(d + "/part/checkpoint.h5"));
  const SimState st = read_checkpoint(ckpt);
  EXPECT_GE(st.step, 300);
  EXPECT_GT(st.history.size(), st.sp.size());  // contact history really was carried
  char tend[64];
  std::snprintf(tend, sizeof tend, "%.17g", st.time + 30.0);
  const std::string args = "--scene " + scene + " --set time.end=" + tend + " --set output.directory=";
  ASSERT_EQ(run_cmd(args + "\\\"" + d + "/full\\\""), 0);
  ASSERT_EQ(run_cmd(args + "\\\"" + d + "/part\\\" --restart " + ckpt), 0);
  const auto a = last_snapshot(d + "/full"), b = last_snapshot(d + "/part");
  std::printf("SIGTERM at step %lld (t = %.1f s), both runs end at step %lld\n",
              static_cast<long long>(st.step), st.time, static_cast<long long>(a.step));
  ASSERT_EQ(a.step, b.step);
  ASSERT_GT(a.step, st.step + 100);
  ASSERT_EQ(a.position, b.position);
  ASSERT_EQ(a.velocity, b.velocity);
  ASSERT_EQ(a.spin, b.spin);
  fs::remove_all(d);
}

// A checkpoint written while gravity.group was part of the run identity (before 2026-12-06, with
// the old default 64) matches a run that leaves it out; every other key still counts.
TEST(App, CheckpointIdentityLeavesOutTheKeysARestartMayChange) {
  const common::RunIdentity old = detail::checkpoint_identity(
      "gravity.group = 64\ngravity.theta = 0.25\noutput.directory = \"o\"\nrun.sort_every = 4\ntime.end = 3.0\n");
  ASSERT_EQ(old.parts.size(), 1u);
  EXPECT_EQ(old.parts.at("gravity.theta"), "0.25");
}

// A checkpoint that recorded gravity.group in its identity (as before 2026-12-06, with the old
// default 64) continues under a run with the new default, with a warning naming both values;
// with the recorded value set again it continues silently; another theta is still refused.
TEST(App, RestartFromACheckpointThatRecordedTheGroupContinues) {
  const std::string d = tmpdir("group");
  const std::string scene = write_scene(d);
  ASSERT_EQ(run_cmd("--scene " + scene + " --set output.directory=\\\"" + d + "/part\\\" --set time.end=13.0"), 0);
  const CheckpointCopy ck = read_checkpoint_copy(d + "/part/checkpoint.h5");
  ASSERT_FALSE(ck.identity.empty());
  ASSERT_EQ(ck.identity.find("gravity.group"), std::string::npos);
  const std::string with_group = ck.identity + "gravity.group = 64\n";
  ck.write(d + "/old.h5", common::Provenance{"ssdem-grav", "", "", "", ""}, &with_group);
  auto restart = [&](const std::string& sets, const std::string& out) {
    const std::string log = d + "/" + out + ".log";
    const std::string cmd = "OMP_NUM_THREADS=1 " + kExe + " --quiet --scene " + scene + " --set output.directory=\\\"" +
                            d + "/" + out + "\\\" --set time.end=14.0" + sets + " --restart " + d + "/old.h5 > " + log +
                            " 2>&1";
    const int rc = std::system(cmd.c_str());
    std::ifstream in(log);
    std::stringstream text;
    text << in.rdbuf();
    return std::make_pair(WIFEXITED(rc) ? WEXITSTATUS(rc) : -1, text.str());
  };
  const auto [rc, out] = restart("", "a");
  EXPECT_EQ(rc, 0) << out;
  EXPECT_NE(out.find("ran with gravity.group = 64, this run uses 256"), std::string::npos) << out;
  const auto [rc64, out64] = restart(" --set gravity.group=64", "b");
  EXPECT_EQ(rc64, 0) << out64;
  EXPECT_EQ(out64.find("gravity.group"), std::string::npos) << out64;
  const auto [rct, outt] = restart(" --set gravity.theta=0.5", "c");
  EXPECT_EQ(rct, 2) << outt;
  EXPECT_NE(outt.find("they differ in gravity.theta: this run 0.5, checkpoint 0.25"), std::string::npos) << outt;
  fs::remove_all(d);
}

TEST(App, RefusesUnresolvableDtWithExit2) {
  const std::string d = tmpdir("dt");
  const std::string scene = write_scene(d);
  // k_n 100x stiffer than the rule at the dt the rule would give: 3 steps per contact
  EXPECT_EQ(run_cmd("--scene " + scene + " --set output.directory=\\\"" + d + "/o\\\" --set time.dt=0.07 --set contact.normal.kn=1e6"), 2);
  fs::remove_all(d);
}

TEST(App, RunawayOverlapStopsWithExit3AndSavesState) {
  const std::string d = tmpdir("overlap");
  // two spheres, far too soft for a 50 m/s impact
  Spheres sp;
  sp.push(0, Vec3(-1.5, 0, 0), Vec3(25, 0, 0), Vec3::Zero(), 1000.0, 1.0);
  sp.push(1, Vec3(1.5, 0, 0), Vec3(-25, 0, 0), Vec3::Zero(), 1000.0, 1.0);
  write_snapshot(d + "/in.h5", sp, 0.0, 0, common::Provenance{"test", "", "", "", ""});
  std::ofstream(d + "/s.toml") << "[time]\nend = 1.0\n[initial]\nsource = \"file\"\nfile = \"" << d
                               << "/in.h5\"\n[gravity]\nself = false\n[contact]\nnormal.kn = 1e3\n"
                               << "[output]\ndirectory = \"" << d << "/o\"\n";
  EXPECT_EQ(run_cmd("--scene " + d + "/s.toml"), 3);
  // the failed run's last good state is in its staging directory (o/ keeps the previous run)
  const std::string failed = only_staging(d + "/o") + "/failed_state.h5";
  ASSERT_TRUE(fs::exists(failed));
  EXPECT_FALSE(fs::exists(d + "/o/failed_state.h5"));
  const SimState st = read_checkpoint(failed);
  EXPECT_EQ(st.sp.size(), 2u);
  const double gap = (st.sp.x[1] - st.sp.x[0]).norm() - 2.0;
  EXPECT_GT(gap, -1.0);  // the saved state is a good one (overlap below the radius)
  fs::remove_all(d);
}

TEST(App, DamageCarriedFromInputFileToSnapshots) {
  const std::string d = tmpdir("damage");
  Spheres sp = lattice_pile(4.0, 1.0, 2000.0, 0.05, 2);
  common::Field dmg{"damage", "1", 1, {}, "Tonge-Ramesh damage"};
  for (std::size_t i = 0; i < sp.size(); ++i) dmg.values.push_back(0.01 * static_cast<double>(i % 100));
  sp.carried.push_back(dmg);
  write_snapshot(d + "/in.h5", sp, 0.0, 0, common::Provenance{"test", "", "", "", ""});
  std::ofstream(d + "/s.toml") << "[time]\nend = 5.0\n[initial]\nsource = \"file\"\nfile = \"" << d
                               << "/in.h5\"\n[contact]\npreset = \"gravel\"\n[output]\ndirectory = \"" << d
                               << "/o\"\ntimes = [2.0]\n";
  ASSERT_EQ(run_cmd("--scene " + d + "/s.toml"), 0);
  const auto out = last_snapshot(d + "/o");
  ASSERT_EQ(out.id, sp.id);
  const common::Field* f = out.field("damage");
  ASSERT_NE(f, nullptr);
  EXPECT_EQ(f->values, dmg.values);
  int nsnap = 0;
  for (const auto& e : fs::directory_iterator(d + "/o"))
    if (e.path().extension() == ".h5" && e.path().filename().string().rfind("snap_", 0) == 0) ++nsnap;
  EXPECT_EQ(nsnap, 3);  // t = 0, t = 2 (output.times), end
  fs::remove_all(d);
}

TEST(Scene, PhysicsSelectionBuildsOnlyWhatIsNeeded) {
  const common::Schema schema = ssdem_schema();
  auto make = [&](const std::string& extra) {
    const common::Scene sc = common::Scene::parse(
        schema, std::string("[time]\nend = 1.0\ndt = 0.01\n[initial]\nbody_radius = 4.0\n") + extra, "t");
    Spheres sp = initial_spheres(sc);
    return std::make_unique<Simulation>(sp, sim_config(sc, sp));
  };
  auto grav_only = make("[contact]\nenabled = false\n");
  EXPECT_TRUE(grav_only->has_tree());
  EXPECT_FALSE(grav_only->has_contacts());
  auto gran_only = make("[gravity]\nself = false\nuniform = [0.0, 0.0, -9.81]\n[contact]\nnormal.kn = 1e5\n");
  EXPECT_FALSE(gran_only->has_tree());
  EXPECT_TRUE(gran_only->has_contacts());
  EXPECT_EQ(gran_only->contact_system()->params().parts, 31u & 15u);  // default parts: all on
  auto normal_only = make("[gravity]\nself = false\n[contact]\nnormal.kn = 1e5\nparts = \"normal\"\n");
  EXPECT_EQ(normal_only->contact_system()->params().parts, 0u);
  EXPECT_THROW(make("[contact]\nparts = \"normal,hertz\"\n"), common::InputError);
}
