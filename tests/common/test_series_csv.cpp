/// @file test_series_csv.cpp
/// The shared time-series CSV writer (common/series_csv.hpp): header from the declared columns,
/// number formats of the tools, cell-count check, partial file and commit, restart continuation.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "common/series_csv.hpp"
#include "test_util.hpp"

using namespace common;

namespace {
std::string slurp(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}
SeriesFormat three(int precision, bool blank = false) {
  return SeriesFormat({{"step", ""}, {"time_s", "s"}, {"E_J", "J"}}, {precision, blank});
}
}  // namespace

TEST(SeriesCsv, HeaderAndNumbersAsAnOstreamWritesThem) {
  const SeriesFormat f = three(17);
  EXPECT_EQ(f.header(), "step,time_s,E_J\n");
  EXPECT_EQ(f.columns()[1].unit, "s");
  const double t = 0.1, e = -1.0 / 3.0;
  std::ostringstream ref;
  ref.precision(17);
  ref << 42 << ',' << t << ',' << e << '\n';
  SeriesRow r(f);
  r.integer(std::int64_t{42}).num(t).num(e);
  EXPECT_EQ(r.line(), ref.str());
  std::ostringstream ref12;
  ref12 << std::size_t{7} << std::setprecision(12) << ',' << 1e-300 << ',' << 123456.789012345 << '\n';
  const SeriesFormat f12 = three(12);
  SeriesRow r12(f12);
  r12.integer(std::size_t{7}).num(1e-300).num(123456.789012345);
  EXPECT_EQ(r12.line(), ref12.str());
}

TEST(SeriesCsv, NonFiniteBlankOrAsTheStreamWritesIt) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const SeriesFormat f12 = three(12), f12blank = three(12, true);
  SeriesRow a(f12);
  a.integer(1).num(nan).num(std::optional<double>{});
  EXPECT_EQ(a.line(), "1,nan,\n");
  SeriesRow b(f12blank);
  b.integer(1).num(nan).num(std::optional<double>(0.5));
  EXPECT_EQ(b.line(), "1,,0.5\n");
  SeriesRow c(f12);
  c.integer(1).text("x").blank();
  EXPECT_EQ(c.line(), "1,x,\n");
}

TEST(SeriesCsv, WrongCellCountIsACallerBug) {
  const SeriesFormat f = three(17);
  SeriesRow r(f);
  r.integer(1).num(2.0);
  EXPECT_THROW(r.line(), std::logic_error);
  r.num(3.0).num(4.0);
  EXPECT_THROW(r.line(), std::logic_error);
  EXPECT_TRUE(f.complete("1,2,3"));
  EXPECT_FALSE(f.complete("1,2"));
}

TEST(SeriesCsv, TableHoldsTheWholeSeries) {
  SeriesTable t(three(17));
  t.add(t.row().integer(0).num(0.0).num(1.5));
  EXPECT_EQ(t.str(), "step,time_s,E_J\n0,0,1.5\n");
}

TEST(SeriesCsv, RowsGoToThePartialFileUntilCommit) {
  testutil::TempDir d;
  const std::string path = d.file("series.csv");
  {
    std::ofstream(path) << "earlier\n";
    SeriesFile f(path, three(17));
    f.write(f.row().integer(0).num(0.0).num(2.0));
    EXPECT_EQ(slurp(path), "earlier\n");  // untouched until commit
    EXPECT_EQ(slurp(PartialFile::partial_name(path)), "step,time_s,E_J\n0,0,2\n");
    f.commit();
  }
  EXPECT_EQ(slurp(path), "step,time_s,E_J\n0,0,2\n");
  EXPECT_FALSE(std::filesystem::exists(PartialFile::partial_name(path)));
}

TEST(SeriesCsv, ContinuationKeepsTheRowsUpToTheRestartStep) {
  testutil::TempDir d;
  const std::string path = d.file("series.csv");
  const std::string partial = PartialFile::partial_name(path);
  std::ofstream(path) << "step,time_s,E_J\n0,0,1\n10,1,1\n20,2,1\n";
  // the uncommitted run reached step 30; its last row was cut short by a crash
  std::ofstream(partial) << "step,time_s,E_J\n0,0,1\n10,1,1\n20,2,1\n30,3,1\n40,4";
  {
    SeriesFile f(path, three(17), 20);  // the partial file reaches step 20: rows from it
    f.commit();
  }
  EXPECT_EQ(slurp(path), "step,time_s,E_J\n0,0,1\n10,1,1\n20,2,1\n");
  std::ofstream(partial) << "step,time_s,E_J\n0,0,9\n";  // reaches no further than step 0
  {
    SeriesFile f(path, three(17), 10);  // 0 < 10: rows from the committed series
    f.write(f.row().integer(20).num(2.0).num(5.0));
    f.commit();
  }
  EXPECT_EQ(slurp(path), "step,time_s,E_J\n0,0,1\n10,1,1\n20,2,5\n");
}
