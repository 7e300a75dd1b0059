/// @file mpi_world.hpp
/// What the MPI tests of ssdem-grav share: the world communicator, and one OpenMP thread (the
/// one-rank references sum in index order; a test that wants more threads asks for them).
#pragma once
#include <mpi.h>
#include <omp.h>

#include "ssdem/mpi/comm.hpp"

namespace ssdem_test {
inline ssdem::mpi::Comm& world() {
  static ssdem::mpi::Comm c(MPI_COMM_WORLD);
  return c;
}
[[maybe_unused]] inline const bool kOneThread = [] {
  omp_set_num_threads(1);
  return true;
}();
}  // namespace ssdem_test
