/// @file schema.hpp
/// One parameter schema per tool: every scene key is declared once with its type, default,
/// SI unit, allowed range or choices and help text. The same declaration validates scene
/// files (unknown keys, wrong types and out-of-range values are errors naming file, key and
/// what is allowed), prints `--help-params`, and resolves the scene echoed into every output.
///
/// Keys are dotted paths into the TOML tree ("time.end", "output.every"). Arrays of tables
/// (`[[body]]`, `[[material]]`) are declared with `add_table_array`, whose elements are checked
/// against an element schema; an element schema may carry a *style switch*: a choice key
/// (e.g. `model = "tillotson"`) whose value selects an extra schema of style-specific keys
/// (the LAMMPS/SWIFT module contract: each style declares its own parameters).
///
/// Renamed keys stay readable for one release through *aliases* (`add_alias(old, new)`): a
/// scene file or `--set` that uses the old key is read as the new one, with a warning naming the
/// file and both keys; giving both is an error. `--help-params` lists the deprecated keys.
///
/// Typed choices: a choice whose value the tool acts on is declared from one table of
/// {name, enum value} pairs (`Choice<E>`, a `constexpr std::array` next to the enum); the
/// allowed values, the help text, the validation and `Scene::choice<E>()` all derive from it.
#pragma once
#include <Eigen/Core>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <type_traits>
#include <variant>
#include <vector>

#include "common/choice.hpp"

namespace common {

/// A renamed key: `old_key` is read as `new_key` (both relative to the schema that holds it).
struct AliasSpec {
  std::string old_key;
  std::string new_key;
};

enum class ParamType { boolean, integer, real, string, choice, vec3, real_list };

/// A default value (absent = the key is required).
using ParamValue = std::variant<bool, long long, double, std::string, Eigen::Vector3d,
                                std::vector<double>>;

struct ParamSpec {
  std::string key;  ///< dotted path relative to the schema root
  ParamType type = ParamType::real;
  std::optional<ParamValue> default_value;  ///< empty: required
  std::string unit;                         ///< SI unit ("m", "kg/m^3", "1" for dimensionless)
  double min = -std::numeric_limits<double>::infinity();  ///< inclusive lower bound (numbers, each vec3/list entry)
  double max = std::numeric_limits<double>::infinity();   ///< inclusive upper bound
  bool min_exclusive = false;                             ///< lower bound is strict
  std::vector<std::string> choices;                       ///< for ParamType::choice
  std::string help;
};

class Schema;

/// An array of tables whose elements follow `element`.
struct TableArraySpec {
  std::string key;
  std::string help;
  std::shared_ptr<Schema> element;
  std::size_t min_count = 0;
  std::size_t max_count = std::numeric_limits<std::size_t>::max();
};

class Schema {
 public:
  Schema() = default;
  explicit Schema(std::string title) : title_(std::move(title)) {}

  Schema& add_real(const std::string& key, std::optional<double> def, const std::string& unit,
                   double min, double max, const std::string& help, bool min_exclusive = false);
  Schema& add_int(const std::string& key, std::optional<long long> def, long long min,
                  long long max, const std::string& help);
  Schema& add_bool(const std::string& key, std::optional<bool> def, const std::string& help);
  Schema& add_string(const std::string& key, std::optional<std::string> def,
                     const std::string& help);
  Schema& add_choice(const std::string& key, std::optional<std::string> def,
                     std::vector<std::string> choices, const std::string& help);
  /// Typed choice: the allowed values are the names of `table` (read back with
  /// Scene::choice(key, table)); `def` is an enum value of the table (std::nullopt: required).
  template <class E, std::size_t N>
  Schema& add_choice(const std::string& key, std::type_identity_t<std::optional<E>> def,
                     const std::array<Choice<E>, N>& table, const std::string& help) {
    std::optional<std::string> d;
    if (def) d = std::string(choice_name(table, *def));
    return add_choice(key, std::move(d), choice_names(table), help);
  }
  Schema& add_vec3(const std::string& key, std::optional<Eigen::Vector3d> def,
                   const std::string& unit, double min, double max, const std::string& help);
  Schema& add_real_list(const std::string& key, std::optional<std::vector<double>> def,
                        const std::string& unit, double min, double max,
                        const std::string& help);
  Schema& add(ParamSpec spec);
  /// Declare `[[key]]`; returns the element schema to fill in.
  Schema& add_table_array(const std::string& key, const std::string& help,
                          std::size_t min_count = 0,
                          std::size_t max_count = std::numeric_limits<std::size_t>::max());
  /// Make `key` (already declared as a choice) select an extra schema per value.
  /// `styles[value]` lists the keys that are valid (and checked) only when key == value.
  Schema& add_style_switch(const std::string& key, std::map<std::string, Schema> styles);
  /// Merge all keys of `other` under `prefix` ("" for the root).
  Schema& include(const std::string& prefix, const Schema& other);
  /// Deprecated spelling: `old_key` is read as `new_key` (declared before, in this schema: a
  /// key or a table array). A scene or --set using `old_key` logs a warning ("deprecated, use
  /// new_key"); giving both is an error. Keep an alias for one release after the rename.
  Schema& add_alias(const std::string& old_key, const std::string& new_key);

  const std::vector<ParamSpec>& params() const { return params_; }
  const std::vector<TableArraySpec>& table_arrays() const { return arrays_; }
  const ParamSpec* find(const std::string& key) const;
  const TableArraySpec* find_array(const std::string& key) const;
  const std::vector<AliasSpec>& aliases() const { return aliases_; }
  const std::string& title() const { return title_; }

  /// Human-readable documentation: one block per key (type, default, unit, range, help).
  std::string help_text() const;

  struct StyleSwitch {
    std::string key;
    std::map<std::string, Schema> styles;
  };
  const std::vector<StyleSwitch>& style_switches() const { return switches_; }

 private:
  std::string title_;
  std::vector<ParamSpec> params_;
  std::vector<TableArraySpec> arrays_;
  std::vector<StyleSwitch> switches_;
  std::vector<AliasSpec> aliases_;
};

class SceneData;  // opaque resolved TOML tree

/// A fully resolved, validated scene (defaults filled in). Accessors take the dotted key as
/// declared in the schema and throw InputError if the key is not declared.
class Scene {
 public:
  /// Parse `path`, apply `overrides` ("key=value" with TOML values, e.g. "time.end=2e-3",
  /// "body[1].velocity=[0,0,-5000]", "material[0].model=\"elastic\""), validate. Throws
  /// InputError naming the file and key.
  static Scene load(const Schema& schema, const std::string& path,
                    const std::vector<std::string>& overrides = {});
  /// Same, from TOML text; `source_name` appears in messages in place of the file name.
  static Scene parse(const Schema& schema, const std::string& toml_text,
                     const std::string& source_name,
                     const std::vector<std::string>& overrides = {});

  Scene();
  ~Scene();
  Scene(const Scene&);
  Scene& operator=(const Scene&);
  Scene(Scene&&) noexcept;
  Scene& operator=(Scene&&) noexcept;

  double real(const std::string& key) const;
  long long integer(const std::string& key) const;
  bool boolean(const std::string& key) const;
  std::string string(const std::string& key) const;  ///< string or choice
  /// A typed choice declared with Schema::add_choice(key, def, table, help): its enum value.
  template <class E, std::size_t N>
  E choice(const std::string& key, const std::array<Choice<E>, N>& table) const {
    const std::string v = string(key);
    for (const auto& c : table)
      if (c.name == v) return c.value;
    throw_not_in_table(key, v);
  }
  Eigen::Vector3d vec3(const std::string& key) const;
  std::vector<double> real_list(const std::string& key) const;
  /// Whether the key was given in the file/overrides (rather than taken from its default).
  bool given(const std::string& key) const;
  /// Whether `key` is a valid key here (declared, and in the active style).
  bool has(const std::string& key) const;

  /// Number of elements of the table array `key`.
  std::size_t count(const std::string& key) const;
  /// Element `i` of the table array `key`, as a scene of its own (its keys are relative).
  Scene element(const std::string& key, std::size_t i) const;

  /// The fully resolved scene as TOML text (recorded in every output file).
  std::string to_toml() const;
  /// File name (or source name) the scene came from, for messages.
  const std::string& source() const;
  /// "file: key" context string for error messages about `key`.
  std::string where(const std::string& key) const;

 private:
  [[noreturn]] void throw_not_in_table(const std::string& key, const std::string& value) const;
  std::unique_ptr<SceneData> d_;
  friend class SceneData;
};

}  // namespace common
