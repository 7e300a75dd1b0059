/// @file test_ss_file.cpp
/// pkdgrav .ss files (common/ss_file.hpp): byte layout, round trip, and malformed files.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "common/status.hpp"
#include "common/ss_file.hpp"

using namespace common;

namespace {
struct Tmp {
  std::filesystem::path dir = std::filesystem::temp_directory_path() / ("ss_test_" + std::to_string(::getpid()));
  Tmp() { std::filesystem::create_directories(dir); }
  ~Tmp() { std::filesystem::remove_all(dir); }
  std::string file(const char* n) const { return (dir / n).string(); }
};

common::SphereSet sample(std::size_t n) {
  common::SphereSet s;
  s.time = 123.5;
  for (std::size_t i = 0; i < n; ++i) {
    s.id.push_back(3 * i + 1);
    for (int d = 0; d < 3; ++d) {
      s.position.push_back(1e4 * (i + 1) + d);
      s.velocity.push_back(-2.5 * i + d);
      s.spin.push_back(1e-4 * (d + 1));
    }
    s.mass.push_back(1e12 * (i + 1));
    s.radius.push_back(100.0);
  }
  return s;
}
}  // namespace

TEST(SsFormat, SiRoundTripIsExactAndLayoutIsBigEndian) {
  Tmp t;
  const auto s = sample(5);
  write_ss(t.file("a.ss"), s, SsUnits::si(), 12);
  EXPECT_EQ(std::filesystem::file_size(t.file("a.ss")), 16u + 96u * 5u);
  std::ifstream in(t.file("a.ss"), std::ios::binary);
  unsigned char h[16];
  in.read(reinterpret_cast<char*>(h), 16);
  EXPECT_EQ(h[8], 0);  // n_data = 5, big-endian
  EXPECT_EQ(h[11], 5);
  EXPECT_EQ(h[12], 0xff);  // magic -1
  EXPECT_EQ(h[15], 0xff);
  EXPECT_EQ(h[0], 0x40);  // 123.5 = 0x405EE00000000000
  EXPECT_EQ(h[1], 0x5e);
  const auto r = read_ss(t.file("a.ss"), SsUnits::si());
  EXPECT_EQ(r.id, s.id);
  EXPECT_EQ(r.position, s.position);
  EXPECT_EQ(r.velocity, s.velocity);
  EXPECT_EQ(r.spin, s.spin);
  EXPECT_EQ(r.mass, s.mass);
  EXPECT_EQ(r.radius, s.radius);
  EXPECT_TRUE(std::filesystem::exists(t.file("a.ss.json")));
}

TEST(SsFormat, PkdgravUnitsRoundTrip) {
  Tmp t;
  const auto s = sample(7);
  const auto u = SsUnits::pkdgrav();
  EXPECT_NEAR(u.time, 5.0226e6, 1e3);  // yr / 2 pi
  write_ss(t.file("b.ss"), s, u);
  const auto r = read_ss(t.file("b.ss"), u);
  for (std::size_t i = 0; i < s.position.size(); ++i) {
    EXPECT_NEAR(r.position[i], s.position[i], 4e-16 * std::fabs(s.position[i]));
    EXPECT_NEAR(r.velocity[i], s.velocity[i], 4e-16 * std::fabs(s.velocity[i]) + 1e-300);
  }
  for (std::size_t i = 0; i < s.mass.size(); ++i) EXPECT_NEAR(r.mass[i], s.mass[i], 4e-16 * s.mass[i]);
  EXPECT_NEAR(r.time, s.time, 1e-15 * s.time);
}

TEST(SsFormat, MalformedFilesAreRejected) {
  Tmp t;
  write_ss(t.file("c.ss"), sample(3), SsUnits::si());
  std::filesystem::resize_file(t.file("c.ss"), 16 + 96 * 2 + 5);
  EXPECT_THROW(read_ss(t.file("c.ss"), SsUnits::si()), common::InputError);
  std::ofstream(t.file("d.ss"), std::ios::binary) << std::string("\x40\0\0\0\0\0\0\0\0\0\0\0\xff\xff\xd8\xab", 16);
  try {
    read_ss(t.file("d.ss"), SsUnits::si());
    FAIL() << "reduced-format magic accepted";
  } catch (const common::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("magic"), std::string::npos);
  }
  EXPECT_THROW(read_ss(t.file("none.ss"), SsUnits::si()), common::InputError);
}
