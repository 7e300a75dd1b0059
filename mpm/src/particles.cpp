/// @file particles.cpp
/// SoA particle storage (no physics here).
#include "mpm/particles.hpp"

namespace mpmfrag {

void ParticleSet::resize(std::size_t n, bool with_q) {
  const std::size_t old = id.size();
  id.resize(n);
  material.resize(n);
  x.resize(3 * n);
  v.resize(3 * n);
  F.resize(9 * n, 0.0);
  for (std::size_t p = old; p < n; ++p) F[9 * p] = F[9 * p + 4] = F[9 * p + 8] = 1.0;
  stress.resize(6 * n);
  mass.resize(n);
  volume.resize(n);
  volume0.resize(n);
  energy.resize(n);
  half_width.resize(3 * n);
  if (with_q) q.resize(n);
  else q.clear();
}

std::size_t ParticleSet::bytes() const {
  return id.size() * sizeof(std::uint64_t) + material.size() * sizeof(std::int32_t) +
         sizeof(double) * (x.size() + v.size() + F.size() + stress.size() + mass.size() +
                           volume.size() + volume0.size() + energy.size() + half_width.size() +
                           q.size());
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
