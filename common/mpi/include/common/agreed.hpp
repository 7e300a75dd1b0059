/// @file agreed.hpp
/// Errors that every rank acts on together (MPI build only). A rank that throws while the others
/// go on into a collective leaves them waiting forever; agreed() runs a piece of work on every
/// rank (it may do nothing on some) and, if it threw anywhere, throws on every rank the error of
/// the lowest rank that failed, with its type, so that every rank exits with the same documented
/// code: InputError (2), NumericalError (3), anything else as IoError (4).
#pragma once
#include <functional>

#include "common/mpi_comm.hpp"

namespace common::mpi {

/// Collective: run `f` here; if any rank's `f` threw, throw that error (the lowest such rank's)
/// on every rank.
void agreed(Comm& comm, const std::function<void()>& f);

}  // namespace common::mpi
