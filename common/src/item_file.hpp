/// @file item_file.hpp
/// Internal: shared machinery for the two item-file kinds (particles, spheres).
#pragma once
#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "common/field.hpp"
#include "common/h5.hpp"
#include "common/status.hpp"
#include "common/xdmf.hpp"

namespace common::detail {

/// Check `n*ncomp` sizes (writer side; a mismatch is a caller bug reported as InputError).
inline void check_size(const char* what, std::size_t got, std::size_t n, std::size_t ncomp) {
  if (got != n * ncomp)
    throw InputError("", what, "array has " + std::to_string(got) + " values, expected " +
                                   std::to_string(n * ncomp));
}

/// Reader side: all values finite (and > 0 if `positive`), else InputError naming the row (the
/// file row: v holds rows row0, row0 + 1, ...).
inline void check_values(const std::string& file, const std::string& path,
                         const std::vector<double>& v, std::size_t ncomp, bool positive, std::size_t row0 = 0) {
  for (std::size_t i = 0; i < v.size(); ++i) {
    if (!std::isfinite(v[i]))
      throw InputError(file, path, "non-finite value (NaN or Inf) at row " + std::to_string(row0 + i / ncomp));
    if (positive && !(v[i] > 0.0))
      throw InputError(file, path, "non-positive value " + std::to_string(v[i]) + " at row " +
                                       std::to_string(row0 + i / ncomp) + " (must be > 0)");
  }
}

/// Ids key the random streams, the hand-off map and the messages: each must appear once.
/// InputError naming the first row whose id already appeared above it. O(n) for the writers'
/// increasing ids, O(n log n) otherwise.
inline void check_unique_ids(const std::string& file, const std::string& path, const std::vector<std::uint64_t>& id) {
  if (std::adjacent_find(id.begin(), id.end(), std::greater_equal<>()) == id.end()) return;
  std::vector<std::pair<std::uint64_t, std::size_t>> v(id.size());
  for (std::size_t i = 0; i < id.size(); ++i) v[i] = {id[i], i};
  std::sort(v.begin(), v.end());
  std::size_t best = id.size(), first = 0;
  for (std::size_t i = 1; i < v.size(); ++i)  // in a run of equal ids, the 2nd row is the first repeat
    if (v[i].first == v[i - 1].first && (i < 2 || v[i - 2].first != v[i].first) && v[i].second < best) {
      best = v[i].second;
      first = v[i - 1].second;
    }
  if (best == id.size()) return;
  throw InputError(file, path, "duplicate id " + std::to_string(id[best]) + " at rows " + std::to_string(first) +
                                   " and " + std::to_string(best) + " (ids must be unique)");
}

/// Root attributes and format check shared by both kinds.
inline void write_header(hid_t f, const char* format, std::int64_t version, double time, std::int64_t step) {
  h5::write_attr(f, "format", std::string(format));
  h5::write_attr(f, "format_version", version);
  h5::write_attr(f, "time", time);
  h5::write_attr(f, "step", step);
}

inline void read_header(hid_t f, const std::string& file, const char* format, std::int64_t version,
                        double& time, std::int64_t& step) {
  if (!h5::has_attr(f, "format"))
    throw InputError(file, "/format", std::string("attribute missing: not a '") + format + "' file");
  const std::string got = h5::read_attr_string(f, "format", file);
  if (got != format)
    throw InputError(file, "/format", "unknown format '" + got + "', expected '" + format + "'");
  const std::int64_t v = h5::read_attr_int(f, "format_version", file);
  if (v > version)
    throw InputError(file, "/format_version", "version " + std::to_string(v) +
                                                  " is newer than this tool reads (" + std::to_string(version) +
                                                  "); update the tool");
  // Version 1 is the first released layout; anything below it predates the file contract.
  if (v < 1)
    throw InputError(file, "/format_version", "version " + std::to_string(v) +
                                                  " is older than the oldest this tool reads (1); regenerate the "
                                                  "file with the current tools");
  time = h5::read_attr_double(f, "time", file);
  step = h5::read_attr_int(f, "step", file);
  if (!std::isfinite(time)) throw InputError(file, "/time", "non-finite time");
}

/// The fields' datasets (this process's `n` rows of each, `block`); false if a data write failed.
inline bool write_fields(hid_t g, const std::vector<Field>& fields, std::size_t n, const h5::RowBlock& block) {
  bool ok = true;
  for (const auto& fl : fields) {
    check_size(fl.name.c_str(), fl.values.size(), n, fl.ncomp);
    ok = h5::write_dataset_rows(g, fl.name, fl.values.data(), n, fl.ncomp, fl.unit, block) && ok;
    if (!fl.description.empty()) {
      h5::Handle ds(H5Dopen2(g, fl.name.c_str(), H5P_DEFAULT));
      h5::write_attr(ds, "description", fl.description);
    }
  }
  return ok;
}
inline void write_fields(hid_t g, const std::vector<Field>& fields, std::size_t n) {
  if (!write_fields(g, fields, n, h5::RowBlock{0, n, H5P_DEFAULT}))
    throw IoError("HDF5: writing a field failed (disk full or file not writable?)");
}

/// Every member of `g` not in `skip` must be a float64 dataset of shape (n,) or (n, k>=2): it is
/// read as an optional field. Anything else (another dtype, a group, a wrong shape) is an
/// InputError naming the dataset: the whole group is checked against the contract. With `range`,
/// rows [range->offset, range->offset + range->count) of the n only (the same checks).
std::vector<Field> read_fields(hid_t f, hid_t g, const std::string& group, const std::string& file,
                               std::size_t n, const std::vector<std::string>& skip,
                               const h5::RowRange* range = nullptr);

inline std::vector<XdmfAttribute> field_attributes(const std::string& group, const std::vector<Field>& fields) {
  std::vector<XdmfAttribute> a;
  for (const auto& f : fields) a.push_back({f.name, group + "/" + f.name, f.ncomp, "Float", 8});
  return a;
}

inline std::string basename(const std::string& path) {
  return std::filesystem::path(path).filename().string();
}

}  // namespace common::detail
