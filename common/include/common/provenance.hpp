/// @file provenance.hpp
/// What every output records: tool, version, git SHA, command line, fully resolved scene.
#pragma once
#include <string>

namespace common {

struct Provenance {
  std::string tool;          ///< "mpm-frag", "mpm2spheres", "ssdem-grav"
  std::string version;       ///< project version
  std::string git_sha;       ///< commit the binary was built from ("+dirty" if modified)
  std::string command_line;  ///< argv joined with spaces (shell-quoted where needed)
  std::string scene_toml;    ///< fully resolved scene text
};

/// Version string of the suite ("0.1.0").
const char* version();
/// Git SHA the library was built from.
const char* git_sha();

/// Provenance of this process.
Provenance make_provenance(const std::string& tool, int argc, const char* const* argv,
                           const std::string& scene_toml);

/// "tool version (sha)" line for --version.
std::string version_line(const std::string& tool);

}  // namespace common
