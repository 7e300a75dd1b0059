/// @file test_malformed.cpp
/// Malformed inputs: each one is rejected with InputError (exit code 2 through ToolApp) and a
/// message naming the file and the offending dataset or attribute.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>

#include "common/cli.hpp"
#include "common/h5.hpp"
#include "common/status.hpp"
#include "test_util.hpp"

using namespace common;

namespace {

/// Write a good particle file, then damage it with `edit` (an open read-write file handle).
std::string damaged_particles(const testutil::TempDir& dir, const std::function<void(hid_t)>& edit) {
  const std::string path = dir.file("bad.h5");
  write_particle_snapshot(path, testutil::sample_particles(10), testutil::sample_provenance());
  h5::quiet_errors();
  h5::Handle f(H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT));
  edit(f);
  return path;
}

std::string damaged_spheres(const testutil::TempDir& dir, const std::function<void(hid_t)>& edit) {
  const std::string path = dir.file("bad_spheres.h5");
  write_sphere_set(path, testutil::sample_spheres(10), testutil::sample_provenance());
  h5::quiet_errors();
  h5::Handle f(H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT));
  edit(f);
  return path;
}

void replace_doubles(hid_t f, const std::string& path, std::vector<double> v, std::size_t rows, std::size_t cols) {
  H5Ldelete(f, path.c_str(), H5P_DEFAULT);
  h5::write_dataset(f, path, v.data(), rows, cols, "x");
}

void set_value(hid_t f, const std::string& path, std::size_t index, double value) {
  h5::Handle ds(H5Dopen2(f, path.c_str(), H5P_DEFAULT));
  h5::Handle space(H5Dget_space(ds));
  hsize_t dims[2];
  const int nd = H5Sget_simple_extent_dims(space, dims, nullptr);
  std::vector<double> v(dims[0] * (nd == 2 ? dims[1] : 1));
  H5Dread(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data());
  v[index] = value;
  H5Dwrite(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data());
}

/// Replace dataset `path` by one of file type `file_type` holding `rows` x `cols` values of 1
/// (cols = 1: 1-D), to test dtype checks on types the writers never produce.
void replace_with_type(hid_t f, const std::string& path, hid_t file_type, std::size_t rows, std::size_t cols) {
  H5Ldelete(f, path.c_str(), H5P_DEFAULT);
  const hsize_t dims[2] = {rows, cols};
  h5::Handle space(H5Screate_simple(cols == 1 ? 1 : 2, dims, nullptr));
  h5::Handle ds(H5Dcreate2(f, path.c_str(), file_type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT));
  const std::vector<double> ones(rows * cols, 1.0);  // converted to the file type by HDF5
  H5Dwrite(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, ones.data());
  h5::write_attr(ds, "unit", std::string("1"));
}

void set_string_attr(hid_t f, const char* name, const std::string& v) {
  H5Adelete(f, name);
  h5::write_attr(f, name, v);
}

std::string particle_error(const std::string& path) {
  try {
    read_particle_snapshot(path);
  } catch (const InputError& e) {
    return e.what();
  }
  return "(accepted)";
}

std::string sphere_error(const std::string& path) {
  try {
    read_sphere_set(path);
  } catch (const InputError& e) {
    return e.what();
  }
  return "(accepted)";
}

struct Case {
  const char* name;
  std::function<void(hid_t)> edit;
  const char* expect;  // substring of the message
};

}  // namespace

TEST(Malformed, ParticleSnapshotCases) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  const std::vector<Case> cases = {
      {"missing dataset", [](hid_t f) { H5Ldelete(f, "/particles/mass", H5P_DEFAULT); }, "/particles/mass: required dataset is missing"},
      {"missing grid", [](hid_t f) { H5Ldelete(f, "/grid", H5P_DEFAULT); }, "grid: required group is missing"},
      {"wrong shape", [](hid_t f) { replace_doubles(f, "/particles/position", std::vector<double>(20, 0.0), 10, 2); }, "/particles/position: wrong shape (10, 2), expected (10, 3)"},
      {"wrong row count", [](hid_t f) { replace_doubles(f, "/particles/mass", std::vector<double>(9, 1.0), 9, 1); }, "/particles/mass: wrong shape (9,), expected (10,)"},
      {"wrong dtype", [](hid_t f) {
         H5Ldelete(f, "/particles/velocity", H5P_DEFAULT);
         std::vector<std::int32_t> v(30, 1);
         h5::write_dataset(f, "/particles/velocity", v.data(), 10, 3, "m/s");
       }, "/particles/velocity: wrong dtype: expected float64"},
      {"int64 id", [](hid_t f) { replace_with_type(f, "/particles/id", H5T_STD_I64LE, 10, 1); }, "/particles/id: wrong dtype: expected uint64"},
      {"uint32 id", [](hid_t f) { replace_with_type(f, "/particles/id", H5T_STD_U32LE, 10, 1); }, "/particles/id: wrong dtype: expected uint64"},
      {"float64 id", [](hid_t f) { replace_with_type(f, "/particles/id", H5T_IEEE_F64LE, 10, 1); }, "/particles/id: wrong dtype: expected uint64"},
      {"unknown format", [](hid_t f) { set_string_attr(f, "format", "something.else"); }, "unknown format 'something.else'"},
      {"sphere file given", [](hid_t f) { set_string_attr(f, "format", "ssdem.spheres"); }, "expected 'mpm-frag.particles'"},
      {"newer version", [](hid_t f) { H5Adelete(f, "format_version"); h5::write_attr(f, "format_version", std::int64_t{99}); }, "newer than this tool reads"},
      {"NaN position", [=](hid_t f) { set_value(f, "/particles/position", 7, nan); }, "/particles/position: non-finite value (NaN or Inf) at row 2"},
      {"Inf velocity", [=](hid_t f) { set_value(f, "/particles/velocity", 0, inf); }, "/particles/velocity: non-finite"},
      {"NaN mass", [=](hid_t f) { set_value(f, "/particles/mass", 3, nan); }, "/particles/mass: non-finite value (NaN or Inf) at row 3"},
      {"zero mass", [](hid_t f) { set_value(f, "/particles/mass", 4, 0.0); }, "/particles/mass: non-positive value"},
      {"negative volume", [](hid_t f) { set_value(f, "/particles/volume", 4, -1.0); }, "/particles/volume: non-positive value"},
      {"NaN in state field", [=](hid_t f) { set_value(f, "/particles/damage", 1, nan); }, "/particles/damage: non-finite"},
      {"bad cell size", [](hid_t f) {
         h5::Handle g(H5Gopen2(f, "grid", H5P_DEFAULT));
         H5Adelete(g, "cell_size");
         h5::write_attr(g, "cell_size", std::vector<double>{0.1, 0.0, 0.1});
       }, "/grid/cell_size: must be finite and > 0"},
  };
  for (const auto& c : cases) {
    testutil::TempDir dir;
    const std::string path = damaged_particles(dir, c.edit);
    const std::string e = particle_error(path);
    EXPECT_NE(e.find(c.expect), std::string::npos) << c.name << ": got '" << e << "'";
    EXPECT_NE(e.find(path), std::string::npos) << c.name << ": message must name the file";
  }
}

TEST(Malformed, SphereSetCases) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  const std::vector<Case> cases = {
      {"zero radius", [](hid_t f) { set_value(f, "/spheres/radius", 2, 0.0); }, "/spheres/radius: non-positive value"},
      {"negative mass", [](hid_t f) { set_value(f, "/spheres/mass", 2, -5.0); }, "/spheres/mass: non-positive value"},
      {"NaN spin", [=](hid_t f) { set_value(f, "/spheres/spin", 5, nan); }, "/spheres/spin: non-finite"},
      {"missing spin", [](hid_t f) { H5Ldelete(f, "/spheres/spin", H5P_DEFAULT); }, "/spheres/spin: required dataset is missing"},
      {"missing group", [](hid_t f) { H5Ldelete(f, "/spheres", H5P_DEFAULT); }, "spheres: required group is missing"},
      {"particle file given", [](hid_t f) { set_string_attr(f, "format", "mpm-frag.particles"); }, "expected 'ssdem.spheres'"},
      {"format attribute missing", [](hid_t f) { H5Adelete(f, "format"); }, "not a 'ssdem.spheres' file"},
      // shape
      {"position N x 2", [](hid_t f) { replace_doubles(f, "/spheres/position", std::vector<double>(20, 0.0), 10, 2); }, "/spheres/position: wrong shape (10, 2), expected (10, 3)"},
      {"velocity 1-D", [](hid_t f) { replace_doubles(f, "/spheres/velocity", std::vector<double>(30, 0.0), 30, 1); }, "/spheres/velocity: wrong shape (30,), expected (10, 3)"},
      {"mass row count", [](hid_t f) { replace_doubles(f, "/spheres/mass", std::vector<double>(9, 1.0), 9, 1); }, "/spheres/mass: wrong shape (9,), expected (10,)"},
      {"radius N x 3", [](hid_t f) { replace_doubles(f, "/spheres/radius", std::vector<double>(30, 1.0), 10, 3); }, "/spheres/radius: wrong shape (10, 3), expected (10,)"},
      {"spin row count", [](hid_t f) { replace_doubles(f, "/spheres/spin", std::vector<double>(33, 0.0), 11, 3); }, "/spheres/spin: wrong shape (11, 3), expected (10, 3)"},
      {"id N x 2", [](hid_t f) { replace_with_type(f, "/spheres/id", H5T_STD_U64LE, 10, 2); }, "/spheres/id: wrong shape (10, 2), expected (N,)"},
      // dtype
      {"int32 velocity", [](hid_t f) { replace_with_type(f, "/spheres/velocity", H5T_STD_I32LE, 10, 3); }, "/spheres/velocity: wrong dtype: expected float64"},
      {"float32 mass", [](hid_t f) { replace_with_type(f, "/spheres/mass", H5T_IEEE_F32LE, 10, 1); }, "/spheres/mass: wrong dtype: expected float64"},
      {"int64 id", [](hid_t f) { replace_with_type(f, "/spheres/id", H5T_STD_I64LE, 10, 1); }, "/spheres/id: wrong dtype: expected uint64"},
      {"float64 id", [](hid_t f) { replace_with_type(f, "/spheres/id", H5T_IEEE_F64LE, 10, 1); }, "/spheres/id: wrong dtype: expected uint64"},
      {"string format_version", [](hid_t f) { set_string_attr(f, "format_version", "1"); }, "format_version: attribute is not an integer"},
      // format and version
      {"unknown format", [](hid_t f) { set_string_attr(f, "format", "pkdgrav.ss"); }, "/format: unknown format 'pkdgrav.ss', expected 'ssdem.spheres'"},
      {"newer version", [](hid_t f) { H5Adelete(f, "format_version"); h5::write_attr(f, "format_version", std::int64_t{2}); }, "/format_version: version 2 is newer than this tool reads (1)"},
      // non-finite values
      {"NaN position", [=](hid_t f) { set_value(f, "/spheres/position", 13, nan); }, "/spheres/position: non-finite value (NaN or Inf) at row 4"},
      {"Inf position", [=](hid_t f) { set_value(f, "/spheres/position", 29, -inf); }, "/spheres/position: non-finite value (NaN or Inf) at row 9"},
      {"Inf velocity", [=](hid_t f) { set_value(f, "/spheres/velocity", 3, inf); }, "/spheres/velocity: non-finite value (NaN or Inf) at row 1"},
      {"NaN velocity", [=](hid_t f) { set_value(f, "/spheres/velocity", 0, nan); }, "/spheres/velocity: non-finite value (NaN or Inf) at row 0"},
      {"NaN mass", [=](hid_t f) { set_value(f, "/spheres/mass", 6, nan); }, "/spheres/mass: non-finite value (NaN or Inf) at row 6"},
      {"Inf mass", [=](hid_t f) { set_value(f, "/spheres/mass", 7, inf); }, "/spheres/mass: non-finite value (NaN or Inf) at row 7"},
      {"Inf radius", [=](hid_t f) { set_value(f, "/spheres/radius", 8, inf); }, "/spheres/radius: non-finite value (NaN or Inf) at row 8"},
      {"NaN in optional field", [=](hid_t f) { set_value(f, "/spheres/damage", 2, nan); }, "/spheres/damage: non-finite value (NaN or Inf) at row 2"},
  };
  for (const auto& c : cases) {
    testutil::TempDir dir;
    const std::string path = damaged_spheres(dir, c.edit);
    const std::string e = sphere_error(path);
    EXPECT_NE(e.find(c.expect), std::string::npos) << c.name << ": got '" << e << "'";
    EXPECT_EQ(e.rfind(path + ": ", 0), 0u) << c.name << ": message must start with the file: '" << e << "'";
  }
}

TEST(Malformed, SphereSetTruncatedAndNonHdf5) {
  testutil::TempDir dir;
  const std::string good = dir.file("good.h5");
  write_sphere_set(good, testutil::sample_spheres(3000), testutil::sample_provenance());
  ASSERT_EQ(read_sphere_set(good).count(), 3000u);
  const auto size = std::filesystem::file_size(good);
  // Cut inside the superblock, the metadata and the raw data, and the very last byte.
  for (const double frac : {0.001, 0.1, 0.5, 0.9}) {
    for (const std::uintmax_t cut : {static_cast<std::uintmax_t>(frac * static_cast<double>(size)), size - 1}) {
      const std::string trunc = dir.file("trunc_" + std::to_string(cut) + ".h5");
      std::filesystem::copy_file(good, trunc, std::filesystem::copy_options::overwrite_existing);
      std::filesystem::resize_file(trunc, cut);
      const std::string e = sphere_error(trunc);
      EXPECT_EQ(e.rfind(trunc + ": ", 0), 0u) << "cut at " << cut << " of " << size << ": got '" << e << "'";
      EXPECT_TRUE(e.find("truncated") != std::string::npos || e.find("not an HDF5 file") != std::string::npos)
          << "cut at " << cut << ": got '" << e << "'";
    }
  }
  const std::string text = dir.file("spheres.csv.h5");
  std::ofstream(text) << "id,x,y,z\n0,1,2,3\n";
  EXPECT_EQ(sphere_error(text), text + ": not an HDF5 file (or truncated/corrupt)");
  const std::string empty = dir.file("empty.h5");
  std::ofstream(empty).close();
  EXPECT_EQ(sphere_error(empty), empty + ": not an HDF5 file (or truncated/corrupt)");
  EXPECT_EQ(sphere_error(dir.file("absent.h5")), dir.file("absent.h5") + ": file does not exist");
}

TEST(Malformed, TruncatedNonHdf5AndMissingFiles) {
  testutil::TempDir dir;
  const std::string good = dir.file("good.h5");
  write_particle_snapshot(good, testutil::sample_particles(2000), testutil::sample_provenance());
  const auto size = std::filesystem::file_size(good);
  const std::string trunc = dir.file("trunc.h5");
  std::filesystem::copy_file(good, trunc);
  std::filesystem::resize_file(trunc, size / 2);
  EXPECT_NE(particle_error(trunc).find("trunc.h5"), std::string::npos);
  EXPECT_NE(particle_error(trunc), "(accepted)");

  const std::string text = dir.file("text.h5");
  std::ofstream(text) << "this is not HDF5\n";
  EXPECT_NE(particle_error(text).find("not an HDF5 file"), std::string::npos);
  EXPECT_NE(particle_error(dir.file("absent.h5")).find("file does not exist"), std::string::npos);
  EXPECT_NE(particle_error(dir.path.string()).find("is a directory"), std::string::npos);
}

TEST(Malformed, ToolAppMapsErrorsToExitCodes) {
  testutil::TempDir dir;
  const std::string path = damaged_particles(dir, [](hid_t f) { H5Ldelete(f, "/particles/id", H5P_DEFAULT); });
  Schema schema("t");
  schema.add_string("input", std::nullopt, "input file");
  auto run = [&](std::vector<std::string> args, const ToolApp::Body& body) {
    ToolApp app("tool", "test tool", schema, false);
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    return app.run(static_cast<int>(argv.size()), argv.data(), body);
  };
  const auto read_input = [](const Scene& s, const Provenance&) {
    read_particle_snapshot(s.string("input"));
    return 0;
  };
  EXPECT_EQ(run({"tool", "--quiet", "--set", "input=" + path}, read_input), 2);
  EXPECT_EQ(run({"tool", "--quiet"}, read_input), 2);                      // required key missing
  EXPECT_EQ(run({"tool", "--quiet", "--set", "bogus=1"}, read_input), 2);  // unknown key
  EXPECT_EQ(run({"tool", "--no-such-flag"}, read_input), 2);               // usage error
  EXPECT_EQ(run({"tool", "--quiet", "--set", "input=x"}, [](const Scene&, const Provenance&) -> int {
              throw NumericalError("J <= 0");
            }), 3);
  EXPECT_EQ(run({"tool", "--quiet", "--set", "input=x"}, [](const Scene&, const Provenance&) -> int {
              throw IoError("disk full");
            }), 4);
  EXPECT_EQ(run({"tool", "--version"}, read_input), 0);
}
