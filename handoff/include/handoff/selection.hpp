/// @file selection.hpp
/// Which particles enter the hand-off. A particle is dropped if any rule says so:
///   damage < min_damage   (needs a `damage` field in the snapshot),
///   |v| > max_speed,
///   material in exclude_materials.
/// Dropped mass and momentum are reported in the audit.
#pragma once
#include <cstdint>
#include <vector>

#include "common/particle_file.hpp"

namespace handoff {

struct SelectionRules {
  double min_damage = 0.0;                ///< keep damage >= this (0: keep all)
  double max_speed = 0.0;                 ///< keep |v| <= this (0: no limit) [m/s]
  std::vector<int> exclude_materials;     ///< material ids to drop
  bool active() const { return min_damage > 0.0 || max_speed > 0.0 || !exclude_materials.empty(); }
};

struct Selection {
  std::vector<std::size_t> kept;     ///< indices into the snapshot, ascending
  std::vector<std::size_t> dropped;  ///< indices into the snapshot, ascending
};

/// Apply the rules. Throws common::InputError if a rule needs a field the snapshot lacks.
Selection select_particles(const common::ParticleSnapshot& s, const SelectionRules& rules,
                           const std::string& file);

/// A snapshot holding only the particles `idx` (all fields carried).
common::ParticleSnapshot subset(const common::ParticleSnapshot& s, const std::vector<std::size_t>& idx);

}  // namespace handoff
