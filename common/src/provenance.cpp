/// @file provenance.cpp
/// Implementation of common/provenance.hpp (the header states the contract, and for physics the equations and sources).
#include "common/provenance.hpp"

#include <string>

namespace common {

namespace {
std::string shell_quote(const std::string& s) {
  if (s.empty()) return "''";
  bool plain = true;
  for (char c : s)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || std::string("-_./=:,+@%").find(c) != std::string::npos))
      plain = false;
  if (plain) return s;
  std::string q = "'";
  for (char c : s) q += (c == '\'') ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}
}  // namespace

Provenance make_provenance(const std::string& tool, int argc, const char* const* argv,
                           const std::string& scene_toml) {
  Provenance p;
  p.tool = tool;
  p.version = version();
  p.git_sha = git_sha();
  for (int i = 0; i < argc; ++i) {
    if (i) p.command_line += ' ';
    p.command_line += shell_quote(argv[i] ? argv[i] : "");
  }
  p.scene_toml = scene_toml;
  return p;
}

std::string version_line(const std::string& tool) {
  return tool + " " + version() + " (git " + git_sha() + ")";
}

}  // namespace common
