/// @file app_support.hpp
/// Helpers of the tests that run ssdem-grav end to end (test_app.cpp, test_sphere_order.cpp):
/// the tool's command line on one thread, a scratch directory, the settling lattice pile both
/// use, the last snapshot of a run and a checkpoint read for rewriting. SSDEM_GRAV_EXE is the tool's path (CMake).
#pragma once
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "common/provenance.hpp"
#include "common/sphere_file.hpp"
#include "ssdem/io.hpp"

namespace ssdem_test {

inline const std::string kExe = SSDEM_GRAV_EXE;

/// ssdem-grav with `args` on one OpenMP thread, quiet; its exit code (-1 if it did not exit).
inline int run_cmd(const std::string& args) {
  const std::string cmd = "OMP_NUM_THREADS=1 " + kExe + " --quiet " + args + " > /dev/null 2>&1";
  const int rc = std::system(cmd.c_str());
  return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}

/// An empty directory <tmp>/ssdem_test_<name>_<pid>.
inline std::string tmpdir(const std::string& name) {
  namespace fs = std::filesystem;
  const fs::path p = fs::temp_directory_path() / ("ssdem_test_" + name + "_" + std::to_string(getpid()));
  fs::remove_all(p);
  fs::create_directories(p);
  return p.string();
}

/// A lattice pile (6 m, 1 m spheres) settling under its own gravity while it spins slowly:
/// contacts with history everywhere; fixed gravity cadence (every 3 steps), 30 s.
inline const char* const kScene = R"(
[time]
end = 30.0
[initial]
source = "lattice_pile"
body_radius = 6.0
sphere_radius = 1.0
density = 2000.0
jitter = 0.0
angular_velocity = [0.0, 0.0, 2e-4]
[gravity]
every = 3
[contact]
preset = "gravel"
[output]
series_every = 30
checkpoint_wall = 0.0
progress_interval = 100.0
)";

/// Writes kScene to <dir>/scene.toml; returns its path.
inline std::string write_scene(const std::string& dir) {
  const std::string p = dir + "/scene.toml";
  std::ofstream(p) << kScene;
  return p;
}

/// The snapshot of `dir` with the highest step.
inline common::SphereSet last_snapshot(const std::string& dir) {
  namespace fs = std::filesystem;
  std::string best;
  for (const auto& e : fs::directory_iterator(dir)) {
    const std::string n = e.path().filename().string();
    if (n.rfind("snap_", 0) == 0 && e.path().extension() == ".h5" && n > fs::path(best).filename().string())
      best = e.path().string();
  }
  return common::read_sphere_set(best);
}

/// A checkpoint with the header values that writing it again needs (a test that damages it).
struct CheckpointCopy {
  ssdem::SimState st;
  double dt = 0.0, kn = 0.0;
  int every = 0;
  std::string identity;
  /// Writes it to `path`, with `identity` instead of the recorded one if given.
  void write(const std::string& path, const common::Provenance& prov, const std::string* identity_instead = nullptr) const {
    ssdem::write_checkpoint(path, st, dt, every, prov, kn, identity_instead ? *identity_instead : identity);
  }
};
inline CheckpointCopy read_checkpoint_copy(const std::string& path) {
  CheckpointCopy c;
  c.st = ssdem::read_checkpoint(path, &c.dt, &c.every, &c.kn, &c.identity);
  return c;
}

}  // namespace ssdem_test
