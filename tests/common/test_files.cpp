/// @file test_files.cpp
/// File contract: bit-exact round trips, units and provenance on every dataset.
#include <gtest/gtest.h>

#include <cmath>

#include "common/h5.hpp"
#include "common/status.hpp"
#include "test_util.hpp"

using namespace common;

TEST(ParticleFile, RoundTripIsBitExact) {
  testutil::TempDir dir;
  const ParticleSnapshot a = testutil::sample_particles(257);
  const std::string path = dir.file("snap.h5");
  write_particle_snapshot(path, a, testutil::sample_provenance());
  const ParticleSnapshot b = read_particle_snapshot(path);
  EXPECT_EQ(b.time, a.time);
  EXPECT_EQ(b.step, a.step);
  EXPECT_EQ(b.grid.origin, a.grid.origin);
  EXPECT_EQ(b.grid.cell_size, a.grid.cell_size);
  EXPECT_EQ(b.grid.shape, a.grid.shape);
  EXPECT_EQ(b.id, a.id);
  EXPECT_EQ(b.position, a.position);  // exact: operator== on doubles
  EXPECT_EQ(b.velocity, a.velocity);
  EXPECT_EQ(b.mass, a.mass);
  EXPECT_EQ(b.volume, a.volume);
  EXPECT_EQ(b.size, a.size);
  EXPECT_EQ(b.material, a.material);
  ASSERT_EQ(b.fields.size(), 2u);
  ASSERT_NE(b.field("stress"), nullptr);
  EXPECT_EQ(b.field("stress")->ncomp, 6u);
  EXPECT_EQ(b.field("stress")->values, a.field("stress")->values);
  EXPECT_EQ(b.field("damage")->values, a.field("damage")->values);
  EXPECT_EQ(b.field("stress")->unit, "Pa");
}

TEST(ParticleFile, EveryDatasetHasUnitAndFileHasProvenance) {
  testutil::TempDir dir;
  const std::string path = dir.file("snap.h5");
  write_particle_snapshot(path, testutil::sample_particles(5), testutil::sample_provenance());
  h5::Handle f = h5::open_file_read(path);
  const std::map<std::string, std::string> expect = {
      {"id", "1"},   {"position", "m"}, {"velocity", "m/s"}, {"mass", "kg"}, {"volume", "m^3"},
      {"size", "m"}, {"material", "1"}, {"damage", "1"},     {"stress", "Pa"}};
  for (const auto& [name, unit] : expect) EXPECT_EQ(h5::unit_of(f, "/particles/" + name), unit) << name;
  const Provenance p = h5::read_provenance(f, path);
  EXPECT_EQ(p.tool, "test-tool");
  EXPECT_EQ(p.git_sha, "abc123");
  EXPECT_EQ(p.command_line, "test-tool --scene x.toml");
  EXPECT_EQ(p.scene_toml, "x = 1\n");
  EXPECT_EQ(h5::read_attr_string(f, "format", path), "mpm-frag.particles");
}

TEST(SphereFile, RoundTripIsBitExact) {
  testutil::TempDir dir;
  const SphereSet a = testutil::sample_spheres(300);
  const std::string path = dir.file("spheres.h5");
  int extra_written = 0;
  write_sphere_set(path, a, testutil::sample_provenance(), [&](long long f) {
    h5::Handle g = h5::create_group(f, "extra");
    const double v[2] = {1.5, 2.5};
    h5::write_dataset(g, "values", v, 2, 1, "s");
    ++extra_written;
  });
  EXPECT_EQ(extra_written, 1);
  std::vector<double> extra;
  const SphereSet b = read_sphere_set(path, [&](long long f) { extra = h5::read_doubles(f, "/extra/values", 2, 1, path); });
  EXPECT_EQ(b.id, a.id);
  EXPECT_EQ(b.position, a.position);
  EXPECT_EQ(b.velocity, a.velocity);
  EXPECT_EQ(b.spin, a.spin);
  EXPECT_EQ(b.mass, a.mass);
  EXPECT_EQ(b.radius, a.radius);
  EXPECT_EQ(b.time, a.time);
  EXPECT_EQ(b.step, a.step);
  ASSERT_NE(b.field("damage"), nullptr);
  EXPECT_EQ(b.field("damage")->values, a.field("damage")->values);
  EXPECT_EQ(extra, (std::vector<double>{1.5, 2.5}));
}

TEST(SphereFile, EmptySetRoundTrips) {
  testutil::TempDir dir;
  SphereSet a;
  write_sphere_set(dir.file("e.h5"), a, testutil::sample_provenance());
  EXPECT_EQ(read_sphere_set(dir.file("e.h5")).count(), 0u);
}

TEST(SphereFile, BlocksReadBackToTheWholeSetAndNameTheFileRow) {
  // the blocks of 1, 2, 3 and 7 readers (common::mpi::dense_first's split) concatenate to the
  // whole read, fields included; a block's message names the file row
  testutil::TempDir dir;
  const std::size_t n = 300;
  SphereSet a = testutil::sample_spheres(n);
  const std::string path = dir.file("spheres.h5");
  write_sphere_set(path, a, testutil::sample_provenance());
  const SphereSet whole = read_sphere_set(path);
  const SphereFileShape shape = sphere_file_shape(path);
  EXPECT_EQ(shape.count, n);
  EXPECT_FALSE(shape.bonds);
  for (std::size_t P : {1u, 2u, 3u, 7u}) {
    SphereSet cat;
    std::vector<double> damage;
    for (std::size_t r = 0; r < P; ++r) {
      const std::size_t lo = n * r / P, hi = n * (r + 1) / P;
      const SphereSet b = read_sphere_rows(path, h5::RowRange{lo, hi - lo});
      ASSERT_EQ(b.count(), hi - lo);
      cat.id.insert(cat.id.end(), b.id.begin(), b.id.end());
      cat.position.insert(cat.position.end(), b.position.begin(), b.position.end());
      cat.mass.insert(cat.mass.end(), b.mass.begin(), b.mass.end());
      cat.spin.insert(cat.spin.end(), b.spin.begin(), b.spin.end());
      ASSERT_NE(b.field("damage"), nullptr);
      damage.insert(damage.end(), b.field("damage")->values.begin(), b.field("damage")->values.end());
    }
    EXPECT_EQ(cat.id, whole.id) << P << " blocks";
    EXPECT_EQ(cat.position, whole.position) << P << " blocks";
    EXPECT_EQ(cat.mass, whole.mass) << P << " blocks";
    EXPECT_EQ(cat.spin, whole.spin) << P << " blocks";
    EXPECT_EQ(damage, whole.field("damage")->values) << P << " blocks";
  }
  // a NaN position at row 207 and a zero mass at row 250: a block holding them names those rows
  a.position[3 * 207 + 1] = std::nan("");
  write_sphere_set(dir.file("bad_x.h5"), a, testutil::sample_provenance());
  a.position[3 * 207 + 1] = 0.0;
  a.mass[250] = 0.0;
  write_sphere_set(dir.file("bad_m.h5"), a, testutil::sample_provenance());
  auto message = [&](const std::string& f) {
    try {
      read_sphere_rows(dir.file(f), h5::RowRange{200, 100});
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message("bad_x.h5").find("/spheres/position: non-finite value (NaN or Inf) at row 207"), std::string::npos)
      << message("bad_x.h5");
  EXPECT_NE(message("bad_m.h5").find("/spheres/mass: non-positive value 0.000000 at row 250"), std::string::npos)
      << message("bad_m.h5");
}
