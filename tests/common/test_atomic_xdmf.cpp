/// @file test_atomic_xdmf.cpp
/// Atomic writes (an interrupted write leaves the previous file intact) and XDMF/HDF5 agreement.
#include <gtest/gtest.h>

#include <fstream>
#include <regex>
#include <sstream>

#include "common/atomic_file.hpp"
#include "common/h5.hpp"
#include "common/status.hpp"
#include "common/xdmf.hpp"
#include "test_util.hpp"

using namespace common;

namespace {
std::string slurp(const std::string& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}
std::size_t file_count(const std::filesystem::path& dir) {
  std::size_t n = 0;
  for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator(dir)) ++n;
  return n;
}
}  // namespace

TEST(Atomic, InterruptedWriteKeepsPreviousFile) {
  testutil::TempDir dir;
  const std::string path = dir.file("snap.h5");
  const ParticleSnapshot first = testutil::sample_particles(50);
  write_particle_snapshot(path, first, testutil::sample_provenance());
  const std::string before = slurp(path);
  // Second write dies part-way (the hook throws after the datasets are written).
  ParticleSnapshot second = testutil::sample_particles(80);
  EXPECT_THROW(write_particle_snapshot(path, second, testutil::sample_provenance(),
                                       [](long long) { throw IoError("simulated disk full"); }),
               IoError);
  EXPECT_EQ(slurp(path), before);                       // old result intact, byte for byte
  EXPECT_EQ(read_particle_snapshot(path).count(), 50u);  // and still readable
  EXPECT_EQ(file_count(dir.path), 2u);                  // .h5 + .xmf, no temporary left behind
}

TEST(Atomic, MissingDirectoryIsIoError) {
  testutil::TempDir dir;
  EXPECT_THROW(write_text_atomic(dir.file("no/such/dir/x.txt"), "x"), IoError);
  EXPECT_THROW(write_sphere_set(dir.file("nodir/s.h5"), testutil::sample_spheres(3), testutil::sample_provenance()), IoError);
}

TEST(Atomic, TextReplaceAndAbandon) {
  testutil::TempDir dir;
  const std::string p = dir.file("a.txt");
  write_text_atomic(p, "one");
  write_text_atomic(p, "two");
  EXPECT_EQ(slurp(p), "two");
  {
    AtomicPath ap(p);
    std::ofstream(ap.temp_path()) << "three";
  }  // never committed
  EXPECT_EQ(slurp(p), "two");
  EXPECT_EQ(file_count(dir.path), 1u);
}

namespace {
/// Minimal well-formedness check: tags balance and nest (no attributes containing '>').
bool balanced_xml(const std::string& x) {
  std::vector<std::string> stack;
  std::size_t i = 0;
  while ((i = x.find('<', i)) != std::string::npos) {
    const std::size_t j = x.find('>', i);
    if (j == std::string::npos) return false;
    std::string tag = x.substr(i + 1, j - i - 1);
    i = j + 1;
    if (tag.empty() || tag[0] == '?' || tag[0] == '!') continue;
    if (tag.back() == '/') continue;
    const bool close = tag[0] == '/';
    std::string name = tag.substr(close ? 1 : 0, tag.find_first_of(" \t\n") - (close ? 1 : 0));
    if (close) {
      if (stack.empty() || stack.back() != name) return false;
      stack.pop_back();
    } else {
      stack.push_back(name);
    }
  }
  return stack.empty();
}

/// Check every DataItem of the sidecar against the HDF5 file: path exists, shape and dtype match.
void check_sidecar(const std::string& h5path, std::size_t expected_items) {
  const std::string xmf = slurp(xdmf_path_for(h5path));
  ASSERT_TRUE(balanced_xml(xmf)) << xmf;
  h5::Handle f = h5::open_file_read(h5path);
  const std::regex item(R"re(<DataItem Format="HDF" NumberType="(\w+)" Precision="(\d)" Dimensions="([\d ]+)">([^:<]+):([^<]+)</DataItem>)re");
  std::size_t n = 0;
  for (std::sregex_iterator it(xmf.begin(), xmf.end(), item), end; it != end; ++it, ++n) {
    const auto& m = *it;
    EXPECT_EQ(m[4].str(), std::filesystem::path(h5path).filename().string());
    const std::string ds = m[5].str();
    ASSERT_TRUE(h5::exists(f, ds)) << ds;
    const auto shape = h5::shape(f, ds, h5path);
    std::string dims;
    for (std::size_t k = 0; k < shape.size(); ++k) {
      if (k) dims += " ";
      dims += std::to_string(shape[k]);
    }
    EXPECT_EQ(m[3].str(), dims) << ds;
    h5::Handle d(H5Dopen2(f, ds.c_str(), H5P_DEFAULT));
    h5::Handle t(H5Dget_type(d));
    EXPECT_EQ(std::stoul(m[2].str()), H5Tget_size(t)) << ds;
    const H5T_class_t cls = H5Tget_class(t);
    const std::string nt = m[1].str();
    if (nt == "Float") EXPECT_EQ(cls, H5T_FLOAT) << ds;
    else {
      EXPECT_EQ(cls, H5T_INTEGER) << ds;
      EXPECT_EQ(nt == "UInt", H5Tget_sign(t) == H5T_SGN_NONE) << ds;
    }
  }
  EXPECT_EQ(n, expected_items);
}
}  // namespace

TEST(Xdmf, ParticleSidecarMatchesHdf5) {
  testutil::TempDir dir;
  const std::string path = dir.file("p.h5");
  write_particle_snapshot(path, testutil::sample_particles(33), testutil::sample_provenance());
  check_sidecar(path, 1 + 6 + 2);  // geometry + 6 required attributes + damage, stress
  const std::string xmf = slurp(xdmf_path_for(path));
  EXPECT_NE(xmf.find("AttributeType=\"Tensor6\""), std::string::npos);
  EXPECT_NE(xmf.find("NumberOfElements=\"33\""), std::string::npos);
}

TEST(Xdmf, SphereSidecarMatchesHdf5) {
  testutil::TempDir dir;
  const std::string path = dir.file("s.h5");
  write_sphere_set(path, testutil::sample_spheres(12), testutil::sample_provenance());
  check_sidecar(path, 1 + 5 + 1);
}

TEST(Xdmf, TemporalCollectionAndEscaping) {
  XdmfGrid a{"a<b", 0.5, 2, "x&y.h5", "/p/position", {}, {}, 0};
  XdmfGrid b{"c", 1.5, 2, "z.h5", "/p/position", {}, {}, 0};
  const std::string t = xdmf_text({a, b});
  EXPECT_TRUE(balanced_xml(t));
  EXPECT_NE(t.find("CollectionType=\"Temporal\""), std::string::npos);
  EXPECT_NE(t.find("a&lt;b"), std::string::npos);
  EXPECT_NE(t.find("x&amp;y.h5"), std::string::npos);
  EXPECT_NE(t.find("<Time Value=\"1.5\"/>"), std::string::npos);
}

// A sphere file with bonds: a spatial collection of the spheres (Polyvertex) and the bonds
// (Polyline, 2 nodes per element, connectivity = /bonds/sphere_index on the sphere positions,
// cell-centred bond attributes); every DataItem matches its dataset's shape and type.
TEST(Xdmf, BondsAreAPolylineGridOnTheSpherePositions) {
  testutil::TempDir dir;
  const std::string path = dir.file("sb.h5");
  SphereSet s = testutil::sample_spheres(12);
  for (std::uint64_t k = 0; k < 5; ++k) s.bonds.add(k, k + 7, 1e7, 4e6, 1e5, 2e5, 50.0, 200.0);
  s.bonds.broken = {0, 1, 0, 0, 1};
  write_sphere_set(path, s, testutil::sample_provenance());
  // spheres: geometry + 5 core attributes + damage; bonds: connectivity + geometry + 6 columns + broken
  check_sidecar(path, (1 + 5 + 1) + (1 + 1 + 6 + 1));
  const std::string xmf = slurp(xdmf_path_for(path));
  EXPECT_NE(xmf.find("CollectionType=\"Spatial\""), std::string::npos);
  EXPECT_NE(xmf.find("<Topology TopologyType=\"Polyline\" NumberOfElements=\"5\" NodesPerElement=\"2\">"),
            std::string::npos);
  EXPECT_NE(xmf.find("Dimensions=\"5 2\">sb.h5:/bonds/sphere_index</DataItem>"), std::string::npos);
  EXPECT_NE(xmf.find("<Attribute Name=\"broken\" AttributeType=\"Scalar\" Center=\"Cell\">"), std::string::npos);
  // the connectivity holds the rows of the bonded spheres
  h5::Handle f = h5::open_file_read(path);
  const auto idx = h5::read_u64(f, "/bonds/sphere_index", 5, 2, path);
  for (std::size_t k = 0; k < 5; ++k) {
    EXPECT_EQ(idx[2 * k], k);
    EXPECT_EQ(idx[2 * k + 1], k + 7);
  }
  // no bonds: the sidecar is the single Polyvertex grid as before
  const std::string p0 = dir.file("s0.h5");
  write_sphere_set(p0, testutil::sample_spheres(12), testutil::sample_provenance());
  EXPECT_EQ(slurp(xdmf_path_for(p0)).find("Polyline"), std::string::npos);
}
