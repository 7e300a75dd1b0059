/// @file unwind_parallel_file.cpp
/// A rank that throws while a collective file is open (between ParallelFile's creation and its
/// commit), as the tools' mains see it: `unwind_parallel_file DIR one|all`. An earlier file
/// DIR/out.h5 (dataset x = 1.0 in every row) is written by every rank together; then a second
/// write begins and rank 1 ("one") or every rank ("all") throws before its first row, while the
/// others go on into the collective writes and the commit. The exception is caught in main,
/// which aborts every rank with its exit code (4) as ssdem-grav and mpm-frag do. Run by
/// unwind_parallel_file.sh, which asserts the exit code within a time limit (no hang), the
/// message and that DIR/out.h5 is the earlier file.
#include <mpi.h>

#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/h5_parallel.hpp"
#include "common/status.hpp"

namespace {
void write(common::mpi::Comm& comm, const std::string& path, double value, bool throw_here) {
  const std::size_t per = 1000, total = per * static_cast<std::size_t>(comm.size);
  common::mpi::ParallelFile f(comm, path, 1u << 20);
  if (throw_here) throw std::runtime_error("injected failure on rank " + std::to_string(comm.rank));
  const std::vector<double> x(per, value);
  bool ok = common::h5::write_dataset_rows(f.id(), "x", x.data(), per, 1, "1", f.rows(per * comm.rank, total));
  f.commit(ok);
}
}  // namespace

int main(int argc, char** argv) {
  int provided = 0;
  MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
  common::mpi::Comm comm(MPI_COMM_WORLD);
  if (argc != 3) {
    std::fprintf(stderr, "usage: unwind_parallel_file DIR one|all\n");
    MPI_Abort(MPI_COMM_WORLD, 2);
  }
  const std::string path = std::string(argv[1]) + "/out.h5", mode = argv[2];
  int rc = 0;
  try {
    write(comm, path, 1.0, false);
    write(comm, path, 2.0, mode == "all" || comm.rank == 1);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "rank %d: %s\n", comm.rank, e.what());
    rc = static_cast<int>(common::ExitCode::io_failure);
  }
  if (rc != 0) MPI_Abort(MPI_COMM_WORLD, rc);  // as the tools' mains
  MPI_Finalize();
  return 0;
}
