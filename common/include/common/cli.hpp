/// @file cli.hpp
/// The command-line contract shared by the three tools:
///   <tool> [--scene FILE] [--set key=value ...] [--help-params] [--print-scene] [--version]
///          [--quiet|--verbose] <tool-specific flags>
/// and the mapping of exceptions to exit codes (status.hpp): InputError and CLI parse errors
/// -> 2, NumericalError -> 3, IoError -> 4, anything else -> 1 (internal error, a bug).
#pragma once
#include <CLI/CLI.hpp>
#include <functional>
#include <string>
#include <vector>

#include "common/provenance.hpp"
#include "common/schema.hpp"

namespace common {

class ToolApp {
 public:
  /// `scene_required`: whether --scene must be given (mpm2spheres can run from flags alone).
  ToolApp(std::string tool, std::string description, Schema schema, bool scene_required = true);

  /// Add tool-specific flags here before run().
  CLI::App& cli() { return app_; }
  const Schema& schema() const { return schema_; }

  using Body = std::function<int(const Scene& scene, const Provenance& prov)>;
  /// Parse argv, handle the standard flags, load and validate the scene, call `body`.
  /// Returns the process exit code; never throws.
  int run(int argc, char** argv, const Body& body);

 private:
  std::string tool_;
  Schema schema_;
  bool scene_required_;
  CLI::App app_;
  std::string scene_path_;
  std::vector<std::string> sets_;
  bool help_params_ = false, print_scene_ = false, version_ = false;
  bool quiet_ = false, verbose_ = false;
};

}  // namespace common
