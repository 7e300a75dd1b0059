/// @file test_files.cpp
/// File contract: bit-exact round trips, units and provenance on every dataset.
#include <gtest/gtest.h>

#include "common/h5.hpp"
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
