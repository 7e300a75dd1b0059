/// @file comm.hpp
/// The MPI helpers of mpm-frag's domain decomposition (MPI build only, SUITE_MPI=ON): the
/// suite's shared ones (common/mpi/include/common/mpi_comm.hpp, also used by ssdem-grav) under
/// this namespace.
#pragma once
#include "common/mpi_comm.hpp"

namespace mpmfrag::mpi {
using common::mpi::Comm;
using common::mpi::get;
using common::mpi::put;
}  // namespace mpmfrag::mpi
