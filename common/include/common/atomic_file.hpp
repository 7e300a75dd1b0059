/// @file atomic_file.hpp
/// Write-to-temporary-then-rename, so that an interrupted or failed run never leaves a half
/// file under the final name and never destroys an existing result (ecosystem.md §4.4).
#pragma once
#include <fstream>
#include <string>
#include <utility>
#include <vector>

namespace common {

/// Owns a temporary path next to `final_path` (same directory, so rename(2) is atomic).
/// Write to `temp_path()`, then call `commit()`; if `commit()` is never reached the
/// temporary file is removed by the destructor and `final_path` is untouched.
class AtomicPath {
 public:
  explicit AtomicPath(std::string final_path);
  ~AtomicPath();
  AtomicPath(const AtomicPath&) = delete;
  AtomicPath& operator=(const AtomicPath&) = delete;

  const std::string& temp_path() const { return temp_; }
  const std::string& final_path() const { return final_; }
  /// fsync the temporary file and rename it onto the final path. Throws IoError on failure.
  void commit();

 private:
  std::string final_;
  std::string temp_;
  bool committed_ = false;
};

/// Check that `path` can become an output before anything is written (AtomicPath and PartialFile
/// call it; a tool may call it first for every output it will write). An existing path that is not
/// a regular file or a directory (FIFO, device node such as /dev/null, socket) is refused with
/// InputError (exit 2; rename(2) would replace it, opening a FIFO blocks); a path that can never be
/// created (a component over NAME_MAX, a file used as a directory) with IoError (exit 4).
void check_output_path(const std::string& path);

/// Atomically replace `path` with `text`. Throws IoError.
void write_text_atomic(const std::string& path, const std::string& text);

/// Replace a set of files (path, text) as a whole: every text is written to its temporary file
/// first; only when all succeeded are they renamed into place, in the given order (put the file
/// whose presence marks a complete set last). A failed write (disk full) removes the temporaries
/// and leaves every earlier file as it was. Throws IoError.
void write_text_set_atomic(const std::vector<std::pair<std::string, std::string>>& files);

/// A file that grows during a long run (a time-series CSV). Rows go to `<final>.partial` in the
/// same directory; commit() renames it onto the final name, so the final name only ever holds
/// the series of a run that completed or stopped in a controlled way (numerical failure after
/// saving its state, signal after a checkpoint). A run that never commits (I/O failure, crash)
/// leaves the earlier `final` untouched and its own rows in the `.partial` file, which the next
/// run overwrites.
class PartialFile {
 public:
  /// Create (truncate) `<final_path>.partial`. Throws IoError.
  explicit PartialFile(std::string final_path);
  PartialFile(const PartialFile&) = delete;
  PartialFile& operator=(const PartialFile&) = delete;

  static std::string partial_name(const std::string& final_path) { return final_path + ".partial"; }
  const std::string& final_path() const { return final_; }
  const std::string& partial_path() const { return partial_; }
  bool committed() const { return committed_; }

  /// The stream to write rows to (invalid after commit()).
  std::ostream& stream() { return out_; }
  /// Flush to the OS; throws IoError if a write has failed.
  void flush();
  /// Flush, fsync, close and rename onto the final path. Throws IoError.
  void commit();

 private:
  std::string final_;
  std::string partial_;
  std::ofstream out_;
  bool committed_ = false;
};

}  // namespace common
