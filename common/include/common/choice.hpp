/// @file choice.hpp
/// Typed scene choices: a table of {scene spelling, enum value} pairs, defined once next to the
/// enum (a `constexpr std::array`), from which the schema declares the allowed values and help
/// text (Schema::add_choice) and the scene returns the enum value (Scene::choice). Light on
/// purpose (no schema, no Eigen), so headers that define an enum can include it.
///
///   enum class SlipRule { coulomb, pkdgrav };
///   inline constexpr std::array kSlipRules{common::Choice{"coulomb", SlipRule::coulomb},
///                                          common::Choice{"pkdgrav", SlipRule::pkdgrav}};
#pragma once
#include <array>
#include <cstddef>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace common {

/// One allowed value of a typed choice: its scene spelling and the enum value it stands for.
template <class E>
struct Choice {
  std::string_view name;
  E value;
};
template <class E>
Choice(const char*, E) -> Choice<E>;

/// The scene spelling of `value` in `table` (throws std::logic_error if it is not there).
template <class E, std::size_t N>
constexpr std::string_view choice_name(const std::array<Choice<E>, N>& table, E value) {
  for (const auto& c : table)
    if (c.value == value) return c.name;
  throw std::logic_error("choice table lacks a value");
}

/// The names of `table`, in order (the allowed values of the key).
template <class E, std::size_t N>
std::vector<std::string> choice_names(const std::array<Choice<E>, N>& table) {
  std::vector<std::string> out;
  for (const auto& c : table) out.emplace_back(c.name);
  return out;
}

/// The enum value spelt `name` in `table`, if any.
template <class E, std::size_t N>
constexpr std::optional<E> choice_value(const std::array<Choice<E>, N>& table, std::string_view name) {
  for (const auto& c : table)
    if (c.name == name) return c.value;
  return std::nullopt;
}

}  // namespace common
