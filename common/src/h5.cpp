/// @file h5.cpp
/// Implementation of common/h5.hpp (the header states the contract, and for physics the equations and sources).
#include "common/h5.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <sstream>

#include "common/huge_pages.hpp"
#include "common/status.hpp"
#include "h5_check.hpp"

namespace common::h5 {

namespace {

void check_io(herr_t rc, const std::string& what) {
  if (rc < 0) throw IoError("HDF5: " + what + " failed (disk full or file not writable?)");
}

std::string shape_str(const std::vector<hsize_t>& d) {
  std::ostringstream o;
  o << "(";
  for (std::size_t i = 0; i < d.size(); ++i) o << (i ? ", " : "") << d[i];
  if (d.size() == 1) o << ",";
  o << ")";
  return o.str();
}

std::string expect_str(long long rows, std::size_t cols) {
  std::string r = rows < 0 ? "N" : std::to_string(rows);
  return cols == 1 ? "(" + r + ",)" : "(" + r + ", " + std::to_string(cols) + ")";
}

/// Create dataset `name` of block.total x cols rows and write this process's rows there: the whole
/// dataset (one process: H5S_ALL) or a hyperslab of it. False if the write failed.
template <class T>
bool write_block(hid_t loc, const std::string& name, const T* data, std::size_t rows, std::size_t cols,
                 const std::string& unit, const RowBlock& block, hid_t mem_type, hid_t file_type) {
  const int nd = cols == 1 ? 1 : 2;
  hsize_t dims[2] = {block.total, cols};
  Handle space(H5Screate_simple(nd, dims, nullptr));
  if (!space.valid()) throw IoError("HDF5: cannot create dataspace for " + name);
  // storage allocated when the dataset is created, as parallel HDF5 always does: serial and
  // collective files have the same layout (h5diff calls empty datasets that differ in this
  // "not comparable")
  Handle dcpl(H5Pcreate(H5P_DATASET_CREATE));
  if (!dcpl.valid() || H5Pset_alloc_time(dcpl, H5D_ALLOC_TIME_EARLY) < 0)
    throw IoError("HDF5: cannot create the properties of dataset " + name);
  Handle ds(H5Dcreate2(loc, name.c_str(), file_type, space, H5P_DEFAULT, dcpl, H5P_DEFAULT));
  if (!ds.valid()) throw IoError("HDF5: cannot create dataset " + name);
  bool ok = true;
  const bool whole = block.offset == 0 && rows == block.total && block.xfer == H5P_DEFAULT;
  if (block.total * cols > 0 && whole) {
    ok = H5Dwrite(ds, mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) >= 0;
  } else if (block.total * cols > 0) {  // several processes: each its rows; one with none joins too
    hsize_t start[2] = {block.offset, 0}, count[2] = {rows, cols}, one[2] = {1, cols};
    Handle mem(H5Screate_simple(nd, rows > 0 ? count : one, nullptr));
    if (rows > 0) {
      ok = H5Sselect_hyperslab(space, H5S_SELECT_SET, start, nullptr, count, nullptr) >= 0;
    } else {
      H5Sselect_none(space);
      H5Sselect_none(mem);
    }
    ok = H5Dwrite(ds, mem_type, mem, space, block.xfer, data) >= 0 && ok;
  }
  write_attr(ds, "unit", unit);  // after the data, as files were always written
  return ok;
}

template <class T>
void write_any(hid_t loc, const std::string& name, const T* data, std::size_t rows,
               std::size_t cols, const std::string& unit, hid_t mem_type, hid_t file_type) {
  if (!write_block(loc, name, data, rows, cols, unit, RowBlock{0, rows, H5P_DEFAULT}, mem_type, file_type))
    check_io(-1, "writing " + name);
}

enum class Kind { real, integer, uint64 };

template <class T>
std::vector<T> read_any(hid_t loc, const std::string& name, long long rows, std::size_t cols,
                        const std::string& file, hid_t mem_type, Kind kind, const RowRange* range = nullptr) {
  if (!exists(loc, name)) throw InputError(file, name, "required dataset is missing");
  Handle ds(H5Dopen2(loc, name.c_str(), H5P_DEFAULT));
  if (!ds.valid()) throw InputError(file, name, "cannot open dataset (corrupt file?)");
  Handle type(H5Dget_type(ds));
  const H5T_class_t cls = H5Tget_class(type);
  if (kind == Kind::real && !(cls == H5T_FLOAT && H5Tget_size(type) == 8))
    throw InputError(file, name, "wrong dtype: expected float64");
  if (kind == Kind::integer && cls != H5T_INTEGER)
    throw InputError(file, name, "wrong dtype: expected an integer type");
  // Ids are uint64 in the contract; a signed or narrower type would be converted silently
  // (negative ids clipped to 0, i.e. duplicated), so it is refused.
  if (kind == Kind::uint64 && !(cls == H5T_INTEGER && H5Tget_sign(type) == H5T_SGN_NONE && H5Tget_size(type) == 8))
    throw InputError(file, name, "wrong dtype: expected uint64");
  Handle space(H5Dget_space(ds));
  const int nd = H5Sget_simple_extent_ndims(space);
  std::vector<hsize_t> d(nd > 0 ? nd : 0);
  if (nd > 0) H5Sget_simple_extent_dims(space, d.data(), nullptr);
  const bool shape_ok =
      (cols == 1 ? nd == 1 : (nd == 2 && d[1] == cols)) &&  // one component: 1-D (N,), never (N, 1)
      (rows < 0 || (nd >= 1 && d[0] == static_cast<hsize_t>(rows)));
  if (!shape_ok)
    throw InputError(file, name, "wrong shape " + shape_str(d) + ", expected " + expect_str(rows, cols));
  detail::check_declared_size(ds, type, nd >= 1 ? d[0] * cols : 0, file, name);
  if (range) {  // rows [offset, offset + count) only
    if (range->offset + range->count > d[0])
      throw InputError(file, name, "rows [" + std::to_string(range->offset) + ", " +
                                       std::to_string(range->offset + range->count) + ") requested of " + std::to_string(d[0]));
    std::vector<T> part;
    common::resize_huge(part, range->count * cols);
    if (part.empty()) return part;
    hsize_t start[2] = {range->offset, 0}, count[2] = {range->count, cols};
    Handle mem(H5Screate_simple(nd, count, nullptr));
    if (H5Sselect_hyperslab(space, H5S_SELECT_SET, start, nullptr, count, nullptr) < 0 ||
        H5Dread(ds, mem_type, mem, space, H5P_DEFAULT, part.data()) < 0)
      throw InputError(file, name, "cannot read dataset (truncated or corrupt file?)");
    return part;
  }
  std::vector<T> out;
  common::resize_huge(out, nd >= 1 ? d[0] * cols : 0);  // large datasets: fewer first-touch faults
  if (!out.empty() && H5Dread(ds, mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data()) < 0)
    throw InputError(file, name, "cannot read dataset (truncated or corrupt file?)");
  return out;
}

Handle open_attr(hid_t obj, const std::string& name, const std::string& file) {
  if (H5Aexists(obj, name.c_str()) <= 0) throw InputError(file, name, "required attribute is missing");
  Handle a(H5Aopen(obj, name.c_str(), H5P_DEFAULT));
  if (!a.valid()) throw InputError(file, name, "cannot open attribute");
  return a;
}

template <class T>
std::vector<T> read_attr_vec(hid_t obj, const std::string& name, const std::string& file,
                             hid_t mem_type, bool want_float) {
  Handle a = open_attr(obj, name, file);
  Handle type(H5Aget_type(a));
  const H5T_class_t cls = H5Tget_class(type);
  if (want_float ? (cls != H5T_FLOAT && cls != H5T_INTEGER) : cls != H5T_INTEGER)
    throw InputError(file, name, want_float ? "attribute is not numeric" : "attribute is not an integer");
  Handle space(H5Aget_space(a));
  const hssize_t n = H5Sget_simple_extent_npoints(space);
  std::vector<T> v(n > 0 ? n : 0);
  if (!v.empty() && H5Aread(a, mem_type, v.data()) < 0) throw InputError(file, name, "cannot read attribute");
  return v;
}

}  // namespace

Handle::~Handle() {
  if (id_ < 0) return;
  switch (H5Iget_type(id_)) {
    case H5I_FILE: H5Fclose(id_); break;
    case H5I_GROUP: H5Gclose(id_); break;
    case H5I_DATASET: H5Dclose(id_); break;
    case H5I_DATASPACE: H5Sclose(id_); break;
    case H5I_DATATYPE: H5Tclose(id_); break;
    case H5I_ATTR: H5Aclose(id_); break;
    case H5I_GENPROP_LST: H5Pclose(id_); break;
    default: break;
  }
}

Handle& Handle::operator=(Handle&& o) noexcept {
  if (this != &o) {
    Handle tmp(id_);
    id_ = o.id_;
    o.id_ = -1;
  }
  return *this;
}

void quiet_errors() { H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr); }

Handle create_file(const std::string& path) {
  quiet_errors();
  Handle fapl(H5Pcreate(H5P_FILE_ACCESS));
  // Memory grows in 16 MiB steps; backing_store = 0: nothing is written on close.
  if (!fapl.valid() || H5Pset_fapl_core(fapl, std::size_t{16} << 20, 0) < 0)
    throw IoError(path + ": cannot set up the in-memory HDF5 driver");
  Handle f(H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl));
  if (!f.valid()) throw IoError(path + ": cannot create HDF5 file");
  return f;
}

void save_file(hid_t file, const std::string& path, const std::string& shown_as) {
  const std::string& name = shown_as.empty() ? path : shown_as;
  if (H5Fflush(file, H5F_SCOPE_GLOBAL) < 0) throw IoError(name + ": HDF5 flush failed");
  const ssize_t size = H5Fget_file_image(file, nullptr, 0);
  if (size < 0) throw IoError(name + ": cannot take the HDF5 file image");
  const std::size_t bytes = static_cast<std::size_t>(size);
  std::unique_ptr<char[]> image(new char[bytes]);  // not value-initialised: HDF5 fills it
  if (H5Fget_file_image(file, image.get(), bytes) != size)
    throw IoError(name + ": cannot take the HDF5 file image");
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
  if (fd < 0) throw IoError(name + ": cannot create: " + std::strerror(errno));
  std::size_t done = 0;
  while (done < bytes) {
    const ssize_t w = ::write(fd, image.get() + done, bytes - done);
    if (w < 0 && errno == EINTR) continue;
    if (w <= 0) {
      const int err = w < 0 ? errno : ENOSPC;
      ::close(fd);
      throw IoError(name + ": write failed after " + std::to_string(done) + " of " +
                    std::to_string(bytes) + " bytes: " + std::strerror(err));
    }
    done += static_cast<std::size_t>(w);
  }
  if (::close(fd) != 0) throw IoError(name + ": close failed: " + std::strerror(errno));
}

Handle open_file_read(const std::string& path) {
  quiet_errors();
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) {
    if (errno == ENOENT) throw InputError(path, "", "file does not exist");
    throw InputError(path, "", std::string("cannot access: ") + std::strerror(errno));
  }
  if (S_ISDIR(st.st_mode)) throw InputError(path, "", "is a directory, not an HDF5 file");
  // A FIFO would block the open forever; a device is never an HDF5 file.
  if (!S_ISREG(st.st_mode)) throw InputError(path, "", "not a regular file (a FIFO, device or socket)");
  if (H5Fis_hdf5(path.c_str()) <= 0)  // reads the signature only
    throw InputError(path, "", "not an HDF5 file (or truncated/corrupt)");
  detail::validate_in_child(path, static_cast<hsize_t>(st.st_size));
  Handle f(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT));
  if (!f.valid()) throw InputError(path, "", "cannot open HDF5 file (truncated or corrupt?)");
  return f;
}

Handle create_group(hid_t loc, const std::string& name) {
  Handle g(H5Gcreate2(loc, name.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT));
  if (!g.valid()) throw IoError("HDF5: cannot create group " + name);
  return g;
}

Handle open_group(hid_t loc, const std::string& name, const std::string& file) {
  if (!exists(loc, name)) throw InputError(file, name, "required group is missing");
  Handle g(H5Gopen2(loc, name.c_str(), H5P_DEFAULT));
  if (!g.valid()) throw InputError(file, name, "cannot open group (corrupt file?)");
  return g;
}

bool exists(hid_t loc, const std::string& path) {
  // Check each component so that a missing intermediate group is not an HDF5 error.
  std::string partial;
  std::size_t start = (!path.empty() && path[0] == '/') ? 1 : 0;
  if (start) partial = "/";
  while (start <= path.size()) {
    std::size_t end = path.find('/', start);
    if (end == std::string::npos) end = path.size();
    partial += path.substr(start, end - start);
    if (H5Lexists(loc, partial.c_str(), H5P_DEFAULT) <= 0) return false;
    if (end == path.size()) break;
    partial += "/";
    start = end + 1;
  }
  return true;
}

void write_attr(hid_t obj, const std::string& name, const std::string& value) {
  Handle type(H5Tcopy(H5T_C_S1));
  H5Tset_size(type, H5T_VARIABLE);
  H5Tset_cset(type, H5T_CSET_UTF8);
  Handle space(H5Screate(H5S_SCALAR));
  Handle a(H5Acreate2(obj, name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT));
  if (!a.valid()) throw IoError("HDF5: cannot create attribute " + name);
  const char* p = value.c_str();
  check_io(H5Awrite(a, type, &p), "writing attribute " + name);
}

void write_attr(hid_t obj, const std::string& name, double value) {
  write_attr(obj, name, std::vector<double>{value});
}
void write_attr(hid_t obj, const std::string& name, std::int64_t value) {
  write_attr(obj, name, std::vector<std::int64_t>{value});
}

void write_attr(hid_t obj, const std::string& name, const std::vector<double>& values) {
  hsize_t n = values.size();
  Handle space(n == 1 ? H5Screate(H5S_SCALAR) : H5Screate_simple(1, &n, nullptr));
  Handle a(H5Acreate2(obj, name.c_str(), H5T_IEEE_F64LE, space, H5P_DEFAULT, H5P_DEFAULT));
  if (!a.valid()) throw IoError("HDF5: cannot create attribute " + name);
  check_io(H5Awrite(a, H5T_NATIVE_DOUBLE, values.data()), "writing attribute " + name);
}

void write_attr(hid_t obj, const std::string& name, const std::vector<std::int64_t>& values) {
  hsize_t n = values.size();
  Handle space(n == 1 ? H5Screate(H5S_SCALAR) : H5Screate_simple(1, &n, nullptr));
  Handle a(H5Acreate2(obj, name.c_str(), H5T_STD_I64LE, space, H5P_DEFAULT, H5P_DEFAULT));
  if (!a.valid()) throw IoError("HDF5: cannot create attribute " + name);
  check_io(H5Awrite(a, H5T_NATIVE_INT64, values.data()), "writing attribute " + name);
}

bool has_attr(hid_t obj, const std::string& name) { return H5Aexists(obj, name.c_str()) > 0; }

std::string read_attr_string(hid_t obj, const std::string& name, const std::string& file) {
  Handle a = open_attr(obj, name, file);
  Handle type(H5Aget_type(a));
  if (H5Tget_class(type) != H5T_STRING) throw InputError(file, name, "attribute is not a string");
  Handle space(H5Aget_space(a));
  if (H5Sget_simple_extent_npoints(space) != 1) throw InputError(file, name, "attribute is not a scalar string");
  if (H5Tis_variable_str(type) > 0) {
    Handle mem(H5Tcopy(H5T_C_S1));
    H5Tset_size(mem, H5T_VARIABLE);
    H5Tset_cset(mem, H5Tget_cset(type));
    char* p = nullptr;
    if (H5Aread(a, mem, &p) < 0) throw InputError(file, name, "cannot read attribute");
    std::string s = p ? p : "";
    H5free_memory(p);
    return s;
  }
  const std::size_t n = H5Tget_size(type);
  std::string s(n, '\0');
  if (H5Aread(a, type, s.data()) < 0) throw InputError(file, name, "cannot read attribute");
  s.resize(std::strlen(s.c_str()));
  return s;
}

double read_attr_double(hid_t obj, const std::string& name, const std::string& file) {
  auto v = read_attr_vec<double>(obj, name, file, H5T_NATIVE_DOUBLE, true);
  if (v.size() != 1) throw InputError(file, name, "expected a scalar attribute");
  return v[0];
}
std::int64_t read_attr_int(hid_t obj, const std::string& name, const std::string& file) {
  auto v = read_attr_vec<std::int64_t>(obj, name, file, H5T_NATIVE_INT64, false);
  if (v.size() != 1) throw InputError(file, name, "expected a scalar integer attribute");
  return v[0];
}
std::vector<double> read_attr_doubles(hid_t obj, const std::string& name, const std::string& file) {
  return read_attr_vec<double>(obj, name, file, H5T_NATIVE_DOUBLE, true);
}
std::vector<std::int64_t> read_attr_ints(hid_t obj, const std::string& name, const std::string& file) {
  return read_attr_vec<std::int64_t>(obj, name, file, H5T_NATIVE_INT64, false);
}

void write_dataset(hid_t loc, const std::string& name, const double* data, std::size_t rows,
                   std::size_t cols, const std::string& unit) {
  write_any(loc, name, data, rows, cols, unit, H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE);
}
void write_dataset(hid_t loc, const std::string& name, const std::uint64_t* data,
                   std::size_t rows, std::size_t cols, const std::string& unit) {
  write_any(loc, name, data, rows, cols, unit, H5T_NATIVE_UINT64, H5T_STD_U64LE);
}
void write_dataset(hid_t loc, const std::string& name, const std::int32_t* data,
                   std::size_t rows, std::size_t cols, const std::string& unit) {
  write_any(loc, name, data, rows, cols, unit, H5T_NATIVE_INT32, H5T_STD_I32LE);
}
void write_dataset(hid_t loc, const std::string& name, const std::int64_t* data,
                   std::size_t rows, std::size_t cols, const std::string& unit) {
  write_any(loc, name, data, rows, cols, unit, H5T_NATIVE_INT64, H5T_STD_I64LE);
}

bool write_dataset_rows(hid_t loc, const std::string& name, const double* data, std::size_t rows,
                        std::size_t cols, const std::string& unit, const RowBlock& block) {
  return write_block(loc, name, data, rows, cols, unit, block, H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE);
}
bool write_dataset_rows(hid_t loc, const std::string& name, const std::uint64_t* data, std::size_t rows,
                        std::size_t cols, const std::string& unit, const RowBlock& block) {
  return write_block(loc, name, data, rows, cols, unit, block, H5T_NATIVE_UINT64, H5T_STD_U64LE);
}
bool write_dataset_rows(hid_t loc, const std::string& name, const std::int32_t* data, std::size_t rows,
                        std::size_t cols, const std::string& unit, const RowBlock& block) {
  return write_block(loc, name, data, rows, cols, unit, block, H5T_NATIVE_INT32, H5T_STD_I32LE);
}

std::vector<double> read_doubles(hid_t loc, const std::string& name, long long rows,
                                 std::size_t cols, const std::string& file) {
  return read_any<double>(loc, name, rows, cols, file, H5T_NATIVE_DOUBLE, Kind::real);
}
std::vector<std::uint64_t> read_u64(hid_t loc, const std::string& name, long long rows,
                                    std::size_t cols, const std::string& file) {
  return read_any<std::uint64_t>(loc, name, rows, cols, file, H5T_NATIVE_UINT64, Kind::uint64);
}
std::vector<std::int32_t> read_i32(hid_t loc, const std::string& name, long long rows,
                                   std::size_t cols, const std::string& file) {
  return read_any<std::int32_t>(loc, name, rows, cols, file, H5T_NATIVE_INT32, Kind::integer);
}
std::vector<std::int64_t> read_i64(hid_t loc, const std::string& name, long long rows,
                                   std::size_t cols, const std::string& file) {
  return read_any<std::int64_t>(loc, name, rows, cols, file, H5T_NATIVE_INT64, Kind::integer);
}

std::vector<double> read_doubles(hid_t loc, const std::string& name, long long rows, std::size_t cols,
                                 const std::string& file, const RowRange& range) {
  return read_any<double>(loc, name, rows, cols, file, H5T_NATIVE_DOUBLE, Kind::real, &range);
}
std::vector<std::uint64_t> read_u64(hid_t loc, const std::string& name, long long rows, std::size_t cols,
                                    const std::string& file, const RowRange& range) {
  return read_any<std::uint64_t>(loc, name, rows, cols, file, H5T_NATIVE_UINT64, Kind::uint64, &range);
}
std::vector<std::int32_t> read_i32(hid_t loc, const std::string& name, long long rows, std::size_t cols,
                                   const std::string& file, const RowRange& range) {
  return read_any<std::int32_t>(loc, name, rows, cols, file, H5T_NATIVE_INT32, Kind::integer, &range);
}

std::vector<hsize_t> shape(hid_t loc, const std::string& name, const std::string& file) {
  if (!exists(loc, name)) throw InputError(file, name, "dataset is missing");
  Handle ds(H5Dopen2(loc, name.c_str(), H5P_DEFAULT));
  if (!ds.valid()) throw InputError(file, name, "cannot open dataset");
  Handle space(H5Dget_space(ds));
  const int nd = H5Sget_simple_extent_ndims(space);
  std::vector<hsize_t> d(nd > 0 ? nd : 0);
  if (nd > 0) H5Sget_simple_extent_dims(space, d.data(), nullptr);
  return d;
}

std::size_t rows(hid_t loc, const std::string& name, const std::string& file) {
  if (!exists(loc, name)) throw InputError(file, name, "required dataset is missing");
  const std::vector<hsize_t> d = shape(loc, name, file);
  if (d.empty()) throw InputError(file, name, "wrong shape " + shape_str(d) + ", expected (N,) or (N, k)");
  return static_cast<std::size_t>(d[0]);
}

std::string unit_of(hid_t loc, const std::string& name) {
  if (!exists(loc, name)) return {};
  Handle ds(H5Dopen2(loc, name.c_str(), H5P_DEFAULT));
  if (!ds.valid() || !has_attr(ds, "unit")) return {};
  return read_attr_string(ds, "unit", "");
}

void write_provenance(hid_t file, const Provenance& p) {
  Handle g = create_group(file, "provenance");
  write_attr(g, "tool", p.tool);
  write_attr(g, "version", p.version);
  write_attr(g, "git_sha", p.git_sha);
  write_attr(g, "command_line", p.command_line);
  write_attr(g, "scene", p.scene_toml);
}

Provenance read_provenance(hid_t file, const std::string& path) {
  Provenance p;
  if (!exists(file, "provenance")) return p;
  Handle g = open_group(file, "provenance", path);
  auto get = [&](const char* k) { return has_attr(g, k) ? read_attr_string(g, k, path) : std::string(); };
  p.tool = get("tool");
  p.version = get("version");
  p.git_sha = get("git_sha");
  p.command_line = get("command_line");
  p.scene_toml = get("scene");
  return p;
}

}  // namespace common::h5
