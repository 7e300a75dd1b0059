/// @file h5_check.cpp
/// Implementation of h5_check.hpp: declared-size bounds and the whole-file read in a child process.
#include "h5_check.hpp"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <sstream>
#include <vector>

#include "common/h5.hpp"
#include "common/status.hpp"

namespace common::h5::detail {

namespace {
/// Size of the file `obj` belongs to (0 if unknown: then nothing is bounded).
hsize_t file_size_of(hid_t obj) {
  Handle f(H5Iget_file_id(obj));
  hsize_t size = 0;
  if (!f.valid() || H5Fget_filesize(f, &size) < 0) return 0;
  return size;
}

/// Bytes that `npoints` elements of `type` take in the file if stored unfiltered, or "" if that
/// fits in `file_size`; otherwise the problem. Filtered (compressed) datasets are not bounded.
std::string declared_size_problem(hsize_t npoints, hid_t type, hsize_t file_size, bool filtered) {
  const std::size_t elem = H5Tget_size(type);
  hsize_t bytes = 0;
  if (elem == 0 || __builtin_mul_overflow(npoints, static_cast<hsize_t>(elem), &bytes))
    return "declares " + std::to_string(npoints) + " elements of " + std::to_string(elem) + " bytes (impossible size)";
  if (filtered || file_size == 0 || bytes <= file_size) return {};  // 0: size unknown
  return "declares " + std::to_string(npoints) + " elements of " + std::to_string(elem) + " bytes (" +
         std::to_string(bytes) + " bytes), more than the whole file holds (" + std::to_string(file_size) +
         " bytes): truncated or corrupt file";
}

bool has_filters(hid_t ds) {
  Handle dcpl(H5Dget_create_plist(ds));
  return dcpl.valid() && H5Pget_nfilters(dcpl) > 0;
}

// ---- validation of an input file in a child process ---------------------------------------
// A damaged HDF5 file can make libhdf5 crash (a flipped global-heap address: SIGSEGV inside
// H5HG_read) or loop forever (a corrupt object header). libhdf5 cannot be made safe against that
// from outside, so open_file_read() first reads *everything* in the file (every object, every
// attribute, every dataset's data, as the readers would) in a forked child under a time limit; only
// if the child finishes cleanly does the calling process open the file. The parent's own reads then
// follow the same code paths over the same bytes, which the child has just survived.

struct DeepRead {
  hsize_t file_size = 0;
  std::string problem;
};

/// Read all elements of an attribute (`is_attr`) or dataset in their native memory type.
bool read_everything(hid_t obj, hid_t type, hid_t space, bool is_attr, bool filtered, const std::string& where,
                     DeepRead& ctx) {
  const hssize_t n = H5Sget_simple_extent_npoints(space);
  if (n < 0) return ctx.problem = where + ": unreadable dataspace", false;
  Handle mem(H5Tget_native_type(type, H5T_DIR_DEFAULT));
  if (!mem.valid()) return ctx.problem = where + ": unreadable datatype", false;
  std::string p = declared_size_problem(static_cast<hsize_t>(n), type, ctx.file_size, filtered);
  if (p.empty()) p = declared_size_problem(static_cast<hsize_t>(n), mem, ctx.file_size * 16 + (1u << 20), filtered);
  if (!p.empty()) return ctx.problem = where + ": " + p, false;
  if (n == 0) return true;
  std::unique_ptr<unsigned char[]> buf(new unsigned char[static_cast<std::size_t>(n) * H5Tget_size(mem)]);
  const herr_t rc = is_attr ? H5Aread(obj, mem, buf.get()) : H5Dread(obj, mem, H5S_ALL, H5S_ALL, H5P_DEFAULT, buf.get());
  if (rc < 0) return ctx.problem = where + ": cannot read " + (is_attr ? "attribute" : "dataset"), false;
  return true;  // variable-length data is left to the child's exit
}

herr_t deep_read_attr(hid_t loc, const char* name, const H5A_info_t*, void* op) {
  auto& ctx = *static_cast<DeepRead*>(op);
  Handle a(H5Aopen(loc, name, H5P_DEFAULT));
  if (!a.valid()) return ctx.problem = std::string("attribute ") + name + ": cannot open", -1;
  Handle type(H5Aget_type(a));
  Handle space(H5Aget_space(a));
  if (!type.valid() || !space.valid()) return ctx.problem = std::string("attribute ") + name + ": unreadable", -1;
  return read_everything(a, type, space, true, false, std::string("attribute ") + name, ctx) ? 0 : -1;
}

herr_t deep_read_object(hid_t loc, const char* name, const H5O_info_t* info, void* op) {
  auto& ctx = *static_cast<DeepRead*>(op);
  const std::string where = std::string("/") + (std::strcmp(name, ".") == 0 ? "" : name);
  Handle obj(H5Oopen(loc, name, H5P_DEFAULT));
  if (!obj.valid()) return ctx.problem = where + ": cannot open object", -1;
  hsize_t idx = 0;
  if (H5Aiterate2(obj, H5_INDEX_NAME, H5_ITER_NATIVE, &idx, deep_read_attr, op) < 0) {
    if (ctx.problem.empty()) ctx.problem = where + ": cannot list attributes";
    ctx.problem = where + ": " + ctx.problem;
    return -1;
  }
  if (info->type == H5O_TYPE_DATASET) {
    Handle type(H5Dget_type(obj));
    Handle space(H5Dget_space(obj));
    if (!type.valid() || !space.valid()) return ctx.problem = where + ": unreadable dataset header", -1;
    if (!read_everything(obj, type, space, false, has_filters(obj), where, ctx)) return -1;
  }
  return 0;
}

/// Everything a reader could read, or the first problem ("" if none).
std::string deep_read(const std::string& path, hsize_t file_size) {
  if (H5Fis_hdf5(path.c_str()) <= 0) return "not an HDF5 file (or truncated/corrupt)";
  Handle f(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT));
  if (!f.valid()) return "cannot open HDF5 file (truncated or corrupt?)";
  DeepRead ctx;
  ctx.file_size = file_size;
  if (H5Ovisit2(f, H5_INDEX_NAME, H5_ITER_NATIVE, deep_read_object, &ctx, H5O_INFO_BASIC) < 0)
    return ctx.problem.empty() ? "cannot walk the objects of the file" : ctx.problem;
  return {};
}

/// Time allowed for the child: 10 s (or $SUITE_H5_CHECK_TIMEOUT_S) plus 1 s per 50 MB.
double check_time_limit(hsize_t file_size) {
  double base = 10.0;
  if (const char* e = std::getenv("SUITE_H5_CHECK_TIMEOUT_S")) {
    char* end = nullptr;
    const double v = std::strtod(e, &end);
    if (end != e && v > 0) base = v;
  }
  return base + static_cast<double>(file_size) / 50e6;
}

}  // namespace

/// Before allocating: a dataset cannot declare more unfiltered data than the file holds.
void check_declared_size(hid_t ds, hid_t type, hsize_t npoints, const std::string& file, const std::string& name) {
  const std::string problem = declared_size_problem(npoints, type, file_size_of(ds), has_filters(ds));
  if (!problem.empty()) throw InputError(file, name, problem);
}

void validate_in_child(const std::string& path, hsize_t file_size) {
  const std::string bad = "corrupt or unreadable HDF5 file (truncated or damaged): ";
  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0) throw IoError(path + ": cannot create a pipe to check the file: " + std::strerror(errno));
  const pid_t pid = ::fork();
  if (pid < 0) {
    const int err = errno;
    ::close(fds[0]);
    ::close(fds[1]);
    throw IoError(path + ": cannot start a process to check the file: " + std::strerror(err));
  }
  if (pid == 0) {  // child: no exit handlers, no stdio flushing (both belong to the parent)
    ::close(fds[0]);
    std::string problem;
    try {
      problem = deep_read(path, file_size);
    } catch (const std::bad_alloc&) {
      problem = "out of memory while reading it";
    } catch (...) {
      problem = "unexpected error while reading it";
    }
    std::size_t done = 0;
    while (done < problem.size()) {
      const ssize_t w = ::write(fds[1], problem.data() + done, problem.size() - done);
      if (w <= 0) break;
      done += static_cast<std::size_t>(w);
    }
    ::_exit(problem.empty() ? 0 : 2);
  }
  ::close(fds[1]);
  const double limit = check_time_limit(file_size);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(limit);
  std::string message;
  bool timed_out = false;
  for (;;) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now()).count();
    if (left <= 0) {
      timed_out = true;
      break;
    }
    pollfd p{fds[0], POLLIN, 0};
    const int r = ::poll(&p, 1, static_cast<int>(std::min<long long>(left, 1000)));
    if (r < 0 && errno == EINTR) continue;
    if (r <= 0) continue;
    char buf[512];
    const ssize_t got = ::read(fds[0], buf, sizeof buf);
    if (got < 0 && errno == EINTR) continue;
    if (got <= 0) break;  // EOF: the child has exited (or closed the pipe)
    message.append(buf, static_cast<std::size_t>(got));
  }
  ::close(fds[0]);
  if (timed_out) ::kill(pid, SIGKILL);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (timed_out) {
    std::ostringstream o;
    o << bad << "reading it did not finish within " << limit << " s";
    throw InputError(path, "", o.str());
  }
  if (WIFSIGNALED(status))
    throw InputError(path, "", bad + "the HDF5 library crashed reading it (signal " +
                                   std::to_string(WTERMSIG(status)) + ")");
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
    throw InputError(path, "", bad + (message.empty() ? "the check ended with status " + std::to_string(status) : message));
}

}  // namespace common::h5::detail
