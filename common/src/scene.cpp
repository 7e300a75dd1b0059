/// @file scene.cpp
/// Scene: TOML parsing (toml++), --set overrides, validation against a Schema, accessors.
#include <spdlog/spdlog.h>
#include <toml++/toml.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "common/schema.hpp"
#include "common/status.hpp"
#include "scene_data.hpp"

namespace common {

namespace {

using scene_detail::apply_override;
using scene_detail::as_number;
using scene_detail::lookup;
using scene_detail::validate;

template <class F>
auto get_checked(const SceneData& d, const std::string& key, ParamType want, F&& convert) {
  const ParamSpec* p = d.find(key);
  if (!p) throw InputError(d.source, d.prefix + key, "not a key of this scene's schema (internal error)");
  const bool ok = p->type == want || (want == ParamType::string && p->type == ParamType::choice);
  if (!ok) throw InputError(d.source, d.prefix + key, "accessed with the wrong type (internal error)");
  const toml::node* n = lookup(d.table, key);
  if (!n) throw InputError(d.source, d.prefix + key, "missing after validation (internal error)");
  return convert(*n);
}

}  // namespace

Scene::Scene() : d_(std::make_unique<SceneData>()) {}
Scene::~Scene() = default;
Scene::Scene(const Scene& o) : d_(std::make_unique<SceneData>(*o.d_)) {
  // `active` points into schema-owned memory shared by copies: still valid.
}
Scene& Scene::operator=(const Scene& o) {
  if (this != &o) d_ = std::make_unique<SceneData>(*o.d_);
  return *this;
}
Scene::Scene(Scene&&) noexcept = default;
Scene& Scene::operator=(Scene&&) noexcept = default;

Scene Scene::parse(const Schema& schema, const std::string& toml_text, const std::string& source_name,
                   const std::vector<std::string>& overrides) {
  Scene s;
  s.d_->source = source_name;
  s.d_->schema = std::make_shared<Schema>(schema);
  try {
    s.d_->table = toml::parse(toml_text, source_name);
  } catch (const toml::parse_error& e) {
    std::ostringstream o;
    o << "TOML syntax error at line " << e.source().begin.line << ", column " << e.source().begin.column
      << ": " << e.description();
    throw InputError(source_name, "", o.str());
  }
  auto overridden = std::make_shared<std::set<std::string>>();
  for (const auto& ov : overrides) {
    apply_override(s.d_->table, ov);
    overridden->insert(ov.substr(0, ov.find('=')));
  }
  s.d_->overridden = std::move(overridden);
  validate(*s.d_);
  return s;
}

Scene Scene::load(const Schema& schema, const std::string& path, const std::vector<std::string>& overrides) {
  std::error_code ec;  // a FIFO would block the read forever
  if (std::filesystem::exists(path, ec) && !std::filesystem::is_regular_file(path, ec))
    throw InputError(path, "", "not a regular file (a FIFO, device or directory): cannot read a scene from it");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "", "cannot open scene file");
  std::ostringstream text;
  text << in.rdbuf();
  return parse(schema, text.str(), path, overrides);
}

double Scene::real(const std::string& key) const {
  return get_checked(*d_, key, ParamType::real, [](const toml::node& n) { return *as_number(n); });
}
long long Scene::integer(const std::string& key) const {
  return get_checked(*d_, key, ParamType::integer, [](const toml::node& n) { return static_cast<long long>(n.as_integer()->get()); });
}
bool Scene::boolean(const std::string& key) const {
  return get_checked(*d_, key, ParamType::boolean, [](const toml::node& n) { return n.as_boolean()->get(); });
}
std::string Scene::string(const std::string& key) const {
  return get_checked(*d_, key, ParamType::string, [](const toml::node& n) { return n.as_string()->get(); });
}
Eigen::Vector3d Scene::vec3(const std::string& key) const {
  return get_checked(*d_, key, ParamType::vec3, [](const toml::node& n) {
    const toml::array& a = *n.as_array();
    return Eigen::Vector3d(*as_number(a[0]), *as_number(a[1]), *as_number(a[2]));
  });
}
std::vector<double> Scene::real_list(const std::string& key) const {
  return get_checked(*d_, key, ParamType::real_list, [](const toml::node& n) {
    std::vector<double> v;
    for (const auto& e : *n.as_array()) v.push_back(*as_number(e));
    return v;
  });
}
bool Scene::given(const std::string& key) const { return d_->given.count(key) > 0; }
bool Scene::has(const std::string& key) const { return d_->find(key) != nullptr; }

std::size_t Scene::count(const std::string& key) const {
  if (!d_->find_array(key)) throw InputError(d_->source, d_->prefix + key, "not a table array of this schema (internal error)");
  const toml::node* n = lookup(d_->table, key);
  return n && n->as_array() ? n->as_array()->size() : 0;
}

Scene Scene::element(const std::string& key, std::size_t i) const {
  const TableArraySpec* a = d_->find_array(key);
  if (!a) throw InputError(d_->source, d_->prefix + key, "not a table array of this schema (internal error)");
  const toml::node* n = lookup(d_->table, key);
  if (!n || !n->as_array() || i >= n->as_array()->size())
    throw InputError(d_->source, d_->prefix + key, "index " + std::to_string(i) + " out of range (internal error)");
  Scene e;
  e.d_->table = *(*n->as_array())[i].as_table();
  e.d_->schema = a->element;
  e.d_->source = d_->source;
  e.d_->prefix = d_->prefix + key + "[" + std::to_string(i) + "].";
  validate(*e.d_);  // already valid: re-resolves the active styles
  e.d_->element_given = d_->element_given;
  e.d_->given = d_->element_given[e.d_->prefix];
  return e;
}

std::string Scene::to_toml() const {
  std::ostringstream o;
  o << d_->table << "\n";
  return o.str();
}

void Scene::throw_not_in_table(const std::string& key, const std::string& value) const {
  throw InputError(d_->source, d_->prefix + key,
                   "value \"" + value + "\" is not in the choice table it is read with (internal error)");
}

const std::string& Scene::source() const { return d_->source; }
std::string Scene::where(const std::string& key) const { return d_->source + ": " + d_->prefix + key; }

}  // namespace common
