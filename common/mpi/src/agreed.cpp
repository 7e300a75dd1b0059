/// @file agreed.cpp
/// Implementation of common/agreed.hpp (the header states the contract).
#include "common/agreed.hpp"

#include <string>

#include "common/status.hpp"

namespace common::mpi {

void agreed(Comm& comm, const std::function<void()>& f) {
  int code = 0;
  std::string msg;
  try {
    f();
  } catch (const InputError& e) {
    code = 2, msg = e.what();
  } catch (const NumericalError& e) {
    code = 3, msg = e.what();
  } catch (const std::exception& e) {
    code = 4, msg = e.what();
  }
  int first = code != 0 ? comm.rank : comm.size;  // the lowest failing rank speaks for all
  MPI_Allreduce(MPI_IN_PLACE, &first, 1, MPI_INT, MPI_MIN, comm.c);
  if (first == comm.size) return;
  MPI_Bcast(&code, 1, MPI_INT, first, comm.c);
  msg = comm.bcast(msg, first);
  if (code == 2) throw InputError(msg);
  if (code == 3) throw NumericalError(msg);
  throw IoError(msg);
}

}  // namespace common::mpi
