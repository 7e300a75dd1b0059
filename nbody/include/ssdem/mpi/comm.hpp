/// @file comm.hpp
/// The MPI helpers of ssdem-grav's domain decomposition (MPI build only, SUITE_MPI=ON): the
/// suite's shared ones (common/mpi/include/common/mpi_comm.hpp, also used by mpm-frag) under
/// this namespace.
#pragma once
#include "common/mpi_comm.hpp"

namespace ssdem::mpi {
using common::mpi::Comm;
using common::mpi::get;
using common::mpi::put;
}  // namespace ssdem::mpi
