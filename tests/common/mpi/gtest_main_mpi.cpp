/// @file gtest_main_mpi.cpp
/// main() of the MPI GoogleTest executables (label mpi; library suite_gtest_main_mpi): MPI with
/// funnelled threads (OpenMP inside a rank, MPI calls from its master thread), every rank runs
/// every test, only rank 0 prints, and the exit status is the worst of the ranks' so that mpirun
/// fails when any rank failed.
#include <gtest/gtest.h>
#include <mpi.h>

int main(int argc, char** argv) {
  int provided = 0;
  MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
  ::testing::InitGoogleTest(&argc, argv);
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  if (rank != 0) {
    auto& l = ::testing::UnitTest::GetInstance()->listeners();
    delete l.Release(l.default_result_printer());
  }
  int rc = RUN_ALL_TESTS();
  MPI_Allreduce(MPI_IN_PLACE, &rc, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
  MPI_Finalize();
  return rc;
}
