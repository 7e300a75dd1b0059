/// @file particles.cpp
/// SoA particle storage (no physics here): resize and byte count over ParticleSet's array
/// table (ParticleSet::for_each_array), material state allocation.
#include "mpm/particles.hpp"

#include <type_traits>

namespace mpmfrag {

namespace {
constexpr std::size_t array_count() {
  std::size_t n = 0;
  ParticleSet::for_each_array([&](const auto&) { ++n; });
  return n;
}
}  // namespace
// Guard of the single list: every member of ParticleSet is an array named in for_each_array.
static_assert(sizeof(ParticleSet) == array_count() * sizeof(std::vector<double>),
              "a ParticleSet member is missing from ParticleSet::for_each_array");

void ParticleSet::resize(std::size_t n, bool with_q) {
  const std::size_t old = id.size();
  for_each_array([&](const auto& a) {
    auto& vec = this->*a.member;
    const std::size_t w = static_cast<std::size_t>(a.info.width);
    if (a.info.optional && !with_q) {
      vec.clear();
      return;
    }
    vec.resize(w * n);
    if (a.info.identity_init)
      for (std::size_t p = old; p < n; ++p) vec[w * p] = vec[w * p + 4] = vec[w * p + 8] = 1.0;
  });
}

std::size_t ParticleSet::bytes() const {
  std::size_t b = 0;
  for_each_array([&](const auto& a) {
    using T = typename std::decay_t<decltype(a)>::element_type;
    b += (this->*a.member).size() * sizeof(T);
  });
  return b;
}

void MaterialSlot::allocate_state() {
  state.clear();
  for (const StateField& f : style->state_fields)
    state.emplace_back((end - begin) * static_cast<std::size_t>(f.ncomp), f.initial);
}

std::size_t MaterialSlot::bytes() const {
  std::size_t b = 0;
  for (const auto& s : state) b += s.size() * sizeof(double);
  return b;
}

}  // namespace mpmfrag
