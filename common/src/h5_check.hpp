/// @file h5_check.hpp
/// Checks on HDF5 input files before and while they are read (internal to common/src):
/// validate_in_child() reads a whole file in a forked child under a time limit, so that a damaged
/// file that would crash libhdf5 or make it loop ends in InputError instead; check_declared_size()
/// refuses a dataset that declares more data than the file can hold, before anything is allocated.
#pragma once
#include <hdf5.h>

#include <string>

namespace common::h5::detail {

/// Throws InputError naming `file` and `name` if `npoints` elements of `type` in dataset `ds`
/// cannot fit in the file (unfiltered data only; compressed datasets are not bounded).
void check_declared_size(hid_t ds, hid_t type, hsize_t npoints, const std::string& file, const std::string& name);

/// Read everything in `path` (every object, attribute and dataset) in a forked child within a
/// time limit of 10 s + 1 s per 50 MB (env SUITE_H5_CHECK_TIMEOUT_S sets the 10 s); throws
/// InputError naming the file if the child crashes, hangs or fails.
void validate_in_child(const std::string& path, hsize_t file_size);

}  // namespace common::h5::detail
