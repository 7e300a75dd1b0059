/// @file atomic_file.cpp
/// Implementation of common/atomic_file.hpp (the header states the contract, and for physics the equations and sources).
#include "common/atomic_file.hpp"

#include <fcntl.h>
#include <limits.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <functional>
#include <memory>
#include <system_error>

#include "common/status.hpp"

namespace common {

namespace {
std::string make_temp_name(const std::string& final_path) {
  namespace fs = std::filesystem;
  const fs::path p(final_path);
  std::string name(".");
  name += p.filename().string();
  name += ".tmp.";
  name += std::to_string(::getpid());
  // A final name near NAME_MAX: the decorated name would not fit; hash it instead.
  if (name.size() > NAME_MAX)
    name = ".tmp." + std::to_string(std::hash<std::string>{}(p.filename().string())) + "." + std::to_string(::getpid());
  return (p.parent_path() / name).string();
}

}  // namespace

void check_output_path(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) == 0) {
    // A directory is left to rename(2), which fails without harm (IoError, exit 4).
    if (!S_ISREG(st.st_mode) && !S_ISDIR(st.st_mode))
      throw InputError(path, "", std::string("output exists and is not a regular file (") +
                                     (S_ISFIFO(st.st_mode) ? "a FIFO"
                                      : S_ISCHR(st.st_mode) || S_ISBLK(st.st_mode) ? "a device" : "a socket") +
                                     "): refusing to replace it");
    return;
  }
  if (errno == ENAMETOOLONG || errno == ENOTDIR || errno == ELOOP)
    throw IoError(path + ": cannot create: " + std::strerror(errno));
}

namespace {
bool dir_exists(const std::filesystem::path& dir) {
  std::error_code ec;  // ENAMETOOLONG etc. were reported by check_output_path
  return std::filesystem::is_directory(dir, ec);
}

void fsync_path(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDONLY);
  if (fd < 0) throw IoError(path + ": cannot reopen for fsync: " + std::strerror(errno));
  const int rc = ::fsync(fd);
  const int err = errno;
  ::close(fd);
  if (rc != 0) throw IoError(path + ": fsync failed: " + std::strerror(err));
}
}  // namespace

AtomicPath::AtomicPath(std::string final_path)
    : final_(std::move(final_path)), temp_(make_temp_name(final_)) {
  check_output_path(final_);
  const auto dir = std::filesystem::path(final_).parent_path();
  if (!dir.empty() && !dir_exists(dir))
    throw IoError(final_ + ": output directory '" + dir.string() + "' does not exist");
}

AtomicPath::~AtomicPath() {
  if (!committed_) std::remove(temp_.c_str());
}

void AtomicPath::commit() {
  fsync_path(temp_);
  if (std::rename(temp_.c_str(), final_.c_str()) != 0)
    throw IoError(final_ + ": cannot rename temporary file into place: " + std::strerror(errno));
  committed_ = true;
}

namespace {
// `text` into out's temporary file, with checked writes (IoError naming the final path).
void write_temp(const AtomicPath& out, const std::string& text) {
  const std::string& path = out.final_path();
  std::FILE* f = std::fopen(out.temp_path().c_str(), "wb");
  if (!f) throw IoError(path + ": cannot create: " + std::strerror(errno));
  const std::size_t n = std::fwrite(text.data(), 1, text.size(), f);
  const bool ok = (n == text.size()) && std::fflush(f) == 0;
  const int err = errno;
  if (std::fclose(f) != 0 || !ok) throw IoError(path + ": write failed: " + std::strerror(err));
}
}  // namespace

void write_text_atomic(const std::string& path, const std::string& text) {
  AtomicPath out(path);
  write_temp(out, text);
  out.commit();
}

void write_text_set_atomic(const std::vector<std::pair<std::string, std::string>>& files) {
  std::vector<std::unique_ptr<AtomicPath>> outs;
  for (const auto& [path, text] : files) {
    outs.push_back(std::make_unique<AtomicPath>(path));
    write_temp(*outs.back(), text);
  }
  for (auto& o : outs) o->commit();  // renames only: no write left to fail
}

PartialFile::PartialFile(std::string final_path)
    : final_(std::move(final_path)), partial_(partial_name(final_)) {
  check_output_path(final_);
  check_output_path(partial_);
  const auto dir = std::filesystem::path(final_).parent_path();
  if (!dir.empty() && !dir_exists(dir))
    throw IoError(final_ + ": output directory '" + dir.string() + "' does not exist");
  out_.open(partial_, std::ios::out | std::ios::trunc);
  if (!out_) throw IoError(partial_ + ": cannot create: " + std::strerror(errno));
}

void PartialFile::flush() {
  if (committed_) throw IoError(final_ + ": write after the series was committed");
  out_.flush();
  if (!out_) throw IoError(partial_ + ": write failed (disk full?)");
}

void PartialFile::commit() {
  if (committed_) return;
  flush();
  out_.close();
  if (!out_) throw IoError(partial_ + ": close failed (disk full?)");
  fsync_path(partial_);
  if (std::rename(partial_.c_str(), final_.c_str()) != 0)
    throw IoError(final_ + ": cannot rename " + partial_ + " into place: " + std::strerror(errno));
  committed_ = true;
}

}  // namespace common
