/// @file test_mpm_restart.cpp
/// mpm-frag checkpoints and --restart on the real executable (a Tonge–Ramesh sphere hit by an
/// elastic impactor, artificial viscosity on, a third body leaving the grid through the outflow
/// edge, so that material state, the optional q array and the outflow record all travel):
///  - SIGTERM mid-run: exit 143 after a checkpoint in the staging directory; a previous complete
///    run in the directory stays byte for byte until the restarted run publishes;
///  - SIGKILL after a periodic checkpoint (output.checkpoint_every), restart on 2 threads;
///  - a completed run continued to a later time.end from its published checkpoint;
/// each ends with every snapshot, the outflow record and the series equal to an uninterrupted
/// run's (every dataset bit for bit; provenance aside). A checkpoint of another run (another
/// density) is refused with exit 2 naming the key. A checkpoint from before the Tonge–Ramesh cost
/// field (damage_substeps, StateField::work) existed restarts, bit-identically on one rank; one
/// without a physics field (damage) is refused naming it.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "common/particle_file.hpp"
#include "test_util.hpp"
#include "tool_runner.hpp"

namespace fs = std::filesystem;

namespace {

std::string slurp(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(f), {});
}
/// Every regular file directly in `dir` except the run lock, name -> content.
std::map<std::string, std::string> contents(const std::string& dir) {
  std::map<std::string, std::string> m;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.is_regular_file() && e.path().filename() != ".lock") m[e.path().filename().string()] = slurp(e.path().string());
  return m;
}
/// The published (not hidden) file names of a run directory, and its manifest as a run would write it.
std::set<std::string> visible_names(const std::string& dir) {
  std::set<std::string> n;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.is_regular_file() && e.path().filename().string()[0] != '.') n.insert(e.path().filename().string());
  return n;
}
std::string manifest_of(const std::string& dir) {
  std::string m;
  for (const auto& n : visible_names(dir)) m += n + "\n";
  return m;
}
std::string staging(const std::string& dir, pid_t pid) { return dir + "/.staging-" + std::to_string(pid); }

template <class T>
bool same_bits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}
/// Every dataset of two particle files bit for bit ("" if equal, else the first that differs).
std::string snapshot_difference(const std::string& a_path, const std::string& b_path) {
  const common::ParticleSnapshot a = common::read_particle_snapshot(a_path);
  const common::ParticleSnapshot b = common::read_particle_snapshot(b_path);
  if (a.time != b.time || a.step != b.step) return "time/step";
  if (!same_bits(a.id, b.id)) return "id";
  if (!same_bits(a.position, b.position)) return "position";
  if (!same_bits(a.velocity, b.velocity)) return "velocity";
  if (!same_bits(a.mass, b.mass)) return "mass";
  if (!same_bits(a.volume, b.volume)) return "volume";
  if (!same_bits(a.size, b.size)) return "size";
  if (!same_bits(a.material, b.material)) return "material";
  if (a.fields.size() != b.fields.size()) return "field count";
  for (std::size_t k = 0; k < a.fields.size(); ++k)
    if (a.fields[k].name != b.fields[k].name || !same_bits(a.fields[k].values, b.fields[k].values))
      return a.fields[k].name;
  return "";
}

/// `out` holds the same run as `ref`: every snapshot, the outflow record and the checkpoint's
/// particles bit for bit, the series byte for byte.
void expect_same_run(const std::string& ref, const std::string& out) {
  std::size_t h5 = 0;
  for (const auto& [name, _] : contents(ref)) {
    if (!name.ends_with(".h5")) continue;
    ++h5;
    ASSERT_TRUE(fs::exists(out + "/" + name)) << name;
    EXPECT_EQ(snapshot_difference(ref + "/" + name, out + "/" + name), "") << name;
  }
  EXPECT_GE(h5, 10u);  // 9 snapshots, outflow, checkpoint
  EXPECT_TRUE(fs::exists(ref + "/ck_outflow.h5"));
  EXPECT_EQ(slurp(out + "/ck_series.csv"), slurp(ref + "/ck_series.csv"));
}

/// The scene (tests/common/data/tiny_impact.toml); the tests set output.directory.
std::string scene_file(const testutil::TempDir&) { return std::string(SUITE_SOURCE_DIR) + "/tests/common/data/tiny_impact.toml"; }

class MpmRestart : public ::testing::Test {
 protected:
  /// The uninterrupted run (one thread), shared by the tests.
  static void SetUpTestSuite() {
    dir_ = new testutil::TempDir;
    scene_ = scene_file(*dir_);
    ref_ = dir_->file("ref");
    const testutil::ToolResult r = mpm("--quiet --scene " + scene_ + " --set output.directory=\"" + ref_ + "\"");
    ASSERT_EQ(r.rc, 0) << r.out;
  }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }
  static testutil::ToolResult mpm(const std::string& args) { return testutil::run_tool(MPM_FRAG_EXE, args); }
  static std::string dir_set(const std::string& out) { return "output.directory=\"" + out + "\""; }
  /// Start a run into `out`, wait until `file` (in its staging directory) exists, send `sig`.
  /// `restart`: the checkpoint it continues (then `file` is a path that must change, not appear).
  static pid_t interrupt(const std::string& out, const std::string& file, int sig, std::vector<std::string> sets,
                         int* status, const std::string& restart = "") {
    sets.push_back(dir_set(out));
    const auto mtime = [&](const std::string& p) {
      std::error_code ec;
      return fs::last_write_time(p, ec);
    };
    const auto before = mtime(file);
    const pid_t pid = testutil::spawn_tool(MPM_FRAG_EXE, scene_, sets,
                                           restart.empty() ? std::vector<std::string>{}
                                                           : std::vector<std::string>{"--restart", restart});
    const bool reached = testutil::wait_for([&] {
      return restart.empty() ? fs::exists(staging(out, pid) + "/" + file) : mtime(file) != before;
    });
    kill(pid, sig);
    waitpid(pid, status, 0);
    EXPECT_TRUE(reached) << file;
    return pid;
  }

  static testutil::TempDir* dir_;
  static std::string scene_, ref_;
};
testutil::TempDir* MpmRestart::dir_ = nullptr;
std::string MpmRestart::scene_, MpmRestart::ref_;

}  // namespace

TEST_F(MpmRestart, SigtermWritesACheckpointAndRestartIsBitIdenticalKeepingThePreviousRunUntilPublish) {
  testutil::TempDir d;
  const std::string out = d.file("o");
  // A previous complete run in the directory (a shorter one, with snapshots at other steps).
  ASSERT_EQ(mpm("--quiet --scene " + scene_ + " --set " + dir_set(out) + " --set time.end=5e-5 --set output.snapshot_interval=1.5e-5").rc, 0);
  const auto previous = contents(out);
  const auto reference = contents(ref_);
  std::string only_previous;  // a snapshot of the previous run that the new run does not write
  for (const auto& [name, _] : previous)
    if (name.ends_with(".h5") && !reference.contains(name)) only_previous = name;
  ASSERT_FALSE(only_previous.empty());
  // interrupted once its third snapshot (by name, from the uninterrupted run) is staged
  std::vector<std::string> snaps;
  for (const auto& [name, _] : reference)
    if (name.starts_with("ck_0") && name.ends_with(".h5")) snaps.push_back(name);
  ASSERT_GE(snaps.size(), 4u);
  int status = 0;
  const pid_t pid = interrupt(out, snaps[2], SIGTERM, {}, &status);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 128 + SIGTERM);
  const std::string ckpt = staging(out, pid) + "/ck_checkpoint.h5";
  ASSERT_TRUE(fs::exists(ckpt));
  EXPECT_EQ(contents(out), previous);
  // A restart killed (SIGKILL) after its own first periodic checkpoint: still nothing published.
  interrupt(out, ckpt, SIGKILL, {"output.checkpoint_every=5"}, &status, ckpt);
  EXPECT_TRUE(WIFSIGNALED(status));
  EXPECT_EQ(contents(out), previous);
  const testutil::ToolResult r = mpm("--quiet --scene " + scene_ + " --set " + dir_set(out) + " --restart " + ckpt);
  ASSERT_EQ(r.rc, 0) << r.out;
  expect_same_run(ref_, out);
  EXPECT_FALSE(fs::exists(staging(out, pid)));
  EXPECT_FALSE(fs::exists(out + "/" + only_previous)) << only_previous;  // the previous run's files are gone
}

TEST_F(MpmRestart, SigkillAfterAPeriodicCheckpointRestartsBitIdenticallyOnTwoThreads) {
  testutil::TempDir d;
  const std::string out = d.file("o");
  int status = 0;
  const pid_t pid = interrupt(out, "ck_checkpoint.h5", SIGKILL, {"output.checkpoint_every=40"}, &status);
  ASSERT_TRUE(WIFSIGNALED(status));
  const std::string ckpt = staging(out, pid) + "/ck_checkpoint.h5";
  {  // what a writer killed mid-file leaves beside the checkpoint (atomic_file.cpp's temporary name)
    std::ofstream junk(staging(out, pid) + "/.ck_000050.h5.tmp." + std::to_string(pid));
    junk << "half an HDF5 file";
  }
  const testutil::ToolResult r =
      mpm("--quiet --scene " + scene_ + " --set " + dir_set(out) + " --set run.threads=2 --restart " + ckpt);
  ASSERT_EQ(r.rc, 0) << r.out;
  expect_same_run(ref_, out);
  EXPECT_FALSE(fs::exists(staging(out, pid)));
  for (const auto& e : fs::directory_iterator(out))  // the killed writer's temporary is not published
    EXPECT_EQ(e.path().filename().string().find(".ck_"), std::string::npos) << e.path();
}

// A run killed while it publishes (between its renames; SUITE_FAULT_PUBLISH_KILL_AFTER) into a
// directory holding an earlier complete run: the restart from the checkpoint still in its staging
// directory completes the publish without deleting what the interrupted publish had moved (the
// earlier run's manifest lists the same names).
TEST_F(MpmRestart, PublishKilledMidwayIsCompletedByTheRestart) {
  testutil::TempDir d;
  const std::string out = d.file("o");
  ASSERT_EQ(mpm("--quiet --scene " + scene_ + " --set " + dir_set(out) + " --set material[1].density=1100.0").rc, 0);
  setenv("SUITE_FAULT_PUBLISH_KILL_AFTER", "2", 1);  // the two files of the first snapshot are moved
  const testutil::ToolResult k = mpm("--quiet --scene " + scene_ + " --set " + dir_set(out));
  unsetenv("SUITE_FAULT_PUBLISH_KILL_AFTER");
  ASSERT_NE(k.rc, 0) << k.out;
  std::string stage;
  for (const auto& e : fs::directory_iterator(out))
    if (e.path().filename().string().rfind(".staging-", 0) == 0) stage = e.path().string();
  ASSERT_FALSE(stage.empty());
  ASSERT_FALSE(fs::exists(stage + "/ck_000000.h5"));  // moved before the kill
  ASSERT_TRUE(fs::exists(stage + "/ck_checkpoint.h5"));
  const testutil::ToolResult r =
      mpm("--quiet --scene " + scene_ + " --set " + dir_set(out) + " --restart " + stage + "/ck_checkpoint.h5");
  ASSERT_EQ(r.rc, 0) << r.out;
  expect_same_run(ref_, out);
  EXPECT_FALSE(fs::exists(stage));
  EXPECT_FALSE(fs::exists(out + "/.publish-journal"));
  EXPECT_EQ(visible_names(out), visible_names(ref_));  // nothing of the earlier run is left
  EXPECT_EQ(slurp(out + "/.run-manifest"), manifest_of(ref_));
}

// Publishes killed twice in a row by fresh runs that do not continue each other (three snapshot
// intervals, so each run writes other names): the run that completes leaves exactly its own files,
// none of the two interrupted publishes' nor of the complete run before them.
TEST_F(MpmRestart, PublishesKilledTwiceThenAFreshRunLeavesOnlyItsFiles) {
  testutil::TempDir d;
  const std::string out = d.file("o"), solo = d.file("solo");
  const std::string tend = " --set time.end=1e-4";
  ASSERT_EQ(mpm("--quiet --scene " + scene_ + " --set " + dir_set(out) + tend + " --set output.snapshot_interval=1e-5").rc, 0);
  for (const char* k : {"3", "1"}) {  // the first moves 3 files, the second 1
    setenv("SUITE_FAULT_PUBLISH_KILL_AFTER", k, 1);
    const std::string interval = std::string(k) == "3" ? "2e-5" : "3e-5";
    const testutil::ToolResult r =
        mpm("--quiet --scene " + scene_ + " --set " + dir_set(out) + tend + " --set output.snapshot_interval=" + interval);
    unsetenv("SUITE_FAULT_PUBLISH_KILL_AFTER");
    ASSERT_NE(r.rc, 0) << r.out;
    ASSERT_TRUE(fs::exists(out + "/.publish-journal"));
  }
  const std::string last = tend + " --set output.snapshot_interval=4e-5";
  ASSERT_EQ(mpm("--quiet --scene " + scene_ + " --set " + dir_set(out) + last).rc, 0);
  ASSERT_EQ(mpm("--quiet --scene " + scene_ + " --set " + dir_set(solo) + last).rc, 0);
  EXPECT_EQ(visible_names(out), visible_names(solo));
  EXPECT_FALSE(fs::exists(out + "/.publish-journal"));
  for (const auto& e : fs::directory_iterator(out))
    EXPECT_NE(e.path().filename().string().rfind(".staging-", 0), 0u) << e.path();
  // continuing a published run is refused while a publish is unfinished (its files are not one run)
  setenv("SUITE_FAULT_PUBLISH_KILL_AFTER", "1", 1);
  ASSERT_NE(mpm("--quiet --scene " + scene_ + " --set " + dir_set(out) + tend).rc, 0);
  unsetenv("SUITE_FAULT_PUBLISH_KILL_AFTER");
  const testutil::ToolResult c =
      mpm("--scene " + scene_ + " --set " + dir_set(out) + " --set output.snapshot_interval=4e-5 --restart " + out +
          "/ck_checkpoint.h5");
  EXPECT_EQ(c.rc, 2) << c.out;
  EXPECT_NE(c.out.find("its last publish was interrupted"), std::string::npos) << c.out;
}

TEST_F(MpmRestart, CompletedRunContinuesToALaterEndFromItsPublishedCheckpoint) {
  testutil::TempDir d;
  const std::string out = d.file("o");
  ASSERT_EQ(mpm("--quiet --scene " + scene_ + " --set " + dir_set(out) + " --set time.end=1e-4").rc, 0);
  const testutil::ToolResult r = mpm("--quiet --scene " + scene_ + " --set " + dir_set(out) + " --restart " + out +
                                     "/ck_checkpoint.h5");
  ASSERT_EQ(r.rc, 0) << r.out;
  expect_same_run(ref_, out);  // snapshots up to 1e-4 s carried over, the rest computed
}

TEST_F(MpmRestart, CheckpointOfAnotherRunIsRefused) {
  testutil::TempDir d;
  const std::string out = d.file("o");
  ASSERT_EQ(mpm("--quiet --scene " + scene_ + " --set " + dir_set(out) + " --set time.end=2.5e-5").rc, 0);
  const auto before = contents(out);
  const testutil::ToolResult r = mpm("--scene " + scene_ + " --set " + dir_set(out) +
                                     " --set material[1].density=1100.0 --restart " + out + "/ck_checkpoint.h5");
  EXPECT_EQ(r.rc, 2) << r.out;
  EXPECT_NE(r.out.find(out + "/ck_checkpoint.h5: checkpoint of another run (run identity "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("they differ in material[1].density: this run 1100.0, checkpoint 1000.0"), std::string::npos)
      << r.out;
  EXPECT_EQ(contents(out), before);
  // not a checkpoint at all: a snapshot
  const testutil::ToolResult s = mpm("--scene " + scene_ + " --set " + dir_set(out) + " --restart " + out + "/ck_000000.h5");
  EXPECT_EQ(s.rc, 2) << s.out;
  EXPECT_NE(s.out.find("not an mpm-frag checkpoint"), std::string::npos) << s.out;
}

namespace {
/// Copy `from` to `to` without the state field `name` of every material that has it; returns
/// how many datasets were removed.
int copy_without_field(const std::string& from, const std::string& to, const std::string& name) {
  fs::copy_file(from, to, fs::copy_options::overwrite_existing);
  const hid_t f = H5Fopen(to.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  int removed = 0;
  for (int m = 0; m < 8; ++m) {
    const std::string ds = "/mpm_state/materials/" + std::to_string(m) + "/" + name;
    if (H5Lexists(f, ("/mpm_state/materials/" + std::to_string(m)).c_str(), H5P_DEFAULT) > 0 &&
        H5Lexists(f, ds.c_str(), H5P_DEFAULT) > 0 && H5Ldelete(f, ds.c_str(), H5P_DEFAULT) >= 0)
      ++removed;
  }
  H5Fclose(f);
  return removed;
}
}  // namespace

TEST_F(MpmRestart, CheckpointWithoutTheCostFieldRestartsOneWithoutDamageIsRefused) {
  testutil::TempDir d;
  const std::string out = d.file("o");
  ASSERT_EQ(mpm("--quiet --scene " + scene_ + " --set " + dir_set(out) + " --set time.end=1e-4").rc, 0);
  const std::string old = d.file("old.h5"), broken = d.file("broken.h5");
  ASSERT_EQ(copy_without_field(out + "/ck_checkpoint.h5", old, "damage_substeps"), 1);
  ASSERT_EQ(copy_without_field(out + "/ck_checkpoint.h5", broken, "damage"), 1);
  const testutil::ToolResult b = mpm("--scene " + scene_ + " --set " + dir_set(out) + " --restart " + broken);
  EXPECT_EQ(b.rc, 2) << b.out;
  EXPECT_NE(b.out.find("state field 'damage' missing"), std::string::npos) << b.out;
  const testutil::ToolResult r = mpm("--quiet --scene " + scene_ + " --set " + dir_set(out) + " --restart " + old);
  ASSERT_EQ(r.rc, 0) << r.out;
  expect_same_run(ref_, out);  // the field weighs MPI cuts only: one rank continues bit for bit
}
