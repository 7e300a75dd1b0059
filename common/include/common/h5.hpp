/// @file h5.hpp
/// Thin RAII wrappers over the HDF5 C API: files, groups, attributes and 1-D/2-D datasets,
/// each dataset written with a `unit` attribute. Readers check dtype class/size and shape and
/// throw InputError naming the file and dataset path.
#pragma once
#include <hdf5.h>

#include <cstdint>
#include <string>
#include <vector>

#include "common/provenance.hpp"

namespace common::h5 {

/// Owning handle; closes with the matching H5*close.
class Handle {
 public:
  Handle() = default;
  explicit Handle(hid_t id) : id_(id) {}
  ~Handle();
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  Handle(Handle&& o) noexcept : id_(o.id_) { o.id_ = -1; }
  Handle& operator=(Handle&& o) noexcept;
  hid_t id() const { return id_; }
  operator hid_t() const { return id_; }
  bool valid() const { return id_ >= 0; }
  /// Give up ownership (the caller closes the id).
  hid_t release() {
    const hid_t id = id_;
    id_ = -1;
    return id;
  }

 private:
  hid_t id_ = -1;
};

/// Create a file for writing. The file is built in memory (HDF5 core driver, no backing
/// store) and reaches the disk only through save_file(): a full disk or a file-size limit then
/// fails one checked POSIX write, never an HDF5 flush half-way through a file (which left
/// libhdf5 with a file it could not close, and the tools crashed at exit). `path` is the name the
/// image will be saved under (used in messages). Peak memory: about twice the file size.
Handle create_file(const std::string& path);
/// Write the image of a file made by create_file() to `path` (created or truncated) with checked
/// writes; throws IoError naming `shown_as` (default: `path`; e.g. the final name of a temporary
/// file) and the cause (disk full, file too large, not writable). The caller renames it into
/// place (AtomicPath), so a failed save never replaces an earlier file.
void save_file(hid_t file, const std::string& path, const std::string& shown_as = "");
/// Open an existing file read-only; throws InputError if missing or not HDF5.
Handle open_file_read(const std::string& path);
/// Create a group (throws IoError); open a group (throws InputError naming `file`).
Handle create_group(hid_t loc, const std::string& name);
Handle open_group(hid_t loc, const std::string& name, const std::string& file);
bool exists(hid_t loc, const std::string& path);

// ---- attributes --------------------------------------------------------------------------
void write_attr(hid_t obj, const std::string& name, const std::string& value);
void write_attr(hid_t obj, const std::string& name, double value);
void write_attr(hid_t obj, const std::string& name, std::int64_t value);
void write_attr(hid_t obj, const std::string& name, const std::vector<double>& values);
void write_attr(hid_t obj, const std::string& name, const std::vector<std::int64_t>& values);
std::string read_attr_string(hid_t obj, const std::string& name, const std::string& file);
double read_attr_double(hid_t obj, const std::string& name, const std::string& file);
std::int64_t read_attr_int(hid_t obj, const std::string& name, const std::string& file);
std::vector<double> read_attr_doubles(hid_t obj, const std::string& name, const std::string& file);
std::vector<std::int64_t> read_attr_ints(hid_t obj, const std::string& name, const std::string& file);
bool has_attr(hid_t obj, const std::string& name);

// ---- datasets ----------------------------------------------------------------------------
/// Write `rows` x `cols` values (cols = 1 writes a 1-D dataset) with a `unit` attribute.
void write_dataset(hid_t loc, const std::string& name, const double* data, std::size_t rows,
                   std::size_t cols, const std::string& unit);
void write_dataset(hid_t loc, const std::string& name, const std::uint64_t* data,
                   std::size_t rows, std::size_t cols, const std::string& unit);
void write_dataset(hid_t loc, const std::string& name, const std::int32_t* data,
                   std::size_t rows, std::size_t cols, const std::string& unit);
void write_dataset(hid_t loc, const std::string& name, const std::int64_t* data,
                   std::size_t rows, std::size_t cols, const std::string& unit);

/// Rows [offset, offset + rows) of a dataset of `total` rows, written by one of several
/// processes together (parallel HDF5; common/mpi/h5_parallel.hpp); `xfer`: the transfer
/// property list (collective MPI-IO). Every process of the file calls write_dataset_rows for
/// every dataset, in the same order, with the same name, total and cols, even with no rows.
struct RowBlock {
  std::size_t offset = 0;
  std::size_t total = 0;
  hid_t xfer = H5P_DEFAULT;
};
/// As write_dataset, for this process's block of rows. Returns false if the data write failed
/// (the caller agrees on failure with the other processes); throws IoError if the dataset
/// cannot be created.
bool write_dataset_rows(hid_t loc, const std::string& name, const double* data, std::size_t rows,
                        std::size_t cols, const std::string& unit, const RowBlock& block);
bool write_dataset_rows(hid_t loc, const std::string& name, const std::uint64_t* data, std::size_t rows,
                        std::size_t cols, const std::string& unit, const RowBlock& block);
bool write_dataset_rows(hid_t loc, const std::string& name, const std::int32_t* data, std::size_t rows,
                        std::size_t cols, const std::string& unit, const RowBlock& block);

/// Read a float64 dataset of shape (rows) if cols == 1 or (rows, cols); `rows` = expected
/// row count, or -1 to accept any. Throws InputError "file: /path: ..." on mismatch.
std::vector<double> read_doubles(hid_t loc, const std::string& name, long long rows,
                                 std::size_t cols, const std::string& file);
/// read_u64 accepts only a uint64 dataset (ids); read_i32/read_i64 any integer type.
std::vector<std::uint64_t> read_u64(hid_t loc, const std::string& name, long long rows,
                                    std::size_t cols, const std::string& file);
std::vector<std::int32_t> read_i32(hid_t loc, const std::string& name, long long rows,
                                   std::size_t cols, const std::string& file);
std::vector<std::int64_t> read_i64(hid_t loc, const std::string& name, long long rows,
                                   std::size_t cols, const std::string& file);
/// Rows [offset, offset + count) of a dataset: one process's part of a file (a restart on
/// several MPI ranks, each reading its own block independently). The same checks as the whole
/// read (dtype, shape, `rows` expected in all); InputError if the range exceeds the dataset.
struct RowRange {
  std::size_t offset = 0;
  std::size_t count = 0;
};
std::vector<double> read_doubles(hid_t loc, const std::string& name, long long rows, std::size_t cols,
                                 const std::string& file, const RowRange& range);
std::vector<std::uint64_t> read_u64(hid_t loc, const std::string& name, long long rows, std::size_t cols,
                                    const std::string& file, const RowRange& range);
std::vector<std::int32_t> read_i32(hid_t loc, const std::string& name, long long rows, std::size_t cols,
                                   const std::string& file, const RowRange& range);
/// Shape of a dataset (throws InputError if absent).
std::vector<hsize_t> shape(hid_t loc, const std::string& name, const std::string& file);
/// Rows of a dataset (its first dimension), with the messages of the whole reads: InputError if
/// it is absent ("required dataset is missing") or has no dimension.
std::size_t rows(hid_t loc, const std::string& name, const std::string& file);
/// The `unit` attribute of a dataset ("" if absent).
std::string unit_of(hid_t loc, const std::string& name);

/// Write provenance as attributes of group `/provenance`.
void write_provenance(hid_t file, const Provenance& p);
/// Read it back (fields absent in the file are left empty).
Provenance read_provenance(hid_t file, const std::string& path);

/// Silence HDF5's automatic error stack printing (errors become exceptions here).
void quiet_errors();

}  // namespace common::h5
