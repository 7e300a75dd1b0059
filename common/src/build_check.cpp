/// @file build_check.cpp
/// other_build_note: a checkpoint's writer against this build (build_check.hpp).
#include "common/build_check.hpp"

#include "common/h5.hpp"
#include "common/provenance.hpp"

namespace common {

std::string other_build_note(const std::string& checkpoint) {
  Provenance p;
  {
    h5::Handle f = h5::open_file_read(checkpoint);
    if (!h5::exists(f, "provenance")) return {};
    p = h5::read_provenance(f, checkpoint);
  }
  if (p.git_sha.empty() || p.git_sha == git_sha()) return {};
  return "checkpoint " + checkpoint + " was written by " + (p.tool.empty() ? "a tool" : p.tool) + " " + p.version +
         " (git " + p.git_sha + "), this is " + version() + " (git " + git_sha() +
         "): the run continues from its state with this build's arithmetic (bit-identical to an "
         "uninterrupted run only where both builds compute the same)";
}

}  // namespace common
