/// @file run_identity.hpp
/// The identity of a run, recorded in its checkpoints so that `--restart` refuses the
/// checkpoint of another run (a different scene, seed or input file).
///
/// The identity is a sorted list of `key = value` lines: every resolved scene key except those
/// that may legitimately change on restart (the caller lists them: time.end and the output.*
/// keys), the seed being an ordinary scene key; for keys that name input files the value is the
/// file's fingerprint (size and FNV-1a 64-bit hash of its content) instead of its path, so a
/// moved input still matches and an edited one does not. The digest is the FNV-1a 64-bit hash
/// of that text (16 hex digits), for messages.
#pragma once
#include <map>
#include <string>
#include <vector>

namespace common {

class Scene;

struct RunIdentity {
  std::map<std::string, std::string> parts;  ///< key -> value (as TOML writes it, or a fingerprint)

  bool empty() const { return parts.empty(); }
  /// "key = value\n" lines, sorted by key.
  std::string text() const;
  /// FNV-1a 64-bit hash of text(), 16 hex digits.
  std::string digest() const;
  static RunIdentity parse(const std::string& text);
  /// This identity without the keys run_identity() leaves out for `excluded` (same rule), e.g. a
  /// checkpoint's recorded identity from before a key became one that a restart may change.
  RunIdentity without(const std::vector<std::string>& excluded) const;
  /// "" when equal; else one "; "-separated entry per differing key:
  /// "<key>: <label_a> <value a>, <label_b> <value b>" ("(absent)" for a missing key).
  static std::string differences(const RunIdentity& a, const std::string& label_a, const RunIdentity& b,
                                 const std::string& label_b);
};

/// Identity of a run of `sc`. `excluded`: keys left out (an entry ending in '.' leaves out the
/// whole table, e.g. "output."); `file_keys`: keys whose non-empty value is an input file path,
/// recorded as file_fingerprint(path) ("(unreadable)" if it cannot be read: its reader reports that).
RunIdentity run_identity(const Scene& sc, const std::vector<std::string>& excluded,
                         const std::vector<std::string>& file_keys);

/// "<size> bytes, fnv1a64 <16 hex digits>" of a file's content. Throws InputError.
std::string file_fingerprint(const std::string& path);

}  // namespace common
