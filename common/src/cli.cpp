/// @file cli.cpp
/// Implementation of common/cli.hpp (the header states the contract, and for physics the equations and sources).
#include "common/cli.hpp"

#include <spdlog/spdlog.h>

#include <cerrno>
#include <filesystem>
#include <iostream>
#include <new>

#include "common/h5.hpp"
#include "common/log.hpp"
#include "common/status.hpp"

namespace common {

ToolApp::ToolApp(std::string tool, std::string description, Schema schema, bool scene_required)
    : tool_(std::move(tool)), schema_(std::move(schema)), scene_required_(scene_required),
      app_(std::move(description), tool_) {
  app_.add_option("--scene,-s", scene_path_, "Scene file (TOML)")->check(CLI::ExistingFile);
  app_.add_option("--set", sets_, "Override a scene value: key=value (TOML value), repeatable")
      ->take_all()->allow_extra_args(false);
  app_.add_flag("--help-params", help_params_, "Print every scene parameter (type, default, unit, range) and exit");
  app_.add_flag("--print-scene", print_scene_, "Print the fully resolved scene and exit");
  app_.add_flag("--version", version_, "Print version and git SHA and exit");
  app_.add_flag("--quiet,-q", quiet_, "Only warnings and errors");
  app_.add_flag("--verbose,-v", verbose_, "Debug output");
}

void ToolApp::add_scene_flag(const std::string& flag, const std::string& key, const std::string& help) {
  auto value = std::make_shared<std::string>();
  CLI::Option* opt = app_.add_option(flag, *value, help + " (scene key " + key + ")");
  scene_flags_.push_back({key, value, opt});
}

int ToolApp::run(int argc, char** argv, const Body& body) {
  try {
    app_.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app_.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app_.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << tool_ << ": error: " << e.what() << "\n(run " << tool_ << " --help for usage)\n";
    return to_int(ExitCode::bad_input);
  }
  if (version_) {
    std::cout << version_line(tool_) << "\n";
    return 0;
  }
  if (help_params_) {
    std::cout << schema_.help_text();
    return 0;
  }
  std::vector<std::string> overrides;
  for (const auto& f : scene_flags_) {
    if (f.option->count() == 0) continue;
    // String and choice keys are quoted (file names stay strings); others are TOML values.
    const ParamSpec* spec = schema_.find(f.key);
    const bool quote = spec && (spec->type == ParamType::string || spec->type == ParamType::choice);
    std::string v = *f.value;
    if (quote) {
      std::string q = "\"";
      for (char c : v) q += (c == '"' || c == '\\') ? std::string("\\") + c : std::string(1, c);
      v = q + "\"";
    }
    overrides.push_back(f.key + "=" + v);
  }
  overrides.insert(overrides.end(), sets_.begin(), sets_.end());
  setup_logging(quiet_, verbose_);
  h5::quiet_errors();
  try {
    if (scene_path_.empty() && scene_required_ && !print_scene_) {
      throw InputError("", "--scene", "a scene file is required (see --help-params for its keys)");
    }
    Scene scene = scene_path_.empty() ? Scene::parse(schema_, "", "<command line>", overrides)
                                      : Scene::load(schema_, scene_path_, overrides);
    if (print_scene_) {
      std::cout << scene.to_toml();
      return 0;
    }
    const Provenance prov = make_provenance(tool_, argc, argv, scene.to_toml());
    return body(scene, prov);
  } catch (const InputError& e) {
    spdlog::error("{}", e.what());
    return to_int(ExitCode::bad_input);
  } catch (const NumericalError& e) {
    spdlog::error("numerical failure: {}", e.what());
    if (!e.saved_state().empty()) spdlog::error("last good state saved to {}", e.saved_state());
    return to_int(ExitCode::numerical);
  } catch (const IoError& e) {
    spdlog::error("I/O failure: {}", e.what());
    return to_int(ExitCode::io_failure);
  } catch (const std::filesystem::filesystem_error& e) {
    // A path the OS refuses. One that can never name a file (a component over NAME_MAX, a file
    // used as a directory, missing) is bad input (2); anything else (permission, read-only or
    // full file system) an I/O failure (4).
    const int c = e.code().value();
    const bool bad = e.code().category() == std::generic_category() || e.code().category() == std::system_category()
                         ? (c == ENAMETOOLONG || c == ENOTDIR || c == ENOENT || c == ELOOP || c == EINVAL)
                         : false;
    spdlog::error("{}{}: {}", bad ? "" : "I/O failure: ", e.path1().string(), e.code().message());
    return to_int(bad ? ExitCode::bad_input : ExitCode::io_failure);
  } catch (const std::bad_alloc&) {
    spdlog::error("out of memory: the input is too large for this machine (or the memory limit is too low)");
    return to_int(ExitCode::io_failure);
  } catch (const std::exception& e) {
    spdlog::critical("internal error (please report): {}", e.what());
    return 1;
  }
}

}  // namespace common
