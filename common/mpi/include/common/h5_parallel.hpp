/// @file h5_parallel.hpp
/// One HDF5 file written by every rank of a communicator together (parallel HDF5 over MPI-IO,
/// MPI build only), with the guarantees of the serial writers (common/h5.hpp, atomic_file.hpp):
/// the file is built under a temporary name beside the final one (rank 0 chooses it) and renamed
/// onto the final name by rank 0 only when every rank's writes and the collective close
/// succeeded, so a full disk, a file-size limit or an unwritable directory leaves any earlier
/// file untouched and no temporary behind, and every rank throws the same IoError.
///
/// A failure inside a collective HDF5 write cannot be recovered: HDF5 1.10's parallel error paths
/// differ between ranks (measured: with a file-size limit one rank waits in a broadcast of the
/// truncation, the other in a barrier of the metadata flush, forever). So the space is checked
/// before anything is written: every rank's file-size limit (RLIMIT_FSIZE) must admit
/// `reserve_bytes`, and rank 0 reserves that many bytes beside the file (posix_fallocate of a
/// scratch file, then removed: a full disk, a quota or a size limit fails there). Failing that,
/// every rank throws IoError and nothing was written. A disk that fills during the write, after
/// the check, still hangs the ranks until the job's limit; the rename never happens, so the
/// earlier file is kept even then.
///
/// Every rank makes the same calls in the same order (HDF5's metadata operations are
/// collective); dataset rows go through h5::write_dataset_rows with rows() (collective MPI-IO
/// transfers).
///
/// An exception between creation and commit (on one rank: an allocation, a logic error) must not
/// close the file: the close is collective and would wait for ranks that are inside a collective
/// write (measured: the job hung until killed). The destructor of an uncommitted file on more
/// than one rank leaves it open, and the tools' mains abort every rank with the exit code
/// (tests common_mpi_unwind_one/all: exit 4 within a second instead of a hang, the earlier file
/// kept; when only ranks other than 0 failed, rank 0 may be killed inside the write and leave its
/// temporary file beside the kept one). So a caller that catches an exception from inside a
/// ParallelFile's life must abort the job, not go on to MPI_Finalize (HDF5's shutdown would then
/// close the file collectively); failures every rank sees go through commit(false).
#pragma once
#include <cstdint>
#include <memory>
#include <string>

#include "common/atomic_file.hpp"
#include "common/h5.hpp"
#include "common/mpi_comm.hpp"

namespace common::mpi {

class ParallelFile {
 public:
  /// Collective: check the space for `reserve_bytes` (the file's size or more), then create
  /// the temporary file (IoError on every rank if any rank cannot).
  ParallelFile(Comm& comm, const std::string& final_path, std::uintmax_t reserve_bytes);
  ~ParallelFile();
  ParallelFile(const ParallelFile&) = delete;
  ParallelFile& operator=(const ParallelFile&) = delete;

  hid_t id() const { return file_.id(); }
  /// This rank's rows [offset, offset + n) of datasets of `total` rows, collective transfers.
  h5::RowBlock rows(std::size_t offset, std::size_t total) const { return {offset, total, xfer_.id()}; }
  /// The collective transfer property list.
  hid_t xfer() const { return xfer_.id(); }
  /// Collective: close the file and rename it into place if `ok` on every rank and the close
  /// succeeded everywhere; else remove it and throw IoError on every rank.
  void commit(bool ok);

 private:
  Comm& comm_;
  std::string final_;
  std::unique_ptr<AtomicPath> temp_;  ///< rank 0 only: the temporary name, renamed at commit
  h5::Handle xfer_;
  h5::Handle file_;
};

}  // namespace common::mpi
