/// @file run_dir.cpp
/// Run lock and staging directory (run_dir.hpp).
#include "common/run_dir.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>

#include "common/atomic_file.hpp"
#include "common/status.hpp"

namespace common {
namespace fs = std::filesystem;
namespace {
constexpr const char* kLock = ".lock";
constexpr const char* kManifest = ".run-manifest";
constexpr const char* kJournal = ".publish-journal";  // a publish in progress: its staging directory, then its names
constexpr const char* kStagingPrefix = ".staging-";

std::string read_all(const std::string& path) {
  std::ifstream f(path);
  return std::string(std::istreambuf_iterator<char>(f), {});
}
}  // namespace

RunDirectory::RunDirectory(const std::string& dir, std::string tool, std::function<bool(const std::string&)> is_output,
                           const std::string& adopt)
    : dir_(dir), tool_(std::move(tool)), is_output_(std::move(is_output)) {
  std::error_code ec;
  fs::create_directories(dir_, ec);
  if (ec) throw IoError(dir_ + ": cannot create output directory: " + ec.message());
  const std::string lock = (fs::path(dir_) / kLock).string();
  lock_fd_ = ::open(lock.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (lock_fd_ < 0) throw IoError(lock + ": cannot create the run lock: " + std::strerror(errno));
  if (::flock(lock_fd_, LOCK_EX | LOCK_NB) != 0) {
    const int err = errno;
    ::close(lock_fd_);
    lock_fd_ = -1;
    if (err != EWOULDBLOCK) throw IoError(lock + ": cannot lock: " + std::strerror(err));
    std::string holder = read_all(lock);
    while (!holder.empty() && (holder.back() == '\n' || holder.back() == ' ')) holder.pop_back();
    throw InputError(dir_ + ": output directory is in use by another run (pid " +
                     (holder.empty() ? std::string("unknown") : holder) + ", lock " + lock +
                     "); wait for it to end or choose another output directory");
  }
  const std::string pid = std::to_string(::getpid()) + "\n";
  if (::ftruncate(lock_fd_, 0) != 0 || ::pwrite(lock_fd_, pid.data(), pid.size(), 0) != static_cast<ssize_t>(pid.size()))
    spdlog::warn("{}: cannot record the pid in the run lock: {}", lock, std::strerror(errno));
  if (!adopt.empty()) {
    staging_ = adopt;
    adopted_ = true;
  } else {
    staging_ = (fs::path(dir_) / (kStagingPrefix + std::to_string(::getpid()))).string();
    fs::remove_all(staging_, ec);  // a dead run's, with our pid
    disown_journal();
    fs::create_directory(staging_, ec);
    if (ec) throw IoError(staging_ + ": cannot create the staging directory: " + ec.message());
  }
}

RunDirectory::~RunDirectory() {
  std::error_code ec;
  if (!published_ && !staging_.empty() && fs::is_empty(staging_, ec) && !ec) {
    fs::remove(staging_, ec);  // nothing written (e.g. refused input)
  } else if (!published_ && adopted_)
    spdlog::warn("{}: the restart did not complete; {} is unchanged and the output of the run it continues is "
                 "still in {}", tool_, dir_, staging_);
  else if (!published_ && !staging_.empty())
    spdlog::warn("{}: the run did not complete; {} is unchanged and this run's partial output is in {}", tool_, dir_,
                 staging_);
  if (lock_fd_ >= 0) ::close(lock_fd_);  // releases the flock
}

// A dead run's interrupted publish, recorded under the staging name a fresh run now reuses (the
// same pid): its names become foreign ("-"), so that a later restart of this run cannot take them.
void RunDirectory::disown_journal() const {
  const std::string journal = (fs::path(dir_) / kJournal).string();
  std::ifstream f(journal);
  std::string owner;
  if (!f || !std::getline(f, owner) || owner != fs::path(staging_).filename().string()) return;
  std::string text = "-\n";
  for (std::string l; std::getline(f, l);)
    if (l.size() > 1) {
      text += '-';
      text.append(l, 1, std::string::npos);
      text += '\n';
    }
  write_text_atomic(journal, text);
}

std::string RunDirectory::staged(const std::string& name) const { return (fs::path(staging_) / name).string(); }

bool RunDirectory::carry(const std::string& name) {
  const fs::path from = fs::path(dir_) / name, to = fs::path(staging_) / name;
  std::error_code ec;
  if (fs::exists(fs::path(dir_) / kJournal, ec))  // carrying is for continuing a complete run
    throw InputError(dir_ + ": its last publish was interrupted (" + kJournal + "), so its files are not one run; "
                     "restart from the checkpoint in that run's staging directory or run from the start");
  if (!fs::is_regular_file(from, ec)) return false;
  fs::remove(to, ec);
  fs::create_hard_link(from, to, ec);
  if (ec) {
    ec.clear();
    fs::copy_file(from, to, fs::copy_options::overwrite_existing, ec);
    if (ec) throw IoError(to.string() + ": cannot carry " + from.string() + " into the staging directory: " + ec.message());
  }
  return true;
}

std::string RunDirectory::staging_of(const std::string& dir, const std::string& path) {
  std::error_code ec;
  const fs::path parent = fs::weakly_canonical(fs::path(path), ec).parent_path();
  if (ec || parent.filename().string().rfind(kStagingPrefix, 0) != 0) return {};
  const fs::path d = fs::weakly_canonical(fs::path(dir), ec);
  if (ec || parent.parent_path() != d) return {};
  return (fs::path(dir) / parent.filename()).string();
}

void RunDirectory::publish() {
  if (published_) return;
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(staging_)) {
    const std::string n = e.path().filename().string();
    if (!e.is_regular_file()) continue;
    if (n.size() > 8 && n.compare(n.size() - 8, 8, ".partial") == 0) continue;  // never published
    if (n[0] == '.') continue;  // a writer's temporary (atomic_file.hpp), left by a kill: never published
    names.push_back(n);
  }
  // A fixed order (tests interrupt after the first k), checkpoints last: a publish killed midway
  // leaves the checkpoint in the staging directory, so the run can still be continued there.
  std::sort(names.begin(), names.end(), [](const std::string& a, const std::string& b) {
    const bool ca = a.find("checkpoint") != std::string::npos, cb = b.find("checkpoint") != std::string::npos;
    return ca != cb ? cb : a < b;
  });
  // Nothing changes in dir unless every target can be replaced.
  for (const auto& n : names) {
    std::error_code ec;
    const fs::path to = fs::path(dir_) / n;
    if (fs::exists(fs::symlink_status(to, ec)) && !fs::is_regular_file(fs::symlink_status(to, ec)))
      throw IoError(to.string() + ": cannot publish the run: the name is taken by something that is not a file");
  }
  // A publish that was interrupted (killed between its renames) left its journal: the files it
  // had moved ("+" lines) are in dir already. If this run continues that run (it adopted the same
  // staging directory), they are this run's; otherwise they are stale like the previous run's.
  // Names an interrupted publish had inherited as stale ("-" lines) stay stale.
  std::set<std::string> mine(names.begin(), names.end()), interrupted;
  const std::string journal = (fs::path(dir_) / kJournal).string();
  if (fs::exists(journal)) {
    std::ifstream f(journal);
    std::string owner;
    std::getline(f, owner);
    const bool ours = adopted_ && owner == fs::path(staging_).filename().string();
    for (std::string l; std::getline(f, l);) {
      std::error_code ec;
      if (l.size() < 2 || (l[0] != '+' && l[0] != '-')) continue;
      const std::string n = l.substr(1);
      if (n.find('/') != std::string::npos || n[0] == '.' || mine.count(n)) continue;
      if (ours && l[0] == '+' && fs::is_regular_file(fs::path(dir_) / n, ec)) mine.insert(n);
      else if (!ours || l[0] == '-') interrupted.insert(n);
    }
  }
  for (const auto& n : mine) interrupted.erase(n);
  std::string text = fs::path(staging_).filename().string() + "\n";
  for (const auto& n : mine) text.append("+").append(n).append("\n");
  for (const auto& n : interrupted) text.append("-").append(n).append("\n");
  write_text_atomic(journal, text);
  // fault injection for the tests: SIGKILL after this many renames (SUITE_FAULT_PUBLISH_KILL_AFTER,
  // digits only; anything else is ignored)
  long kill_after = -1;
  if (const char* e = std::getenv("SUITE_FAULT_PUBLISH_KILL_AFTER");
      e && *e && std::strspn(e, "0123456789") == std::strlen(e))
    kill_after = std::strtol(e, nullptr, 10);
  long renamed = 0;
  for (const auto& n : names) {
    if (renamed++ == kill_after) std::raise(SIGKILL);
    const std::string from = staged(n), to = (fs::path(dir_) / n).string();
    if (std::rename(from.c_str(), to.c_str()) != 0)
      throw IoError(to + ": cannot rename " + from + " into place: " + std::strerror(errno));
  }
  // The previous run's files that this run did not produce.
  const std::string manifest = (fs::path(dir_) / kManifest).string();
  std::vector<std::string> stale;
  if (fs::exists(manifest)) {
    std::ifstream f(manifest);
    for (std::string l; std::getline(f, l);)
      if (!l.empty() && l.find('/') == std::string::npos && !mine.count(l)) stale.push_back(l);
  } else {
    for (const auto& e : fs::directory_iterator(dir_)) {
      const std::string n = e.path().filename().string();
      if (e.is_regular_file() && n[0] != '.' && !mine.count(n) && is_output_ && is_output_(n)) stale.push_back(n);
    }
  }
  for (const auto& n : interrupted) stale.push_back(n);
  for (const auto& n : stale) {
    std::error_code ec;
    fs::remove(fs::path(dir_) / n, ec);
  }
  text.clear();
  for (const auto& n : mine) text += n + "\n";
  write_text_atomic(manifest, text);
  std::error_code ec;
  fs::remove(journal, ec);
  fs::remove_all(staging_, ec);
  // staging directories of earlier runs that never completed (nobody else can hold the lock)
  for (const auto& e : fs::directory_iterator(dir_, ec))
    if (e.is_directory() && e.path().filename().string().rfind(kStagingPrefix, 0) == 0) fs::remove_all(e.path(), ec);
  published_ = true;
  spdlog::debug("{}: published {} files into {}", tool_, names.size(), dir_);
}

}  // namespace common
