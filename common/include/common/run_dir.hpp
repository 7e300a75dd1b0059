/// @file run_dir.hpp
/// A run's output directory, atomic per run rather than per file (mpm-frag, ssdem-grav).
///
/// - Run lock: `<dir>/.lock` is flock(2)ed for the whole run and holds the holder's pid; a
///   second run into a locked directory is refused (InputError, exit 2) naming the directory
///   and that pid. The kernel drops the lock when the process ends, however it ends.
/// - Staging: the run writes every file into `<dir>/.staging-<pid>/`. publish() (called when
///   the run completed, exit 0) renames each staged file into `<dir>` (but hidden names: the
///   temporaries of atomic writes that a killed run may have left in the staging directory a
///   restart adopted, and `*.partial`, which are removed with it), then removes the files
///   of the previous run that this run did not produce (those listed in `<dir>/.run-manifest`,
///   or, for a directory written before manifests existed, those `is_output` accepts), writes
///   the new manifest and removes the staging directory and the staging directories of earlier
///   runs that never completed. `<dir>` thus holds exactly one complete run, plus files that
///   no run wrote (a pipeline's links, a scene file).
/// - A run that does not reach publish() (numerical failure, I/O failure, signal, crash) leaves
///   `<dir>` exactly as the previous run left it (a kill inside publish(): see below); its own
///   output (series, failed state, checkpoint) stays in its staging directory, which the
///   destructor names in a log line.
/// - A restart may adopt the staging directory of the interrupted run it continues (the one
///   holding its checkpoint), so that run's snapshots and series become part of the new one.
/// - A publish killed between its renames (a window of milliseconds) leaves `<dir>` holding part
///   of the new run beside the rest of the previous one, and `<dir>/.publish-journal` (its staging
///   directory, the names it publishes, and names it had inherited as stale; written before the
///   first rename; files are renamed in name order, checkpoints last, so the checkpoint is still
///   in the staging directory). The next publish completes it: it counts the files already moved
///   as its own if it adopted that staging directory (a restart from that checkpoint), else as
///   stale, and removes the previous run's leftovers either way. Test hook:
///   SUITE_FAULT_PUBLISH_KILL_AFTER=k raises SIGKILL after k renames.
#pragma once
#include <functional>
#include <string>
#include <vector>

namespace common {

class RunDirectory {
 public:
  /// Create `dir` if needed (IoError), lock it (InputError if another run holds it), and
  /// create a fresh staging directory, or adopt `adopt` (a `.staging-*` directory of `dir`).
  RunDirectory(const std::string& dir, std::string tool, std::function<bool(const std::string&)> is_output,
               const std::string& adopt = {});
  ~RunDirectory();
  RunDirectory(const RunDirectory&) = delete;
  RunDirectory& operator=(const RunDirectory&) = delete;

  const std::string& dir() const { return dir_; }
  const std::string& staging() const { return staging_; }
  /// `<staging>/<name>`.
  std::string staged(const std::string& name) const;
  /// Hard-link (or copy) `<dir>/<name>` into the staging directory, so a continued run
  /// publishes it again. Returns false if there is no such file. Throws IoError; InputError if
  /// `<dir>`'s last publish was interrupted (its files are not one run).
  bool carry(const std::string& name);
  /// The staging directory of `dir` that `path` lies in (directly), or "".
  static std::string staging_of(const std::string& dir, const std::string& path);
  /// Publish the staged files (see above). Throws IoError; nothing in `dir` has changed if a
  /// staged file's target cannot be replaced (a directory of that name).
  void publish();
  bool published() const { return published_; }

 private:
  void disown_journal() const;
  std::string dir_, tool_, staging_;
  std::function<bool(const std::string&)> is_output_;
  int lock_fd_ = -1;
  bool published_ = false;
  bool adopted_ = false;
};

}  // namespace common
