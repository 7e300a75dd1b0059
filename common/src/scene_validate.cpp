/// @file scene_validate.cpp
/// Scene building steps behind common::Scene: dotted-key lookup, --set overrides, deprecated-key
/// aliases, unknown-key suggestions, range and type checks, defaults (declared in scene_data.hpp).
#include <spdlog/spdlog.h>
#include <toml++/toml.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <sstream>

#include "common/status.hpp"
#include "scene_data.hpp"

namespace common::scene_detail {


std::vector<std::string> split_dots(const std::string& key) {
  std::vector<std::string> parts;
  std::size_t start = 0;
  while (true) {
    const auto dot = key.find('.', start);
    parts.push_back(key.substr(start, dot - start));
    if (dot == std::string::npos) break;
    start = dot + 1;
  }
  return parts;
}

const toml::node* lookup(const toml::table& t, const std::string& key) {
  const toml::table* cur = &t;
  const auto parts = split_dots(key);
  for (std::size_t i = 0; i < parts.size(); ++i) {
    const toml::node* n = cur->get(parts[i]);
    if (!n) return nullptr;
    if (i + 1 == parts.size()) return n;
    cur = n->as_table();
    if (!cur) return nullptr;
  }
  return nullptr;
}

toml::table& table_for(toml::table& t, const std::string& key, std::string& leaf) {
  toml::table* cur = &t;
  const auto parts = split_dots(key);
  for (std::size_t i = 0; i + 1 < parts.size(); ++i) {
    toml::node* n = cur->get(parts[i]);
    if (!n) {
      cur->insert_or_assign(parts[i], toml::table{});
      n = cur->get(parts[i]);
    }
    cur = n->as_table();
    if (!cur) throw InputError("", key, "'" + parts[i] + "' must be a table");
  }
  leaf = parts.back();
  return *cur;
}

std::string num(double x) {
  std::ostringstream o;
  o.precision(10);
  o << x;
  return o.str();
}

std::string range_text(const ParamSpec& p) {
  std::string r(p.min_exclusive ? "(" : "[");
  r += num(p.min);
  r += ", ";
  r += num(p.max);
  r += "]";
  if (!p.unit.empty() && p.unit != "1") r += " " + p.unit;
  return r;
}

std::string node_text(const toml::node& n) {
  std::ostringstream o;
  if (auto s = n.as_string()) o << '"' << s->get() << '"';
  else if (n.is_table()) o << "a table";
  else if (n.is_array()) o << "an array";
  else n.visit([&](const auto& v) { o << v; });
  return o.str();
}

bool in_range(const ParamSpec& p, double x) {
  if (!std::isfinite(x)) return false;
  if (p.min_exclusive ? !(x > p.min) : !(x >= p.min)) return false;
  return x <= p.max;
}

std::optional<double> as_number(const toml::node& n) {
  if (auto f = n.as_floating_point()) return f->get();
  if (auto i = n.as_integer()) return static_cast<double>(i->get());
  return std::nullopt;
}

/// Check one present value; returns a normalised node to store.
void check_value(const ParamSpec& p, toml::table& parent, const std::string& leaf, const std::string& src,
                 const std::string& where) {
  const toml::node& n = *parent.get(leaf);
  auto fail = [&](const std::string& what) { throw InputError(src, where, what + ", got " + node_text(n)); };
  switch (p.type) {
    case ParamType::boolean:
      if (!n.is_boolean()) fail("expected true or false");
      break;
    case ParamType::integer: {
      if (!n.is_integer()) fail("expected an integer in " + range_text(p));
      if (!in_range(p, static_cast<double>(n.as_integer()->get()))) fail("out of range: allowed " + range_text(p));
      break;
    }
    case ParamType::real: {
      auto x = as_number(n);
      if (!x) fail("expected a number in " + range_text(p));
      if (!in_range(p, *x)) fail("out of range: allowed " + range_text(p));
      parent.insert_or_assign(leaf, *x);  // normalise integers to floating point
      break;
    }
    case ParamType::string:
      if (!n.is_string()) fail("expected a string");
      break;
    case ParamType::choice: {
      std::string list;
      for (const auto& c : p.choices) list += (list.empty() ? "" : ", ") + ("\"" + c + "\"");
      if (!n.is_string()) fail("expected one of " + list);
      const std::string v = n.as_string()->get();
      if (std::find(p.choices.begin(), p.choices.end(), v) == p.choices.end()) fail("expected one of " + list);
      break;
    }
    case ParamType::vec3:
    case ParamType::real_list: {
      const toml::array* a = n.as_array();
      const bool v3 = p.type == ParamType::vec3;
      const std::string what = v3 ? "expected an array of 3 numbers, each in " + range_text(p)
                                  : "expected an array of numbers, each in " + range_text(p);
      if (!a || (v3 && a->size() != 3)) fail(what);
      toml::array norm;
      for (const auto& e : *a) {
        auto x = as_number(e);
        if (!x || !in_range(p, *x)) fail(what);
        norm.push_back(*x);
      }
      parent.insert_or_assign(leaf, std::move(norm));
      break;
    }
  }
}

void insert_default(toml::table& parent, const std::string& leaf, const ParamValue& v) {
  std::visit(
      [&](const auto& x) {
        using T = std::decay_t<decltype(x)>;
        if constexpr (std::is_same_v<T, Eigen::Vector3d>) {
          parent.insert_or_assign(leaf, toml::array{x[0], x[1], x[2]});
        } else if constexpr (std::is_same_v<T, std::vector<double>>) {
          toml::array a;
          for (double d : x) a.push_back(d);
          parent.insert_or_assign(leaf, std::move(a));
        } else if constexpr (std::is_same_v<T, long long>) {
          parent.insert_or_assign(leaf, static_cast<int64_t>(x));
        } else {
          parent.insert_or_assign(leaf, x);
        }
      },
      v);
}

std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> prev(b.size() + 1), cur(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) prev[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    cur[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j)
      cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1)});
    std::swap(prev, cur);
  }
  return prev[b.size()];
}

void validate(SceneData& d);

/// Remove the value at dotted `key`, then the tables that this leaves empty.
void erase_key(toml::table& t, const std::string& key) {
  const auto parts = split_dots(key);
  std::vector<toml::table*> chain{&t};
  for (std::size_t i = 0; i + 1 < parts.size(); ++i) {
    toml::node* n = chain.back()->get(parts[i]);
    if (!n || !n->as_table()) return;
    chain.push_back(n->as_table());
  }
  chain.back()->erase(parts.back());
  for (std::size_t i = chain.size() - 1; i > 0 && chain[i]->empty(); --i) chain[i - 1]->erase(parts[i - 1]);
}

/// Read the deprecated keys of `s` (Schema::add_alias) as their new names, with a warning.
/// Old and new both given in the file (or both by --set) is an error; when one of them comes
/// from --set, the --set value wins (as any --set does over the file).
void resolve_aliases(SceneData& d, const Schema& s) {
  for (const AliasSpec& a : s.aliases()) {
    const toml::node* old_node = lookup(d.table, a.old_key);
    if (!old_node) continue;
    const std::string old_full = d.prefix + a.old_key, new_full = d.prefix + a.new_key;
    const bool old_set = d.overridden && d.overridden->count(old_full) > 0;
    const bool new_set = d.overridden && d.overridden->count(new_full) > 0;
    const std::string origin = old_set ? std::string("--set") : d.source;
    spdlog::warn("{}: '{}' is deprecated, use '{}' (the old name is read for one release)", origin, old_full,
                 new_full);
    if (lookup(d.table, a.new_key)) {
      if (old_set == new_set)
        throw InputError(origin, old_full,
                         "deprecated name of '" + new_full + "', and both are given; keep only '" + new_full + "'");
      if (new_set) {
        erase_key(d.table, a.old_key);
        continue;
      }
    }
    toml::table held;
    held.insert_or_assign("v", *old_node);
    erase_key(d.table, a.old_key);
    std::string leaf;
    table_for(d.table, a.new_key, leaf).insert_or_assign(leaf, *held.get("v"));
  }
}

/// Walk the table and reject keys the (active) schema does not declare.
void reject_unknown(const SceneData& d, const toml::table& t, const std::string& path,
                    const std::vector<std::string>& declared) {
  for (const auto& [k, node] : t) {
    const std::string key = path.empty() ? std::string(k.str()) : path + "." + std::string(k.str());
    if (d.find(key) || d.find_array(key)) continue;
    const bool is_prefix = std::any_of(declared.begin(), declared.end(),
                                       [&](const std::string& s) { return s.rfind(key + ".", 0) == 0; });
    if (is_prefix && node.is_table()) {
      reject_unknown(d, *node.as_table(), key, declared);
      continue;
    }
    std::string best;
    std::size_t best_d = 4;
    for (const auto& s : declared) {
      const std::size_t e = edit_distance(s, key);
      if (e < best_d) best_d = e, best = s;
    }
    std::string msg = "unknown key";
    if (!best.empty()) msg += " (did you mean '" + d.prefix + best + "'?)";
    msg += "; run with --help-params for the valid keys";
    throw InputError(d.source, d.prefix + key, msg);
  }
}

void validate(SceneData& d) {
  d.active = {d.schema.get()};
  resolve_aliases(d, *d.schema);
  // Resolve style switches first: their choice decides which extra keys are valid.
  for (const auto& sw : d.schema->style_switches()) {
    const ParamSpec* p = d.schema->find(sw.key);
    std::string leaf;
    toml::table& parent = table_for(d.table, sw.key, leaf);
    if (parent.get(leaf)) {
      check_value(*p, parent, leaf, d.source, d.prefix + sw.key);
    } else if (!p->default_value) {
      throw InputError(d.source, d.prefix + sw.key, "required key is missing");
    }
    const toml::node* n = lookup(d.table, sw.key);
    const std::string style = n ? n->as_string()->get() : std::get<std::string>(*p->default_value);
    auto it = sw.styles.find(style);
    if (it != sw.styles.end()) d.active.push_back(&it->second);
  }
  for (std::size_t i = 1; i < d.active.size(); ++i) resolve_aliases(d, *d.active[i]);
  std::vector<std::string> declared;
  for (const Schema* s : d.active) {
    for (const auto& p : s->params()) declared.push_back(p.key);
    for (const auto& a : s->table_arrays()) declared.push_back(a.key);
  }
  reject_unknown(d, d.table, "", declared);
  for (const Schema* s : d.active) {
    for (const auto& p : s->params()) {
      std::string leaf;
      toml::table& parent = table_for(d.table, p.key, leaf);
      if (parent.get(leaf)) {
        check_value(p, parent, leaf, d.source, d.prefix + p.key);
        d.given.insert(p.key);
      } else if (p.default_value) {
        insert_default(parent, leaf, *p.default_value);
      } else {
        throw InputError(d.source, d.prefix + p.key, "required key is missing (" + p.help + ")");
      }
    }
    for (const auto& a : s->table_arrays()) {
      std::string leaf;
      toml::table& parent = table_for(d.table, a.key, leaf);
      toml::node* n = parent.get(leaf);
      std::size_t count = 0;
      if (n) {
        toml::array* arr = n->as_array();
        // `key = []` (how to_toml() prints an array with no entries) is an empty array of tables
        if (!arr || (!arr->empty() && !arr->is_array_of_tables()))
          throw InputError(d.source, d.prefix + a.key, "expected an array of tables ([[" + a.key + "]])");
        count = arr->size();
        for (std::size_t i = 0; i < arr->size(); ++i) {
          SceneData e;
          e.table = *(*arr)[i].as_table();
          e.schema = a.element;
          e.source = d.source;
          e.prefix = d.prefix + a.key + "[" + std::to_string(i) + "].";
          e.overridden = d.overridden;
          validate(e);
          d.element_given[e.prefix] = e.given;
          d.element_given.merge(e.element_given);
          (*arr)[i].as_table()->clear();
          *(*arr)[i].as_table() = std::move(e.table);
        }
        d.given.insert(a.key);
      } else {
        parent.insert_or_assign(leaf, toml::array{});
      }
      if (count < a.min_count || count > a.max_count)
        throw InputError(d.source, d.prefix + a.key,
                         "needs between " + std::to_string(a.min_count) + " and " +
                             (a.max_count == std::numeric_limits<std::size_t>::max() ? std::string("any number of")
                                                                                    : std::to_string(a.max_count)) +
                             " [[" + a.key + "]] entries, got " + std::to_string(count));
    }
  }
}

/// Apply "key=value" (key may contain name[i] components) to the raw table.
void apply_override(toml::table& root, const std::string& ov) {
  const auto eq = ov.find('=');
  if (eq == std::string::npos || eq == 0)
    throw InputError("--set", ov, "expected key=value (e.g. --set time.end=1e-3)");
  const std::string key = ov.substr(0, eq);
  const std::string text = ov.substr(eq + 1);
  toml::table parsed;
  try {
    parsed = toml::parse("v = " + text);
  } catch (const toml::parse_error&) {
    parsed.insert_or_assign("v", text);  // bare words are taken as strings
  }
  toml::table* cur = &root;
  const auto parts = split_dots(key);
  for (std::size_t i = 0; i < parts.size(); ++i) {
    std::string name = parts[i];
    long idx = -1;
    const auto br = name.find('[');
    if (br != std::string::npos) {
      if (name.back() != ']') throw InputError("--set", key, "malformed index (use name[i])");
      try {
        idx = std::stol(name.substr(br + 1, name.size() - br - 2));
      } catch (...) {
        throw InputError("--set", key, "malformed index (use name[i])");
      }
      name = name.substr(0, br);
    }
    const bool last = i + 1 == parts.size();
    if (idx < 0) {
      if (last) {
        cur->insert_or_assign(name, *parsed.get("v"));
        return;
      }
      if (!cur->get(name)) cur->insert_or_assign(name, toml::table{});
      cur = cur->get(name)->as_table();
      if (!cur) throw InputError("--set", key, "'" + name + "' is not a table");
    } else {
      if (last) throw InputError("--set", key, "cannot replace a whole table; set one of its keys");
      if (!cur->get(name)) cur->insert_or_assign(name, toml::array{});
      toml::array* arr = cur->get(name)->as_array();
      if (!arr) throw InputError("--set", key, "'" + name + "' is not an array of tables");
      if (idx > static_cast<long>(arr->size()))
        throw InputError("--set", key, "index " + std::to_string(idx) + " out of range (have " +
                                           std::to_string(arr->size()) + " entries; use index " +
                                           std::to_string(arr->size()) + " to append one)");
      if (idx == static_cast<long>(arr->size())) arr->push_back(toml::table{});
      cur = (*arr)[idx].as_table();
      if (!cur) throw InputError("--set", key, "'" + name + "' is not an array of tables");
    }
  }
}

}  // namespace common::scene_detail
