/// @file mpi_test_util.hpp
/// Helpers of the collective-file tests (label mpi): the world communicator, a directory shared
/// by the ranks, a provenance record, which rank holds which row, a write under a file-size
/// limit, a file's bytes.
#pragma once
#include <mpi.h>
#include <sys/resource.h>
#include <unistd.h>

#include <csignal>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "common/mpi_comm.hpp"
#include "common/provenance.hpp"
#include "common/status.hpp"

namespace mpi_test {

inline common::mpi::Comm& world() {
  static common::mpi::Comm c(MPI_COMM_WORLD);
  return c;
}

/// A directory shared by the ranks (rank 0 makes it), removed at the end of the test.
struct SharedDir {
  std::string path;
  SharedDir() {
    std::string p;
    if (world().rank == 0) {
      char tmpl[] = "/tmp/common_mpi.XXXXXX";
      const char* made = ::mkdtemp(tmpl);
      if (!made) std::abort();  // no shared scratch directory: nothing to test
      p = made;
    }
    path = world().bcast(p);
  }
  ~SharedDir() {
    MPI_Barrier(MPI_COMM_WORLD);
    if (world().rank == 0) std::filesystem::remove_all(path);
  }
};

inline common::Provenance prov() {
  common::Provenance p;
  p.tool = "test_common_mpi";
  p.version = "1";
  p.git_sha = "abc";
  p.command_line = "mpirun test";
  p.scene_toml = "[a]\nb = 1\n";
  return p;
}

/// Which rank holds global row k of a test set: hashed, all but the last rank (P > 1), or all on
/// the last rank.
enum class Spread { hashed, last_empty, all_on_last };
inline int owner(std::size_t k, Spread how) {
  const int P = world().size;
  switch (how) {
    case Spread::hashed: return static_cast<int>((k * 2654435761u >> 7) % P);
    case Spread::last_empty: return P > 1 ? static_cast<int>(k % (P - 1)) : 0;
    case Spread::all_on_last: return P - 1;
  }
  return 0;
}

/// Run `write` with a 64 KiB file-size limit on this rank (a full disk, SIGXFSZ ignored); true if
/// it threw common::IoError (its message in *what).
template <class F>
bool io_error_under_file_size_limit(F&& write, std::string* what = nullptr) {
  std::signal(SIGXFSZ, SIG_IGN);
  rlimit old{};
  ::getrlimit(RLIMIT_FSIZE, &old);
  rlimit lim = old;
  lim.rlim_cur = 64 * 1024;
  ::setrlimit(RLIMIT_FSIZE, &lim);
  bool threw = false;
  try {
    write();
  } catch (const common::IoError& e) {
    threw = true;
    if (what) *what = e.what();
  }
  ::setrlimit(RLIMIT_FSIZE, &old);
  return threw;
}

inline std::string contents(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

}  // namespace mpi_test
