/// @file atomic_file.hpp
/// Write-to-temporary-then-rename, so that an interrupted or failed run never leaves a half
/// file under the final name and never destroys an existing result (ecosystem.md §4.4).
#pragma once
#include <string>

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

/// Atomically replace `path` with `text`. Throws IoError.
void write_text_atomic(const std::string& path, const std::string& text);

}  // namespace common
