/// @file run_directory.cpp
/// Implementation of mpm/run_directory.hpp (the header states the contract).
#include "mpm/run_directory.hpp"

#include <cstdio>
#include <filesystem>

namespace mpmfrag {

std::string snap_name(const RunConfig& run, const std::string& tag, std::int64_t step) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "_%s%06lld.h5", tag.c_str(), static_cast<long long>(step));
  return (std::filesystem::path(run.out_dir) / (run.prefix + buf)).string();
}

std::int64_t snap_step(const std::string& prefix, const std::string& n) {
  const std::string p = prefix + "_";
  if (n.rfind(p, 0) != 0) return -1;
  const std::size_t dot = n.rfind('.');
  if (dot == std::string::npos || dot == p.size() || (n.substr(dot) != ".h5" && n.substr(dot) != ".xmf")) return -1;
  const std::string digits = n.substr(p.size(), dot - p.size());
  if (digits.size() > 15 || digits.find_first_not_of("0123456789") != std::string::npos) return -1;
  return std::stoll(digits);
}

std::unique_ptr<common::RunDirectory> open_run_directory(const RunConfig& run, const std::string& restart) {
  const std::string prefix = run.prefix + "_";
  return std::make_unique<common::RunDirectory>(
      run.out_dir, "mpm-frag",
      [prefix](const std::string& n) {
        return n.rfind(prefix, 0) == 0 && (n.ends_with(".h5") || n.ends_with(".xmf") || n.ends_with(".csv") ||
                                           n.ends_with(".partial"));
      },
      restart.empty() ? std::string() : common::RunDirectory::staging_of(run.out_dir, restart));
}

void carry_snapshots(common::RunDirectory& rd, const RunConfig& run, const std::string& restart, std::int64_t step) {
  if (restart.empty() || !common::RunDirectory::staging_of(run.out_dir, restart).empty()) return;
  for (const auto& e : std::filesystem::directory_iterator(run.out_dir)) {
    const std::string n = e.path().filename().string();
    const std::int64_t s = snap_step(run.prefix, n);
    if (s >= 0 && s <= step) rd.carry(n);
  }
}

}  // namespace mpmfrag
