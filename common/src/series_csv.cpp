/// @file series_csv.cpp
/// The time-series CSV writer shared by the tools (series_csv.hpp).
#include "common/series_csv.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace common {

SeriesFormat::SeriesFormat(std::vector<SeriesColumn> columns, SeriesNumbers numbers)
    : cols_(std::move(columns)), num_(numbers) {
  if (cols_.empty()) throw std::logic_error("series: no columns");
}

std::string SeriesFormat::header() const {
  std::string h;
  for (std::size_t c = 0; c < cols_.size(); ++c) {
    if (c) h += ',';
    h += cols_[c].name;
  }
  return h + '\n';
}

std::string SeriesFormat::number(double v) const {
  if (num_.blank_non_finite && !std::isfinite(v)) return {};
  std::ostringstream o;
  o.precision(num_.precision);
  o << v;
  return o.str();
}

bool SeriesFormat::complete(std::string_view line) const {
  return static_cast<std::size_t>(std::count(line.begin(), line.end(), ',')) + 1 == cols_.size();
}

SeriesRow& SeriesRow::cell(std::string_view s) {
  if (cells_++) s_ += ',';
  s_ += s;
  return *this;
}

std::string SeriesRow::line() const {
  if (cells_ != f_->columns().size())
    throw std::logic_error("series row has " + std::to_string(cells_) + " cells, expected " +
                           std::to_string(f_->columns().size()));
  return s_ + '\n';
}

namespace {
std::vector<std::string> read_lines(const std::string& path) {
  std::vector<std::string> lines;
  std::ifstream in(path);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

// Header plus the rows up to and including `step` of the run being continued.
std::string continuation(const std::string& path, const SeriesFormat& f, std::int64_t step) {
  std::vector<std::string> lines = read_lines(PartialFile::partial_name(path));
  if (lines.size() < 2 || std::atoll(lines.back().c_str()) < step) lines = read_lines(path);
  std::string keep = f.header();
  for (std::size_t i = 1; i < lines.size(); ++i) {
    const std::string& l = lines[i];  // a row cut short by a crash has fewer cells: dropped
    if (f.complete(l) && std::atoll(l.c_str()) <= step) keep += l + '\n';
  }
  return keep;
}
}  // namespace

SeriesFile::SeriesFile(const std::string& path, SeriesFormat f, std::optional<std::int64_t> continue_at)
    : SeriesFile(path, f, Initial{continue_at ? continuation(path, f, *continue_at) : f.header()}) {}

SeriesFile::SeriesFile(const std::string& path, SeriesFormat f, Initial initial)
    : f_(std::move(f)), file_(path), text_(std::move(initial.text)) {
  file_.stream() << text_;
  file_.flush();
}

void SeriesFile::write(const SeriesRow& r) {
  const std::string line = r.line();
  text_ += line;
  file_.stream() << line;
  file_.flush();
}

}  // namespace common
