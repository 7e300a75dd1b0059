/// @file run_handoff.hpp
/// The whole mpm2spheres run: read, select, project, (correct), audit, write.
#pragma once
#include "common/provenance.hpp"
#include "handoff/audit.hpp"
#include "handoff/handoff_scene.hpp"

namespace handoff {

struct HandoffOutcome {
  Audit audit;
  ProjectionResult result;
};

/// In-memory hand-off of an already-read snapshot (used by the tool and the tests), with the
/// particles of an mpm-frag outflow file when `outflow` is given (outflow.hpp; the selection
/// rules apply to them too, and every invariant of the audit includes them).
HandoffOutcome hand_off(const common::ParticleSnapshot& snapshot, const HandoffConfig& cfg,
                        const common::ParticleSnapshot* outflow = nullptr);

/// The tool body; returns the exit code (0, or 3 when the KE loss exceeds the threshold).
/// Throws common::InputError / IoError.
int run_handoff(const HandoffConfig& cfg, const common::Provenance& prov);

}  // namespace handoff
