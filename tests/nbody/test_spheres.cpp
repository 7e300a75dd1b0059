/// @file test_spheres.cpp
/// The sphere arrays' one list (Spheres::zip_arrays): resize, push, append, size check, memory
/// accounting and the conversion to and from sphere files all cover every array.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "ssdem/io.hpp"
#include "ssdem/spheres.hpp"

using namespace ssdem;

namespace {
Spheres two() {
  Spheres sp;
  sp.push(7, Vec3(1, 2, 3), Vec3(4, 5, 6), Vec3(7, 8, 9), 10.0, 0.5);
  sp.push(9, Vec3(-1, -2, -3), Vec3(-4, -5, -6), Vec3(-7, -8, -9), 20.0, 0.25);
  return sp;
}
}  // namespace

TEST(Spheres, EveryArrayIsListedOnceWithItsFileDescriptor) {
  std::vector<std::string> names;
  std::size_t bytes = 0;
  Spheres::zip_arrays([&](const common::SphereArray& a) {
    names.push_back(a.name);
    bytes += a.bytes();
  });
  EXPECT_EQ(names, (std::vector<std::string>{"id", "position", "velocity", "spin", "mass", "radius", "dissipated"}));
  EXPECT_EQ(bytes, Spheres::bytes_per_sphere());
  EXPECT_EQ(Spheres::bytes_per_sphere(), 8u + 3 * 24 + 16 + 8);
  // the file's core arrays are the same list, less the run's own "dissipated" (a field in files)
  std::vector<std::string> file;
  common::SphereSet::zip_arrays([&](const common::SphereArray& a) { file.push_back(a.name); });
  names.pop_back();
  EXPECT_EQ(file, names);
}

TEST(Spheres, ResizePushAppendCoverEveryArray) {
  Spheres sp = two();
  EXPECT_TRUE(sp.consistent());
  sp.resize(3);
  EXPECT_TRUE(sp.consistent());
  EXPECT_EQ(sp.id[2], 0u);
  EXPECT_EQ(sp.x[2], Vec3::Zero());
  EXPECT_EQ(sp.s[2], 0.0);
  Spheres a = two();
  a.append(two());
  EXPECT_TRUE(a.consistent());
  ASSERT_EQ(a.size(), 4u);
  EXPECT_EQ(a.id[3], 9u);
  EXPECT_EQ(a.w[2], Vec3(7, 8, 9));
  EXPECT_EQ(a.m[3], 20.0);
  a.m.pop_back();
  EXPECT_FALSE(a.consistent());
}

TEST(Spheres, SphereFileConversionRoundTripsEveryArray) {
  Spheres sp = two();
  sp.dissipated = {0.5, 1.5};
  sp.carried.push_back({"damage", "1", 1, {0.25, 0.75}, "damage"});
  const common::SphereSet s = to_sphere_set(sp, 3.0, 12);
  EXPECT_EQ(s.time, 3.0);
  EXPECT_EQ(s.step, 12);
  EXPECT_EQ(s.id, sp.id);
  EXPECT_EQ(s.position, (std::vector<double>{1, 2, 3, -1, -2, -3}));
  EXPECT_EQ(s.spin, (std::vector<double>{7, 8, 9, -7, -8, -9}));
  EXPECT_EQ(s.radius, sp.s);
  ASSERT_EQ(s.fields.size(), 2u);  // damage and the run's dissipated energy
  EXPECT_EQ(s.fields[1].name, "dissipated");
  EXPECT_EQ(s.fields[1].unit, "J");
  const Spheres back = from_sphere_set(s);
  EXPECT_EQ(back.id, sp.id);
  EXPECT_EQ(back.x, sp.x);
  EXPECT_EQ(back.v, sp.v);
  EXPECT_EQ(back.w, sp.w);
  EXPECT_EQ(back.m, sp.m);
  EXPECT_EQ(back.s, sp.s);
  EXPECT_EQ(back.dissipated, sp.dissipated);
  ASSERT_EQ(back.carried.size(), 1u);
  EXPECT_EQ(back.carried[0].values, sp.carried[0].values);
}
