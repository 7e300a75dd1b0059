/// @file build_check.cpp
/// other_build_note: a checkpoint's writer against this build (build_check.hpp).
#include "common/build_check.hpp"

#include <exception>

#include "common/h5.hpp"
#include "common/provenance.hpp"

namespace common {

std::string other_build_note(const std::string& checkpoint) {
  // Informational only: the caller has read and checked the checkpoint already, so it is opened
  // directly (no second validation pass), and any failure here gives no note rather than an error.
  Provenance p;
  try {
    h5::Handle f(H5Fopen(checkpoint.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT));
    if (!f.valid() || !h5::exists(f, "provenance")) return {};
    p = h5::read_provenance(f, checkpoint);
  } catch (const std::exception&) {
    return {};
  }
  if (p.git_sha.empty() || p.git_sha == git_sha()) return {};
  return "checkpoint " + checkpoint + " was written by " + (p.tool.empty() ? "a tool" : p.tool) + " " + p.version +
         " (git " + p.git_sha + "), this is " + version() + " (git " + git_sha() +
         "): the run continues from its state with this build's arithmetic (bit-identical to an "
         "uninterrupted run only where both builds compute the same)";
}

}  // namespace common
