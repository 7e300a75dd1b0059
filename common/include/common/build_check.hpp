/// @file build_check.hpp
/// Whether a checkpoint was written by this build. A restart by the build that wrote the
/// checkpoint continues bit-identically; one by another build (a fix, an update in mid-run,
/// `RESUME_ACROSS_BUILDS=1` in the pipelines) continues from the same state but with that build's
/// arithmetic, so the run says so in its log and its run information.
#pragma once
#include <string>

namespace common {

/// Empty when `checkpoint`'s /provenance git_sha is this build's (or is not recorded, or cannot be
/// read); else one line naming both builds, for the log and the run information. Builds are told
/// apart by their git SHA only: two builds of different uncommitted changes on one commit both
/// report "<sha>+dirty" and are not told apart.
std::string other_build_note(const std::string& checkpoint);

}  // namespace common
