/// @file test_mpi_orb.cpp
/// The collective orthogonal recursive bisection (OrbTree::collective, nbody/src/mpi/orb_collective.cpp)
/// against the one built from all positions (OrbTree(x, P)), under mpirun -np 2 and -np 3: the
/// cuts must be the same values on the same axes (tolerance 0), and every sphere the same owner,
/// for spheres spread over the ranks at random, on a lattice (many equal coordinates: ties go to
/// the upper side), clustered debris with far fragments, all spheres at one point, all spheres on
/// one rank, and no spheres.
#include <gtest/gtest.h>
#include <mpi.h>

#include "common/rng.hpp"
#include "ssdem/mpi/orb.hpp"

using namespace ssdem;

namespace {

mpi::Comm& comm() {
  static mpi::Comm c(MPI_COMM_WORLD);
  return c;
}

// every rank knows all positions (the test's reference); it passes those `pick` gives it
void expect_same(const std::vector<Vec3>& all, int (*pick)(std::size_t, int), const char* what) {
  const mpi::OrbTree ref(all, comm().size);
  std::vector<Vec3> own;
  for (std::size_t i = 0; i < all.size(); ++i)
    if (pick(i, comm().size) == comm().rank) own.push_back(all[i]);
  const mpi::OrbTree col = mpi::OrbTree::collective(comm(), own);
  EXPECT_EQ(col.cuts(), ref.cuts()) << what;
  std::size_t differ = 0;
  for (const Vec3& p : all) differ += col.owner(p) != ref.owner(p);
  EXPECT_EQ(differ, 0u) << what;
}

int at_random(std::size_t i, int P) { return static_cast<int>(common::KeyedRng(3, i).uniform() * P); }
int on_last(std::size_t, int P) { return P - 1; }

}  // namespace

TEST(MpiOrbCollective, EqualsTheTreeOfAllPositions) {
  std::vector<Vec3> cloud, lattice, debris, point;
  for (std::size_t i = 0; i < 5000; ++i) {
    common::KeyedRng r(11, i);
    cloud.emplace_back(r.normal(), 3.0 * r.normal(), 0.5 * r.normal());
    lattice.emplace_back(static_cast<double>(i % 7), static_cast<double>((i / 7) % 5), static_cast<double>(i / 35) - 0.0);
    const double far = i % 50 == 0 ? 1e4 : 1.0;
    debris.emplace_back(far * r.normal(), far * r.normal(), r.normal());
    point.emplace_back(1.5, -2.0, 0.25);
  }
  lattice[3] = Vec3(-0.0, 0.0, 0.0);  // a negative zero among zeros
  expect_same(cloud, at_random, "cloud");
  expect_same(lattice, at_random, "lattice");
  expect_same(debris, at_random, "debris");
  expect_same(point, at_random, "one point");
  expect_same(cloud, on_last, "all on one rank");
  expect_same(std::vector<Vec3>(), at_random, "no spheres");
  expect_same(std::vector<Vec3>(cloud.begin(), cloud.begin() + 2), at_random, "fewer spheres than ranks");
}
