/// @file test_disk_full.cpp
/// A full disk while writing a particle or sphere file (simulated with RLIMIT_FSIZE, which makes
/// write() fail with EFBIG once the limit is reached, like ENOSPC): the writer throws IoError,
/// leaves no temporary file, keeps the earlier file at the same path intact, and the process
/// exits normally afterwards. (Before the in-memory writer, libhdf5 kept the failed file open and
/// the tools crashed at exit inside H5close: the child below runs the exit handlers to catch that.)
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>

#include "common/status.hpp"
#include "test_util.hpp"

using namespace common;

namespace {

std::string read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// Run `body` in a child process whose files may not exceed `limit` bytes; the child's exit
/// status (0: body returned true) is returned, or 128 + signal if it died of a signal.
int run_with_file_limit(rlim_t limit, const std::function<bool()>& body) {
  const pid_t pid = ::fork();
  if (pid == 0) {
    std::signal(SIGXFSZ, SIG_IGN);  // write() then fails with EFBIG instead of killing us
    rlimit rl{limit, limit};
    ::setrlimit(RLIMIT_FSIZE, &rl);
    bool ok = false;
    try {
      ok = body();
    } catch (...) {
      ok = false;
    }
    std::exit(ok ? 0 : 1);  // exit(), not _exit(): libhdf5's exit handlers must run cleanly
  }
  int status = 0;
  ::waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

bool only_file_in(const std::filesystem::path& dir, const std::string& name) {
  int count = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    ++count;
    if (e.path().filename() != name) return false;
  }
  return count == 1;
}

}  // namespace

TEST(DiskFull, ParticleSnapshotFailsCleanlyAndKeepsTheEarlierFile) {
  testutil::TempDir dir;
  const std::string path = dir.file("snap.h5");
  write_particle_snapshot(path, testutil::sample_particles(10), testutil::sample_provenance());
  std::filesystem::remove(dir.file("snap.xmf"));
  const std::string before = read_bytes(path);
  const int rc = run_with_file_limit(64 * 1024, [&] {
    try {
      write_particle_snapshot(path, testutil::sample_particles(20000), testutil::sample_provenance());
    } catch (const IoError& e) {
      return std::string(e.what()).find("File too large") != std::string::npos;
    }
    return false;  // no error: the limit did not bite
  });
  EXPECT_EQ(rc, 0) << "expected IoError naming the failure and a normal exit";
  EXPECT_EQ(read_bytes(path), before) << "the earlier snapshot must be left as it was";
  EXPECT_TRUE(only_file_in(dir.path, "snap.h5")) << "no temporary or partial file may remain";
}

TEST(DiskFull, SphereFileFailsCleanlyAndKeepsTheEarlierFile) {
  testutil::TempDir dir;
  const std::string path = dir.file("spheres.h5");
  write_sphere_set(path, testutil::sample_spheres(10), testutil::sample_provenance());
  std::filesystem::remove(dir.file("spheres.xmf"));
  const std::string before = read_bytes(path);
  const int rc = run_with_file_limit(64 * 1024, [&] {
    try {
      write_sphere_set(path, testutil::sample_spheres(20000), testutil::sample_provenance());
    } catch (const IoError&) {
      return true;
    }
    return false;
  });
  EXPECT_EQ(rc, 0);
  EXPECT_EQ(read_bytes(path), before);
  EXPECT_TRUE(only_file_in(dir.path, "spheres.h5"));
}

TEST(DiskFull, WriteWithinTheLimitSucceeds) {
  // The same child set-up with room enough: the write goes through (guards the test above
  // against passing because the child fails for another reason).
  testutil::TempDir dir;
  const std::string path = dir.file("snap.h5");
  const int rc = run_with_file_limit(64 * 1024 * 1024, [&] {
    write_particle_snapshot(path, testutil::sample_particles(20000), testutil::sample_provenance());
    return read_particle_snapshot(path).count() == 20000;
  });
  EXPECT_EQ(rc, 0);
}
