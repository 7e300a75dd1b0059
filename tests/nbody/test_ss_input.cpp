/// @file test_ss_input.cpp
/// ssdem-grav reads a pkdgrav .ss file (initial.source = "ss", common/ss_file.hpp): records built
/// byte by byte here in pkdgrav units arrive in SI (units checked against the Gaussian
/// gravitational constant, independent of the reader's own constants); ids come from org_idx;
/// duplicate ids, out-of-bounds values, a missing path and a truncated file are refused, the last
/// by the executable with exit 2 and a message naming the file.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "common/sphere_file.hpp"
#include "common/ss_file.hpp"
#include "common/status.hpp"
#include "ssdem/scene_setup.hpp"

using namespace ssdem;
namespace fs = std::filesystem;

namespace {

// Independent pkdgrav units: 1 AU (IAU 2012); the time unit is 1/k days, k = 0.01720209895 the
// Gaussian gravitational constant (AU^{3/2} M_sun^{-1/2} day^{-1}), i.e. one year / (2 pi). The
// reader derives it from G and M_sun instead; the two agree to ~1e-5 (G M_sun's uncertainty), so
// the tolerance below is 3e-5 relative: forgetting 2 pi, or the time unit in a velocity or spin,
// is off by a factor >= 2.
constexpr double kAU = 1.495978707e11, kMsun = 1.98847e30, kTimeUnit = 86400.0 / 0.01720209895;
constexpr double kUnitTol = 3e-5;

struct Record {
  double m, r, x[3], v[3], w[3];
  std::int32_t color, org;
};

void put_f64(std::string& b, double x) {
  const auto u = std::bit_cast<std::uint64_t>(x);
  for (int i = 7; i >= 0; --i) b.push_back(static_cast<char>((u >> (8 * i)) & 0xff));
}
void put_i32(std::string& b, std::int32_t x) {
  const auto u = static_cast<std::uint32_t>(x);
  for (int i = 3; i >= 0; --i) b.push_back(static_cast<char>((u >> (8 * i)) & 0xff));
}
/// Bytes of a standard .ss file (XDR: big-endian; 16-byte header, 96-byte records).
std::string ss_bytes(const std::vector<Record>& recs, double time = 0.25) {
  std::string b;
  put_f64(b, time);
  put_i32(b, static_cast<std::int32_t>(recs.size()));
  put_i32(b, -1);
  for (const Record& r : recs) {
    put_f64(b, r.m);
    put_f64(b, r.r);
    for (double c : r.x) put_f64(b, c);
    for (double c : r.v) put_f64(b, c);
    for (double c : r.w) put_f64(b, c);
    put_i32(b, r.color);
    put_i32(b, r.org);
  }
  return b;
}

struct Dir {
  fs::path p = fs::temp_directory_path() / ("ssdem_ss_" + std::to_string(getpid()));
  Dir() {
    fs::remove_all(p);
    fs::create_directories(p);
  }
  ~Dir() { fs::remove_all(p); }
  std::string f(const std::string& n) const { return (p / n).string(); }
  std::string write(const std::string& n, const std::string& bytes) const {
    std::ofstream(f(n), std::ios::binary) << bytes;
    return f(n);
  }
};

// Three spheres of a small rubble pile, in pkdgrav units, at awkward values (a few hundred metres
// apart, a few cm/s, spins of hours).
std::vector<Record> pile() {
  return {{1.3e-18, 7.3e-10, {1.1e-9, -2.3e-9, 0.7e-9}, {1.7e-6, -0.3e-6, 2.9e-7}, {3.1e-2, 0.0, -1.7e-2}, 3, 17},
          {2.9e-18, 9.1e-10, {-3.3e-9, 0.4e-9, 1.9e-9}, {-2.2e-6, 1.1e-6, 0.0}, {0.0, 4.4e-2, 0.0}, 5, 4},
          {0.6e-18, 5.2e-10, {0.2e-9, 3.8e-9, -2.7e-9}, {0.0, 0.0, -3.9e-6}, {-1.3e-2, 2.0e-2, 5.5e-3}, 3, 230}};
}

common::Scene ss_scene(const std::string& path, const std::string& extra = "") {
  return common::Scene::parse(ssdem_schema(),
                              "[time]\nend = 1.0\ndt = 0.01\n[initial]\nsource = \"ss\"\nss = \"" + path + "\"\n" + extra,
                              "scene.toml");
}

std::string message_of(const common::Scene& sc) {
  try {
    initial_spheres(sc);
  } catch (const common::InputError& e) {
    return e.what();
  }
  return "(accepted)";
}

}  // namespace

TEST(SsInput, PkdgravUnitsArriveInSiWithIdsFromOrgIdx) {
  Dir d;
  const auto recs = pile();
  const Spheres sp = initial_spheres(ss_scene(d.write("pile.ss", ss_bytes(recs))));
  ASSERT_EQ(sp.size(), 3u);
  const double vu = kAU / kTimeUnit, wu = 1.0 / kTimeUnit;
  for (std::size_t i = 0; i < 3; ++i) {
    const Record& r = recs[i];
    EXPECT_EQ(sp.id[i], static_cast<std::uint64_t>(r.org));
    EXPECT_NEAR(sp.m[i], r.m * kMsun, 1e-15 * r.m * kMsun);
    EXPECT_NEAR(sp.s[i], r.r * kAU, 1e-15 * r.r * kAU);
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(sp.x[i][k], r.x[k] * kAU, 1e-15 * std::fabs(r.x[k] * kAU));
      EXPECT_NEAR(sp.v[i][k], r.v[k] * vu, kUnitTol * std::fabs(r.v[k] * vu) + 1e-300);
      EXPECT_NEAR(sp.w[i][k], r.w[k] * wu, kUnitTol * std::fabs(r.w[k] * wu) + 1e-300);
    }
  }
  // the numbers a user checks: 1 velocity unit = 29.78 km/s, the time unit = 58.13 days
  EXPECT_NEAR(sp.v[0][0] / recs[0].v[0], 2.9785e4, 1.0);
  EXPECT_NEAR(common::SsUnits::pkdgrav().time / 86400.0, 58.1316, 1e-3);
}

TEST(SsInput, SiFilesFromTheCommonWriterRoundTripExactly) {
  Dir d;
  common::SphereSet s;
  s.resize(4);
  for (std::size_t i = 0; i < 4; ++i) {
    s.id[i] = 1000 - 7 * i;
    s.mass[i] = 3.7e9 * (i + 1.3);
    s.radius[i] = 61.7 + 3.1 * i;
    for (int k = 0; k < 3; ++k) {
      s.position[3 * i + k] = 437.1 * (i + 0.7) - 113.3 * k;
      s.velocity[3 * i + k] = 0.031 * (k - 1.5) * (i + 1);
      s.spin[3 * i + k] = 1.7e-4 * (k + 0.5) - 2e-4 * i;
    }
  }
  common::write_ss(d.f("si.ss"), s, common::SsUnits::si());
  const Spheres sp = initial_spheres(ss_scene(d.f("si.ss"), "ss_units = \"si\"\n"));
  ASSERT_EQ(sp.size(), 4u);
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_EQ(sp.id[i], s.id[i]);
    EXPECT_EQ(sp.m[i], s.mass[i]);
    EXPECT_EQ(sp.s[i], s.radius[i]);
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(sp.x[i][k], s.position[3 * i + k]);
      EXPECT_EQ(sp.v[i][k], s.velocity[3 * i + k]);
      EXPECT_EQ(sp.w[i][k], s.spin[3 * i + k]);
    }
  }
}

TEST(SsInput, BadFilesAndKeysAreRefusedNamingFileAndKey) {
  Dir d;
  auto recs = pile();
  recs[2].org = recs[0].org;
  std::string m = message_of(ss_scene(d.write("dup.ss", ss_bytes(recs))));
  EXPECT_NE(m.find("dup.ss"), std::string::npos) << m;
  EXPECT_NE(m.find("duplicate id 17"), std::string::npos) << m;
  recs = pile();
  recs[1].x[0] = 10.0;  // 10 AU > the 1e12 m bound (common/finite.hpp)
  m = message_of(ss_scene(d.write("far.ss", ss_bytes(recs))));
  EXPECT_NE(m.find("far.ss: position"), std::string::npos) << m;
  EXPECT_NE(m.find("index 1 is outside the allowed range [-1000000000000, 1000000000000] m"), std::string::npos) << m;
  recs = pile();
  recs[0].org = -3;  // aggregate member
  m = message_of(ss_scene(d.write("agg.ss", ss_bytes(recs))));
  EXPECT_NE(m.find("agg.ss: record 0"), std::string::npos) << m;
  recs = pile();
  recs[2].w[1] = std::nan("");
  m = message_of(ss_scene(d.write("nan.ss", ss_bytes(recs))));
  EXPECT_NE(m.find("nan.ss: record 2: non-finite"), std::string::npos) << m;
  m = message_of(ss_scene(""));
  EXPECT_NE(m.find("scene.toml: initial.ss: required for source = ss"), std::string::npos) << m;
  EXPECT_THROW(ss_scene(d.f("pile.ss"), "ss_units = \"cgs\"\n"), common::InputError);
}

TEST(SsInput, ToolRunsFromAnSsFileAndRefusesATruncatedOneWithExit2) {
  Dir d;
  const std::string good = d.write("pile.ss", ss_bytes(pile()));
  std::string bytes = ss_bytes(pile());
  bytes.resize(bytes.size() - 40);
  const std::string cut = d.write("cut.ss", bytes);
  auto run = [&](const std::string& ss, const std::string& out) {
    std::ofstream(d.f("s.toml")) << "[time]\nend = 0.05\ndt = 0.01\n[initial]\nsource = \"ss\"\nss = \"" << ss
                                 << "\"\n[contact]\nenabled = false\n[output]\ndirectory = \"" << d.f(out) << "\"\n";
    const std::string cmd = std::string("OMP_NUM_THREADS=1 ") + SSDEM_GRAV_EXE + " --quiet --scene " + d.f("s.toml") +
                            " > " + d.f("log") + " 2>&1";
    const int rc = std::system(cmd.c_str());
    return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
  };
  ASSERT_EQ(run(good, "ok"), 0);
  common::SphereSet last;
  for (const auto& e : fs::directory_iterator(d.f("ok")))
    if (e.path().filename().string().rfind("snap_", 0) == 0 && e.path().extension() == ".h5") {
      const auto s = common::read_sphere_set(e.path().string());
      if (last.id.empty() || s.step > last.step) last = s;
    }
  EXPECT_EQ(last.id, (std::vector<std::uint64_t>{17, 4, 230}));
  EXPECT_GE(last.step, 5);  // the run reached its end (t = 0.05 s, dt = 0.01 s)
  EXPECT_NEAR(last.mass[1], 2.9e-18 * kMsun, 1e-15 * 2.9e-18 * kMsun);

  EXPECT_EQ(run(cut, "bad"), 2);
  std::stringstream log;
  log << std::ifstream(d.f("log")).rdbuf();
  EXPECT_NE(log.str().find(cut + ": size 264 B does not match 3 standard records (expected 304 B)"), std::string::npos)
      << log.str();
  EXPECT_FALSE(fs::exists(d.f("bad") + "/series.csv"));
}
