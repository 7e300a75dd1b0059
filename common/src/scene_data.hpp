/// @file scene_data.hpp
/// The resolved TOML tree behind common::Scene and the scene-building steps shared by scene.cpp
/// (parsing, accessors) and scene_validate.cpp (aliases, --set overrides, validation against the
/// schema). Internal to common/src.
#pragma once
#include <toml++/toml.h>

#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "common/schema.hpp"

namespace common {

class SceneData {
 public:
  toml::table table;
  std::shared_ptr<const Schema> schema;  // element or root schema (without styles)
  std::vector<const Schema*> active;     // schema + active style schemas
  std::string source;
  std::string prefix;                    // "body[1]." for elements
  std::set<std::string> given;
  std::map<std::string, std::set<std::string>> element_given;  // by element prefix
  std::shared_ptr<const std::set<std::string>> overridden;      // keys set by --set, as written

  const ParamSpec* find(const std::string& key) const {
    for (const Schema* s : active)
      if (const ParamSpec* p = s->find(key)) return p;
    return nullptr;
  }
  const TableArraySpec* find_array(const std::string& key) const {
    for (const Schema* s : active)
      if (const TableArraySpec* a = s->find_array(key)) return a;
    return nullptr;
  }
};

namespace scene_detail {

/// The node at dotted `key` of `t`, or null.
const toml::node* lookup(const toml::table& t, const std::string& key);
/// A TOML integer or float as a double (empty for other node types).
std::optional<double> as_number(const toml::node& n);
/// Apply one `key=value` override (TOML value; `a[1].b` reaches into arrays of tables).
void apply_override(toml::table& root, const std::string& ov);
/// Resolve aliases, check every key against the active schemas, fill defaults (InputError naming
/// the source and key on any problem).
void validate(SceneData& d);

}  // namespace scene_detail
}  // namespace common
