/// @file selection.cpp
/// Implementation of handoff/selection.hpp (the header states the contract, and for physics the equations and sources).
#include "handoff/selection.hpp"

#include <algorithm>
#include <cmath>

#include "common/status.hpp"

namespace handoff {

Selection select_particles(const common::ParticleSnapshot& s, const SelectionRules& rules,
                           const std::string& file) {
  Selection sel;
  const common::Field* damage = s.field("damage");
  if (rules.min_damage > 0.0 && !damage)
    throw common::InputError(file, "select.min_damage",
                             "the snapshot has no /particles/damage dataset to select on");
  sel.kept.reserve(s.count());
  for (std::size_t i = 0; i < s.count(); ++i) {
    bool keep = true;
    if (rules.min_damage > 0.0 && damage->values[i] < rules.min_damage) keep = false;
    if (rules.max_speed > 0.0) {
      const double v2 = s.velocity[3 * i] * s.velocity[3 * i] + s.velocity[3 * i + 1] * s.velocity[3 * i + 1] +
                        s.velocity[3 * i + 2] * s.velocity[3 * i + 2];
      if (v2 > rules.max_speed * rules.max_speed) keep = false;
    }
    if (std::find(rules.exclude_materials.begin(), rules.exclude_materials.end(), s.material[i]) !=
        rules.exclude_materials.end())
      keep = false;
    (keep ? sel.kept : sel.dropped).push_back(i);
  }
  return sel;
}

common::ParticleSnapshot subset(const common::ParticleSnapshot& s, const std::vector<std::size_t>& idx) {
  common::ParticleSnapshot o;
  o.time = s.time;
  o.step = s.step;
  o.grid = s.grid;
  const std::size_t n = idx.size();
  o.id.resize(n);
  o.position.resize(3 * n);
  o.velocity.resize(3 * n);
  o.size.resize(3 * n);
  o.mass.resize(n);
  o.volume.resize(n);
  o.material.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t i = idx[k];
    o.id[k] = s.id[i];
    o.mass[k] = s.mass[i];
    o.volume[k] = s.volume[i];
    o.material[k] = s.material[i];
    for (int d = 0; d < 3; ++d) {
      o.position[3 * k + d] = s.position[3 * i + d];
      o.velocity[3 * k + d] = s.velocity[3 * i + d];
      o.size[3 * k + d] = s.size[3 * i + d];
    }
  }
  for (const auto& f : s.fields) {
    common::Field g{f.name, f.unit, f.ncomp, std::vector<double>(n * f.ncomp), f.description};
    for (std::size_t k = 0; k < n; ++k)
      for (std::size_t c = 0; c < f.ncomp; ++c) g.values[k * f.ncomp + c] = f.values[idx[k] * f.ncomp + c];
    o.fields.push_back(std::move(g));
  }
  return o;
}

}  // namespace handoff
