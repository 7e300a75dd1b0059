/// @file series_csv.hpp
/// The time-series CSV of every tool (mpm-frag, ssdem-grav, ssdem-analyse): columns declared
/// once with name and unit, rows built cell by cell in column order, numbers written the way
/// the tools always wrote them, and the growing-file protocol of common::PartialFile (rows go
/// to `<path>.partial`, commit() renames it onto `path`; a restarted run continues the series).
///
/// Number format: std::ostream's default floating format (shortest of fixed/scientific, as
/// printf %g) with `precision` significant digits; integers in decimal. Non-finite values are
/// written as the stream writes them ("nan", "inf") unless `blank_non_finite`, then as an empty
/// cell. The header is the column names joined by ',' (the unit is carried separately).
#pragma once
#include <concepts>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "common/atomic_file.hpp"

namespace common {

/// One column: `name` is the header text (e.g. "time_s"), `unit` the SI unit of its values
/// ("1": dimensionless; "" for labels and counts).
struct SeriesColumn {
  std::string name;
  std::string unit;
};

/// How a series writes doubles.
struct SeriesNumbers {
  int precision = 17;             ///< significant digits (std::ostream::precision)
  bool blank_non_finite = false;  ///< NaN/Inf as an empty cell instead of "nan"/"inf"
};

/// The declared columns of a series and its number format.
class SeriesFormat {
 public:
  SeriesFormat(std::vector<SeriesColumn> columns, SeriesNumbers numbers);
  const std::vector<SeriesColumn>& columns() const { return cols_; }
  const SeriesNumbers& numbers() const { return num_; }
  /// "name1,name2,...\n"
  std::string header() const;
  /// One double as a cell.
  std::string number(double v) const;
  /// Whether `line` (no newline) has exactly as many cells as there are columns.
  bool complete(std::string_view line) const;

 private:
  std::vector<SeriesColumn> cols_;
  SeriesNumbers num_;
};

/// One row, cells appended in column order. line() checks the count. Refers to its format,
/// which must outlive it.
class SeriesRow {
 public:
  explicit SeriesRow(const SeriesFormat& f) : f_(&f) {}
  explicit SeriesRow(SeriesFormat&&) = delete;
  SeriesRow& num(double v) { return cell(f_->number(v)); }
  /// Empty cell if `v` is absent.
  SeriesRow& num(const std::optional<double>& v) { return v ? num(*v) : blank(); }
  template <std::integral I>
  SeriesRow& integer(I v) { return cell(std::to_string(v)); }
  SeriesRow& text(std::string_view s) { return cell(s); }
  SeriesRow& blank() { return cell({}); }
  /// The row with its newline. Throws std::logic_error if the cell count differs from the columns.
  std::string line() const;

 private:
  SeriesRow& cell(std::string_view s);
  const SeriesFormat* f_;
  std::string s_;
  std::size_t cells_ = 0;
};

/// A whole series held in memory (written at once, e.g. with write_text_atomic).
class SeriesTable {
 public:
  explicit SeriesTable(SeriesFormat f) : f_(std::move(f)), text_(f_.header()) {}
  SeriesRow row() const { return SeriesRow(f_); }
  void add(const SeriesRow& r) { text_ += r.line(); }
  const std::string& str() const { return text_; }

 private:
  SeriesFormat f_;
  std::string text_;
};

/// A series file that grows during a run (common::PartialFile protocol).
class SeriesFile {
 public:
  /// Creates `<path>.partial` and writes the header. With `continue_at` (a restarted run at
  /// that step) the header is followed by the rows of the run the checkpoint came from whose
  /// first cell (the step) is <= `continue_at`, taken from `<path>.partial` if that file reaches
  /// the step (the run never committed it: killed, I/O failure), else from `path`; rows cut
  /// short by a crash (fewer cells) are dropped. Throws IoError.
  SeriesFile(const std::string& path, SeriesFormat f, std::optional<std::int64_t> continue_at = std::nullopt);
  /// The header and rows a run had written when it saved a checkpoint (text()).
  struct Initial {
    std::string text;  ///< header and continued rows
  };
  /// Creates `<path>.partial` holding `initial.text` (a restarted run that keeps its series in its
  /// checkpoint: mpm-frag). Throws IoError.
  SeriesFile(const std::string& path, SeriesFormat f, Initial initial);

  SeriesRow row() const { return SeriesRow(f_); }
  /// Append a row and flush. Throws IoError.
  void write(const SeriesRow& r);
  /// Everything written so far (header and rows).
  const std::string& text() const { return text_; }
  /// Rename the series onto `path`. Throws IoError.
  void commit() { file_.commit(); }
  const std::string& path() const { return file_.final_path(); }

 private:
  SeriesFormat f_;
  PartialFile file_;
  std::string text_;
};

}  // namespace common
