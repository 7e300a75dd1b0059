/// @file status.cpp
/// Implementation of common/status.hpp (the header states the contract, and for physics the equations and sources).
#include "common/status.hpp"

namespace common {

namespace {
std::string join_where(const std::string& file, const std::string& key, const std::string& problem) {
  std::string s;
  if (!file.empty()) s += file + ": ";
  if (!key.empty()) s += key + ": ";
  return s + problem;
}
}  // namespace

InputError::InputError(const std::string& file, const std::string& key, const std::string& problem)
    : std::runtime_error(join_where(file, key, problem)) {}

}  // namespace common
