/// @file cli.hpp
/// The command-line contract shared by the three tools:
///   <tool> [--scene FILE] [--set key=value ...] [--help-params] [--print-scene] [--version]
///          [--quiet|--verbose] <tool-specific flags>
/// and the mapping of exceptions to exit codes (status.hpp): InputError and CLI parse errors
/// -> 2, NumericalError -> 3, IoError -> 4, anything else -> 1 (internal error, a bug).
#pragma once
#include <CLI/CLI.hpp>
#include <functional>
#include <memory>
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
  /// A convenience flag that sets a scene key: `--flag V` is `--set key=V` (explicit --set
  /// options given on the same command line win). The value is taken as TOML, or as a string.
  void add_scene_flag(const std::string& flag, const std::string& key, const std::string& help);
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
  struct SceneFlag {
    std::string key;
    std::shared_ptr<std::string> value;
    CLI::Option* option;
  };
  std::vector<SceneFlag> scene_flags_;
  bool help_params_ = false, print_scene_ = false, version_ = false;
  bool quiet_ = false, verbose_ = false;
};

}  // namespace common
