/// @file schema.cpp
/// Implementation of common/schema.hpp (the header states the contract, and for physics the equations and sources).
#include "common/schema.hpp"

#include <iomanip>
#include <sstream>
#include <stdexcept>

namespace common {

namespace {
const char* type_name(ParamType t) {
  switch (t) {
    case ParamType::boolean: return "bool";
    case ParamType::integer: return "integer";
    case ParamType::real: return "real";
    case ParamType::string: return "string";
    case ParamType::choice: return "choice";
    case ParamType::vec3: return "vec3";
    case ParamType::real_list: return "real list";
  }
  return "?";
}

std::string num(double x) {
  std::ostringstream o;
  o << std::setprecision(10) << x;
  return o.str();
}

std::string value_text(const ParamValue& v) {
  std::ostringstream o;
  std::visit(
      [&](const auto& x) {
        using T = std::decay_t<decltype(x)>;
        if constexpr (std::is_same_v<T, bool>) o << (x ? "true" : "false");
        else if constexpr (std::is_same_v<T, long long>) o << x;
        else if constexpr (std::is_same_v<T, double>) o << num(x);
        else if constexpr (std::is_same_v<T, std::string>) o << '"' << x << '"';
        else if constexpr (std::is_same_v<T, Eigen::Vector3d>) o << "[" << num(x[0]) << ", " << num(x[1]) << ", " << num(x[2]) << "]";
        else {
          o << "[";
          for (std::size_t i = 0; i < x.size(); ++i) o << (i ? ", " : "") << num(x[i]);
          o << "]";
        }
      },
      v);
  return o.str();
}

void describe(std::ostringstream& o, const Schema& s, const std::string& prefix, const std::string& indent) {
  for (const auto& p : s.params()) {
    o << indent << prefix << p.key << "  (" << type_name(p.type) << ")";
    if (p.default_value) o << "  default " << value_text(*p.default_value);
    else o << "  REQUIRED";
    if (!p.unit.empty()) o << "  [" << p.unit << "]";
    o << "\n";
    if (p.type == ParamType::choice) {
      o << indent << "    one of:";
      for (const auto& c : p.choices) o << " " << c;
      o << "\n";
    } else if (p.type != ParamType::boolean && p.type != ParamType::string &&
               (std::isfinite(p.min) || std::isfinite(p.max))) {
      o << indent << "    range: " << (p.min_exclusive ? "(" : "[") << num(p.min) << ", " << num(p.max) << "]\n";
    }
    if (!p.help.empty()) o << indent << "    " << p.help << "\n";
  }
  for (const auto& a : s.aliases())
    o << indent << prefix << a.old_key << "  DEPRECATED: use " << prefix << a.new_key
      << " (the old name is read, with a warning, for one release)\n";
  for (const auto& sw : s.style_switches()) {
    for (const auto& [name, st] : sw.styles) {
      if (st.params().empty() && st.table_arrays().empty()) continue;
      o << indent << "  when " << prefix << sw.key << " = \"" << name << "\":\n";
      describe(o, st, prefix, indent + "    ");
    }
  }
  for (const auto& a : s.table_arrays()) {
    o << indent << "[[" << prefix << a.key << "]]  (array of tables, " << a.min_count << ".."
      << (a.max_count == std::numeric_limits<std::size_t>::max() ? std::string("any") : std::to_string(a.max_count))
      << " entries)\n";
    if (!a.help.empty()) o << indent << "    " << a.help << "\n";
    describe(o, *a.element, prefix + a.key + "[i].", indent + "  ");
  }
}
}  // namespace

Schema& Schema::add(ParamSpec spec) {
  if (find(spec.key) || find_array(spec.key))
    throw std::logic_error("schema: key '" + spec.key + "' declared twice");
  for (const auto& a : aliases_)
    if (a.old_key == spec.key) throw std::logic_error("schema: key '" + spec.key + "' is a deprecated alias");
  params_.push_back(std::move(spec));
  return *this;
}

Schema& Schema::add_real(const std::string& key, std::optional<double> def, const std::string& unit,
                         double min, double max, const std::string& help, bool min_exclusive) {
  ParamSpec p{key, ParamType::real, {}, unit, min, max, min_exclusive, {}, help};
  if (def) p.default_value = *def;
  return add(std::move(p));
}

Schema& Schema::add_int(const std::string& key, std::optional<long long> def, long long min,
                        long long max, const std::string& help) {
  ParamSpec p{key, ParamType::integer, {}, "1", static_cast<double>(min), static_cast<double>(max), false, {}, help};
  if (def) p.default_value = *def;
  return add(std::move(p));
}

Schema& Schema::add_bool(const std::string& key, std::optional<bool> def, const std::string& help) {
  ParamSpec p{key, ParamType::boolean, {}, "", -INFINITY, INFINITY, false, {}, help};
  if (def) p.default_value = *def;
  return add(std::move(p));
}

Schema& Schema::add_string(const std::string& key, std::optional<std::string> def, const std::string& help) {
  ParamSpec p{key, ParamType::string, {}, "", -INFINITY, INFINITY, false, {}, help};
  if (def) p.default_value = *def;
  return add(std::move(p));
}

Schema& Schema::add_choice(const std::string& key, std::optional<std::string> def,
                           std::vector<std::string> choices, const std::string& help) {
  ParamSpec p{key, ParamType::choice, {}, "", -INFINITY, INFINITY, false, std::move(choices), help};
  if (def) p.default_value = *def;
  return add(std::move(p));
}

Schema& Schema::add_vec3(const std::string& key, std::optional<Eigen::Vector3d> def,
                         const std::string& unit, double min, double max, const std::string& help) {
  ParamSpec p{key, ParamType::vec3, {}, unit, min, max, false, {}, help};
  if (def) p.default_value = *def;
  return add(std::move(p));
}

Schema& Schema::add_real_list(const std::string& key, std::optional<std::vector<double>> def,
                              const std::string& unit, double min, double max, const std::string& help) {
  ParamSpec p{key, ParamType::real_list, {}, unit, min, max, false, {}, help};
  if (def) p.default_value = *def;
  return add(std::move(p));
}

Schema& Schema::add_table_array(const std::string& key, const std::string& help,
                                std::size_t min_count, std::size_t max_count) {
  if (find(key) || find_array(key)) throw std::logic_error("schema: key '" + key + "' declared twice");
  for (const auto& a : aliases_)
    if (a.old_key == key) throw std::logic_error("schema: key '" + key + "' is a deprecated alias");
  arrays_.push_back({key, help, std::make_shared<Schema>(), min_count, max_count});
  return *arrays_.back().element;
}

Schema& Schema::add_style_switch(const std::string& key, std::map<std::string, Schema> styles) {
  auto it = std::find_if(params_.begin(), params_.end(), [&](const ParamSpec& p) { return p.key == key; });
  if (it == params_.end() || it->type != ParamType::choice)
    throw std::logic_error("schema: style switch '" + key + "' must be a declared choice");
  if (it->choices.empty())
    for (const auto& [name, s] : styles) it->choices.push_back(name);
  for (const auto& [name, s] : styles) {
    if (std::find(it->choices.begin(), it->choices.end(), name) == it->choices.end())
      throw std::logic_error("schema: style '" + name + "' is not a choice of '" + key + "'");
    for (const auto& p : s.params())
      if (find(p.key)) throw std::logic_error("schema: style key '" + p.key + "' shadows a common key");
  }
  switches_.push_back({key, std::move(styles)});
  return *this;
}

Schema& Schema::include(const std::string& prefix, const Schema& other) {
  const std::string pre = prefix.empty() ? "" : prefix + ".";
  for (auto p : other.params_) {
    p.key = pre + p.key;
    add(std::move(p));
  }
  for (auto a : other.arrays_) {
    a.key = pre + a.key;
    arrays_.push_back(std::move(a));
  }
  for (auto sw : other.switches_) {
    if (!pre.empty()) {
      std::map<std::string, Schema> styles;
      for (auto& [name, st] : sw.styles) {
        Schema s2;
        s2.include(prefix, st);
        styles[name] = std::move(s2);
      }
      sw.styles = std::move(styles);
      sw.key = pre + sw.key;
    }
    switches_.push_back(std::move(sw));
  }
  for (auto a : other.aliases_) {
    a.old_key = pre + a.old_key;
    a.new_key = pre + a.new_key;
    aliases_.push_back(std::move(a));
  }
  return *this;
}

Schema& Schema::add_alias(const std::string& old_key, const std::string& new_key) {
  if (!find(new_key) && !find_array(new_key))
    throw std::logic_error("schema: alias target '" + new_key + "' is not declared");
  if (find(old_key) || find_array(old_key))
    throw std::logic_error("schema: alias '" + old_key + "' is a declared key");
  for (const auto& a : aliases_)
    if (a.old_key == old_key) throw std::logic_error("schema: alias '" + old_key + "' declared twice");
  aliases_.push_back({old_key, new_key});
  return *this;
}

const ParamSpec* Schema::find(const std::string& key) const {
  for (const auto& p : params_)
    if (p.key == key) return &p;
  return nullptr;
}

const TableArraySpec* Schema::find_array(const std::string& key) const {
  for (const auto& a : arrays_)
    if (a.key == key) return &a;
  return nullptr;
}

std::string Schema::help_text() const {
  std::ostringstream o;
  if (!title_.empty()) o << title_ << "\n\n";
  o << "Scene keys (TOML; dotted keys are nested tables; override any key with --set key=value):\n\n";
  describe(o, *this, "", "");
  return o.str();
}

}  // namespace common
