/// @file log.hpp
/// Logging through spdlog (stderr) and a progress reporter for long runs.
#pragma once
#include <chrono>
#include <cstdint>
#include <string>

namespace common {

/// quiet: warnings and errors only; verbose: debug; otherwise info.
void setup_logging(bool quiet, bool verbose);

/// Prints "step, simulated time, dt, energy error, ETA" at a fixed wall-clock interval.
class Progress {
 public:
  /// `t_end` is the simulated end time (s); `interval_s` the wall-clock interval between lines.
  Progress(std::string label, double t_start, double t_end, double interval_s = 10.0);
  /// Log a line if the interval has elapsed (or `force`). Returns whether it logged.
  bool update(std::int64_t step, double t, double dt, double energy_rel_error, bool force = false);
  /// Wall-clock seconds since construction.
  double elapsed() const;

 private:
  std::string label_;
  double t_start_, t_end_, interval_;
  std::chrono::steady_clock::time_point start_, last_;
};

}  // namespace common
