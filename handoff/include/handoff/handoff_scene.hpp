/// @file handoff_scene.hpp
/// Parameter schema of mpm2spheres and the options it resolves to.
#pragma once
#include <array>
#include <string>

#include "common/schema.hpp"
#include "common/ss_file.hpp"
#include "handoff/face_bonds.hpp"
#include "handoff/projection.hpp"
#include "handoff/selection.hpp"

namespace handoff {

/// Hand-off method (key `method`).
enum class HandoffMethod { paper, conserving };
inline constexpr std::array kHandoffMethods{common::Choice{"paper", HandoffMethod::paper},
                                            common::Choice{"conserving", HandoffMethod::conserving}};

/// Units of the exported pkdgrav .ss file (key `export.ss_units`; common/ss_file.hpp).
using common::kSsUnitSystems;
using common::SsUnitSystem;

/// The one schema: validates scene files, prints --help-params.
common::Schema handoff_schema();

struct HandoffConfig {
  std::string input, output, audit_json, ss_path;
  SsUnitSystem ss_units = SsUnitSystem::pkdgrav;
  std::string outflow;  ///< mpm-frag outflow file (particles that left the grid); empty: none
  HandoffMethod method = HandoffMethod::paper;
  ProjectionOptions projection;
  SelectionRules select;
  double max_energy_loss = 1.0;  ///< relative KE loss above which the tool fails (exit 3)
  int ss_color = 3;
  bool carry_given = false;      ///< the user listed fields explicitly (missing ones are errors)
  HandoffBondParams bonds;       ///< bonds.*: bonds between face-adjacent spheres (face_bonds.hpp)
};

HandoffConfig handoff_config(const common::Scene& scene);

}  // namespace handoff
