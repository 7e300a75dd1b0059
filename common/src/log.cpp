/// @file log.cpp
/// Implementation of common/log.hpp (the header states the contract, and for physics the equations and sources).
#include "common/log.hpp"

#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <cmath>

namespace common {

void setup_logging(bool quiet, bool verbose) {
  auto logger = spdlog::get("suite");
  if (!logger) logger = spdlog::stderr_color_mt("suite");
  spdlog::set_default_logger(logger);
  spdlog::set_pattern("[%H:%M:%S] [%^%l%$] %v");
  spdlog::set_level(quiet ? spdlog::level::warn : verbose ? spdlog::level::debug : spdlog::level::info);
}

Progress::Progress(std::string label, double t_start, double t_end, double interval_s)
    : label_(std::move(label)), t_start_(t_start), t_end_(t_end), interval_(interval_s),
      start_(std::chrono::steady_clock::now()), last_(start_) {}

double Progress::elapsed() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

bool Progress::update(std::int64_t step, double t, double dt, double energy_rel_error, bool force) {
  const auto now = std::chrono::steady_clock::now();
  if (!force && std::chrono::duration<double>(now - last_).count() < interval_) return false;
  last_ = now;
  const double wall = elapsed();
  const double frac = (t_end_ > t_start_) ? (t - t_start_) / (t_end_ - t_start_) : 1.0;
  const double eta = (frac > 1e-12) ? wall * (1.0 - frac) / frac : NAN;
  spdlog::info("{} step {} t = {:.6e} s ({:.1f} %) dt = {:.3e} s dE/E0 = {:+.3e} wall {:.1f} s ETA {:.1f} s",
               label_, step, t, 100.0 * frac, dt, energy_rel_error, wall, eta);
  return true;
}

}  // namespace common
