/// @file h5_parallel.cpp
/// Implementation of common/h5_parallel.hpp (the header states the contract).
#include "common/h5_parallel.hpp"

#include <fcntl.h>
#include <sys/resource.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "common/status.hpp"

namespace common::mpi {

namespace {
/// Rank 0: "" if `bytes` can be written beside `temp` (a scratch file of that size is
/// allocated and removed), else the reason.
std::string reserve(const std::string& temp, std::uintmax_t bytes) {
  const std::string scratch = temp + ".reserve";
  const int fd = ::open(scratch.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
  if (fd < 0) return std::string("cannot create a file beside it: ") + std::strerror(errno);
  const int rc = ::posix_fallocate(fd, 0, static_cast<off_t>(bytes));
  ::close(fd);
  ::unlink(scratch.c_str());
  return rc == 0 ? std::string() : "no room for " + std::to_string(bytes) + " bytes: " + std::strerror(rc);
}
}  // namespace

ParallelFile::ParallelFile(Comm& comm, const std::string& final_path, std::uintmax_t reserve_bytes)
    : comm_(comm), final_(final_path) {
  h5::quiet_errors();
  std::string err;
  if (comm.rank == 0) {
    try {
      temp_ = std::make_unique<AtomicPath>(final_path);
      err = reserve(temp_->temp_path(), reserve_bytes);
      if (!err.empty()) err = final_path + ": " + err + " (disk full, quota or file-size limit)";
    } catch (const std::exception& e) {
      err = e.what();
    }
  }
  err = comm.bcast(err);
  rlimit lim{};  // every rank writes somewhere in the file: each one's limit must admit all of it
  const bool fits = ::getrlimit(RLIMIT_FSIZE, &lim) != 0 || lim.rlim_cur == RLIM_INFINITY || lim.rlim_cur >= reserve_bytes;
  if (err.empty() && !comm.all(fits))
    err = final_path + ": a rank's file-size limit (ulimit -f) is below the file's " + std::to_string(reserve_bytes) + " bytes";
  if (!err.empty()) throw IoError(err);
  const std::string temp = comm.bcast(comm.rank == 0 ? temp_->temp_path() : std::string());
  h5::Handle fapl(H5Pcreate(H5P_FILE_ACCESS));
  bool ok = fapl.valid() && H5Pset_fapl_mpio(fapl, comm.c, MPI_INFO_NULL) >= 0;
  // every metadata operation is collective anyway: let HDF5 write metadata collectively too
  ok = ok && H5Pset_all_coll_metadata_ops(fapl, true) >= 0 && H5Pset_coll_metadata_write(fapl, true) >= 0;
  if (!comm.all(ok)) throw IoError(final_path + ": cannot set up parallel HDF5 (MPI-IO driver)");
  file_ = h5::Handle(H5Fcreate(temp.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl));
  if (!comm.all(file_.valid())) throw IoError(final_path + ": cannot create the HDF5 file " + temp + " on every rank");
  xfer_ = h5::Handle(H5Pcreate(H5P_DATASET_XFER));
  if (!comm.all(xfer_.valid() && H5Pset_dxpl_mpio(xfer_, H5FD_MPIO_COLLECTIVE) >= 0))
    throw IoError(final_path + ": cannot set up collective transfers");
}

ParallelFile::~ParallelFile() {
  // Not committed: an exception on this rank (a failure every rank sees goes through
  // commit(false)). Closing is collective, and the other ranks may be inside a collective write
  // or the commit, where they would wait for this rank for ever, and it for them. So the file is
  // left open on more than one rank: the exception reaches the tool's main, which aborts every
  // rank with its exit code (MPI_Abort), and rank 0, if it is unwinding too, removes the
  // temporary name (temp_). One rank alone closes it as the serial writers do.
  if (file_.valid() && comm_.size > 1) (void)file_.release();
}

void ParallelFile::commit(bool ok) {
  const hid_t f = file_.id();
  ok = H5Fflush(f, H5F_SCOPE_GLOBAL) >= 0 && ok;  // collective
  (void)file_.release();
  ok = H5Fclose(f) >= 0 && ok;                     // collective
  std::string err = comm_.all(ok) ? std::string() : final_ + ": writing the HDF5 file failed on some rank (disk full or file too large?)";
  if (comm_.rank == 0 && err.empty()) {
    try {
      temp_->commit();
    } catch (const std::exception& e) {
      err = e.what();
    }
  }
  err = comm_.bcast(err);
  temp_.reset();  // rank 0: removes the temporary file unless renamed
  if (!err.empty()) throw IoError(err);
}

}  // namespace common::mpi
