/// @file status.hpp
/// Exit codes and error types shared by mpm-frag, mpm2spheres and ssdem-grav.
///
/// | code | meaning                                                                |
/// |------|------------------------------------------------------------------------|
/// | 0    | success                                                                |
/// | 2    | bad input: usage, scene file, input HDF5 file (also corrupt), a path   |
/// |      | that is not a regular file or that the OS refuses as a name            |
/// | 3    | numerical failure (NaN, inverted element, runaway overlap); the last   |
/// |      | good state has been saved before exiting                               |
/// | 4    | I/O or resource failure (cannot create, write or rename an output,     |
/// |      | disk full, out of memory)                                              |
#pragma once
#include <stdexcept>
#include <string>

namespace common {

enum class ExitCode : int { success = 0, bad_input = 2, numerical = 3, io_failure = 4 };

/// Bad input: a scene value, a flag, or an input file. The message names the file, the key
/// and what is allowed. Maps to exit code 2.
class InputError : public std::runtime_error {
 public:
  explicit InputError(const std::string& what) : std::runtime_error(what) {}
  /// "<file>: <key>: <problem>" with empty parts left out.
  InputError(const std::string& file, const std::string& key, const std::string& problem);
};

/// A numerical failure detected by a solver (NaN/Inf, J <= 0, overlap beyond the radius...).
/// Maps to exit code 3. The thrower is responsible for saving the last good state first
/// (or `saved_state` names the file it saved).
class NumericalError : public std::runtime_error {
 public:
  explicit NumericalError(const std::string& what, std::string saved_state = {})
      : std::runtime_error(what), saved_state_(std::move(saved_state)) {}
  const std::string& saved_state() const { return saved_state_; }
  void set_saved_state(std::string s) { saved_state_ = std::move(s); }

 private:
  std::string saved_state_;
};

/// Output could not be written (open, write, fsync or rename failed). Maps to exit code 4.
class IoError : public std::runtime_error {
 public:
  explicit IoError(const std::string& what) : std::runtime_error(what) {}
};

/// Integer value of an exit code.
constexpr int to_int(ExitCode c) { return static_cast<int>(c); }

}  // namespace common
