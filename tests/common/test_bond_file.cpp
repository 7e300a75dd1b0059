/// @file test_bond_file.cpp
/// The /bonds group of sphere files (common/bond_file.hpp): bit-exact round trip with units, no
/// group without bonds, and every refusal of the reader naming the file, the dataset and the
/// valid range (values edited in place in a good file).
#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "common/h5.hpp"
#include "common/status.hpp"
#include "test_util.hpp"

using namespace common;

namespace {
SphereSet bonded(std::size_t n = 12) {
  SphereSet s = testutil::sample_spheres(n);
  for (auto& id : s.id) id = 1000 + 3 * id;  // ids are not row numbers
  s.bonds.add(1000, 1003, 1.25e7, 4.5e6, 3.3e5, 6.1e5, 41.5, 203.25);
  s.bonds.add(1006, 1033, 0.0, 0.0, 0.0, 0.0, 1e-3, 1e12);  // the range ends
  s.bonds.add(1030, 1009, 1e30, 1e30, 1e300, 1e300, 1e12, 1e-3);
  return s;
}

// Overwrite dataset `ds` of `path` with `v` (same shape).
template <class T>
void poke(const std::string& path, const std::string& ds, const std::vector<T>& v) {
  const hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  const hid_t d = H5Dopen2(f, ds.c_str(), H5P_DEFAULT);
  ASSERT_GE(d, 0);
  ASSERT_GE(H5Dwrite(d, std::is_same_v<T, double> ? H5T_NATIVE_DOUBLE : H5T_NATIVE_UINT64, H5S_ALL, H5S_ALL,
                     H5P_DEFAULT, v.data()),
            0);
  H5Dclose(d);
  H5Fclose(f);
}

// Read `path` and expect an InputError whose message holds every string of `parts`.
void expect_refused(const std::string& path, const std::vector<std::string>& parts) {
  try {
    read_sphere_set(path);
    ADD_FAILURE() << "accepted";
  } catch (const InputError& e) {
    for (const auto& p : parts) EXPECT_NE(std::string(e.what()).find(p), std::string::npos) << e.what() << " / " << p;
  }
}
}  // namespace

TEST(BondFile, RoundTripIsBitExactWithUnits) {
  testutil::TempDir dir;
  const std::string path = dir.file("b.h5");
  SphereSet a = bonded();
  a.bonds.broken = {0, 1, 0};
  write_sphere_set(path, a, testutil::sample_provenance());
  const SphereSet b = read_sphere_set(path);
  EXPECT_EQ(b.bonds.id_a, a.bonds.id_a);
  EXPECT_EQ(b.bonds.id_b, a.bonds.id_b);
  EXPECT_EQ(b.bonds.kn, a.bonds.kn);
  EXPECT_EQ(b.bonds.ks, a.bonds.ks);
  EXPECT_EQ(b.bonds.sigma_c, a.bonds.sigma_c);
  EXPECT_EQ(b.bonds.tau_c, a.bonds.tau_c);
  EXPECT_EQ(b.bonds.radius, a.bonds.radius);
  EXPECT_EQ(b.bonds.length0, a.bonds.length0);
  EXPECT_EQ(b.bonds.broken, a.bonds.broken);
  h5::Handle f = h5::open_file_read(path);
  EXPECT_EQ(h5::unit_of(f, "/bonds/kn"), "N/m^3");
  EXPECT_EQ(h5::unit_of(f, "/bonds/ks"), "N/m^3");
  EXPECT_EQ(h5::unit_of(f, "/bonds/sigma_c"), "Pa");
  EXPECT_EQ(h5::unit_of(f, "/bonds/tau_c"), "Pa");
  EXPECT_EQ(h5::unit_of(f, "/bonds/radius"), "m");
  EXPECT_EQ(h5::unit_of(f, "/bonds/length0"), "m");
  EXPECT_EQ(h5::unit_of(f, "/bonds/id_a"), "1");
  EXPECT_EQ(h5::unit_of(f, "/bonds/sphere_index"), "1");
  EXPECT_EQ(h5::unit_of(f, "/bonds/broken"), "1");
  // rows of the bonded spheres: ids 1000 + 3 r
  EXPECT_EQ(h5::read_u64(f, "/bonds/sphere_index", 3, 2, path), (std::vector<std::uint64_t>{0, 1, 2, 11, 10, 3}));
}

TEST(BondFile, NoBondsNoGroup) {
  testutil::TempDir dir;
  const std::string path = dir.file("s.h5");
  write_sphere_set(path, testutil::sample_spheres(4), testutil::sample_provenance());
  h5::Handle f = h5::open_file_read(path);
  EXPECT_FALSE(h5::exists(f, "bonds"));
  EXPECT_TRUE(read_sphere_set(path).bonds.empty());
}

TEST(BondFile, WriterRefusesUnknownIds) {
  testutil::TempDir dir;
  SphereSet a = bonded();
  a.bonds.id_b[1] = 999;
  EXPECT_THROW(write_sphere_set(dir.file("x.h5"), a, testutil::sample_provenance()), InputError);
}

TEST(BondFile, BadValuesAreRefusedNamingFileDatasetAndRange) {
  testutil::TempDir dir;
  struct Case {
    std::string ds;
    std::function<void(const std::string&)> edit;
    std::vector<std::string> msg;
  };
  const double nan = std::nan("");
  const std::vector<Case> cases = {
      {"kn<0", [](const std::string& p) { poke<double>(p, "/bonds/kn", {1e7, -1.0, 1e7}); },
       {"/bonds/kn", "row 1", "[0, 1e+30] N/m^3"}},
      {"ks nan", [&](const std::string& p) { poke<double>(p, "/bonds/ks", {1e7, 1e7, nan}); },
       {"/bonds/ks", "row 2", "[0, 1e+30]"}},
      {"sigma inf", [](const std::string& p) { poke<double>(p, "/bonds/sigma_c", {INFINITY, 1.0, 1.0}); },
       {"/bonds/sigma_c", "row 0", "[0, 1e+300] Pa"}},
      {"tau<0", [](const std::string& p) { poke<double>(p, "/bonds/tau_c", {1.0, 1.0, -3.0}); },
       {"/bonds/tau_c", "row 2"}},
      {"radius 0", [](const std::string& p) { poke<double>(p, "/bonds/radius", {1.0, 0.0, 1.0}); },
       {"/bonds/radius", "row 1", "(0, 1e+12] m"}},
      {"length huge", [](const std::string& p) { poke<double>(p, "/bonds/length0", {1.0, 2e12, 1.0}); },
       {"/bonds/length0", "row 1", "(0, 1e+12] m"}},
      {"unknown id",
       [](const std::string& p) {
         poke<std::uint64_t>(p, "/bonds/id_b", {1003, 77, 1009});
       },
       {"/bonds/id_b", "id 77", "row 1", "/spheres/id"}},
      {"self bond",
       [](const std::string& p) {
         poke<std::uint64_t>(p, "/bonds/id_b", {1000, 1033, 1009});
         poke<std::uint64_t>(p, "/bonds/sphere_index", {0, 0, 2, 11, 10, 3});
       },
       {"/bonds/id_b", "row 0", "to itself"}},
      {"twice",
       [](const std::string& p) {
         poke<std::uint64_t>(p, "/bonds/id_a", {1000, 1003, 1030});
         poke<std::uint64_t>(p, "/bonds/id_b", {1003, 1000, 1009});
         poke<std::uint64_t>(p, "/bonds/sphere_index", {0, 1, 1, 0, 10, 3});
       },
       {"/bonds/id_a", "bonded twice", "rows 0 and 1"}},
      {"index", [](const std::string& p) { poke<std::uint64_t>(p, "/bonds/sphere_index", {0, 1, 2, 11, 10, 4}); },
       {"/bonds/sphere_index", "row 2"}},
      {"broken 2", [](const std::string& p) { poke<double>(p, "/bonds/broken", {0.0, 2.0, 0.0}); },
       {"/bonds/broken", "row 1", "0 = intact or 1 = broken"}},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.ds);
    const std::string path = dir.file("bad.h5");
    SphereSet a = bonded();
    a.bonds.broken = {0, 0, 0};
    write_sphere_set(path, a, testutil::sample_provenance());
    c.edit(path);
    auto msg = c.msg;
    msg.push_back(path);
    expect_refused(path, msg);
  }
  // a missing column and a wrong length
  const std::string path = dir.file("bad2.h5");
  write_sphere_set(path, bonded(), testutil::sample_provenance());
  {
    const hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    H5Ldelete(f, "/bonds/tau_c", H5P_DEFAULT);
    H5Fclose(f);
  }
  expect_refused(path, {path, "/bonds/tau_c"});
  write_sphere_set(path, bonded(), testutil::sample_provenance());
  {
    h5::quiet_errors();
    const hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    H5Ldelete(f, "/bonds/kn", H5P_DEFAULT);
    const double v[2] = {1.0, 2.0};
    h5::write_dataset(f, "/bonds/kn", v, 2, 1, "N/m^3");
    H5Fclose(f);
  }
  expect_refused(path, {path, "/bonds/kn"});
}
