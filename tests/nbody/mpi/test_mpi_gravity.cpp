/// @file test_mpi_gravity.cpp
/// The distributed tree with locally essential trees (nbody/include/ssdem/mpi/gravity_let.hpp)
/// against the one-rank tree (TreeGravity), under mpirun -np 2 and -np 3: every rank computes
/// the one-rank forces of the whole set as the reference and checks its own spheres. Tolerance 0:
/// the accelerations and potentials must be the same bits, for spheres placed on the ranks by
/// position (as ORB does) and at random (every sphere then travels to its gravity owner), on
/// clustered debris (two piles and a cloud of fragments of unequal sizes), with coincident
/// spheres (leaves at max_depth larger than a group), with every sphere on one rank, and with
/// fewer spheres than a group. The import must be a small part of the set (the point of a
/// locally essential tree), and a non-finite position on one rank fails every rank alike.
#include <gtest/gtest.h>
#include <mpi.h>

#include <algorithm>
#include <cmath>

#include "common/rng.hpp"
#include "common/status.hpp"
#include "ssdem/generators.hpp"
#include "ssdem/gravity.hpp"
#include "ssdem/mpi/gravity_let.hpp"

using namespace ssdem;

namespace {

mpi::Comm& comm() {
  static mpi::Comm c(MPI_COMM_WORLD);
  return c;
}

// Two piles of 1 m spheres and a cloud of fragments (0.2-3 m) around them, SI.
Spheres debris(std::size_t cloud, double R = 12.0) {
  Spheres a = lattice_pile(R, 1.0, 2000.0, 0.05, 3, Vec3::Zero(), 0);
  Spheres b = lattice_pile(7.0, 1.0, 2000.0, 0.05, 4, Vec3(40.0, 5.0, -3.0), a.size());
  Spheres sp = a;
  sp.append(b);
  const std::uint64_t first = sp.size();
  for (std::size_t k = 0; k < cloud; ++k) {
    common::KeyedRng rng(5, first + k);
    const double r = 15.0 + 200.0 * std::pow(rng.uniform(), 2.0);
    Vec3 u(rng.normal(), rng.normal(), rng.normal());
    u.normalize();
    const double s = 0.2 + 2.8 * rng.uniform();
    sp.push(first + k, r * u, Vec3::Zero(), Vec3::Zero(), 2000.0 * 4.18879 * s * s * s, s);
  }
  return sp;
}

// this rank's spheres: by x (slabs of equal count) or at random (keyed by id)
std::vector<std::uint32_t> mine(const Spheres& sp, bool by_position) {
  const int P = comm().size, r = comm().rank;
  std::vector<std::uint32_t> own;
  if (by_position) {
    std::vector<std::uint32_t> ord(sp.size());
    for (std::uint32_t i = 0; i < ord.size(); ++i) ord[i] = i;
    std::stable_sort(ord.begin(), ord.end(), [&](std::uint32_t a, std::uint32_t b) { return sp.x[a].x() < sp.x[b].x(); });
    for (std::size_t k = sp.size() * r / P; k < sp.size() * (r + 1) / P; ++k) own.push_back(ord[k]);
    std::sort(own.begin(), own.end());
  } else {
    for (std::uint32_t i = 0; i < sp.size(); ++i)
      if (static_cast<int>(common::KeyedRng(9, sp.id[i]).uniform() * P) == r) own.push_back(i);
  }
  return own;
}

struct Outcome {
  std::size_t mismatches = 0, checked = 0;
  mpi::LetStats st;
};

// Own spheres of every rank against the one-rank tree; the local arrays are the whole set
// (global index = index), which is all the distributed tree reads of them.
Outcome compare(const Spheres& sp, const std::vector<std::uint32_t>& own, GravityParams gp) {
  std::vector<Vec3> ref;
  std::vector<double> rpot;
  TreeGravity(gp).compute(sp, ref, &rpot);
  std::vector<std::uint64_t> gidx(sp.size());
  for (std::size_t i = 0; i < sp.size(); ++i) gidx[i] = i;
  mpi::DistributedTree let(comm(), gp);
  std::vector<Vec3> acc(sp.size(), Vec3::Constant(7.0));
  std::vector<double> pot(sp.size(), 7.0);
  let.compute(sp, own, acc, &pot, gidx);
  Outcome o;
  for (std::uint32_t i : own) {
    ++o.checked;
    if (acc[i] != ref[i] || pot[i] != rpot[i]) {
      if (o.mismatches < 3)
        ADD_FAILURE() << "rank " << comm().rank << " sphere " << i << ": a " << acc[i].transpose() << " vs one rank "
                      << ref[i].transpose() << ", pot " << pot[i] << " vs " << rpot[i];
      ++o.mismatches;
    }
  }
  // a second evaluation on the same object (reused buffers) gives the same bits
  std::vector<Vec3> acc2(sp.size(), Vec3::Zero());
  let.compute(sp, own, acc2, nullptr, gidx);
  for (std::uint32_t i : own)
    if (acc2[i] != acc[i]) ++o.mismatches;
  o.st = let.stats();
  long long n[2] = {static_cast<long long>(o.checked), static_cast<long long>(o.mismatches)};
  comm().sum(n, 2);
  o.checked = static_cast<std::size_t>(n[0]);
  o.mismatches = static_cast<std::size_t>(n[1]);
  return o;
}

}  // namespace

TEST(MpiGravityLet, ClusteredDebrisByPositionEqualsOneRankTree) {
  const Spheres sp = debris(6000, 30.0);
  const Outcome o = compare(sp, mine(sp, true), GravityParams{});
  EXPECT_EQ(o.checked, sp.size());
  EXPECT_EQ(o.mismatches, 0u);
  // the locally essential tree is a part of the whole set (the share falls as (N/P)^(-1/3) with
  // more spheres per rank: nbody-mpi-gravity-bench)
  double imp[2] = {o.st.imported_particles / 2, o.st.bytes_let / 2};  // two evaluations
  comm().max(imp, 2);
  EXPECT_GT(imp[0], 0.0);
  EXPECT_LT(imp[0], 0.4 * static_cast<double>(sp.size()));
  if (comm().rank == 0)
    std::printf("LET on %d ranks, %zu spheres: largest import %.0f particles; rank 0 imported %.0f particles, %.0f nodes, "
                "%.0f B; top cells %.0f, maximal %.0f, moved %.0f\n",
                comm().size, sp.size(), imp[0], o.st.imported_particles / 2, o.st.imported_nodes / 2, o.st.bytes_let / 2,
                o.st.top_cells, o.st.maximal_cells, o.st.moved_spheres / 2);
}

TEST(MpiGravityLet, RandomOwnersAndOtherOpeningAnglesEqualOneRankTree) {
  const Spheres sp = debris(3000);
  for (double theta : {0.5, 0.8}) {
    GravityParams gp;
    gp.theta = theta;
    gp.group = 16;
    gp.bucket = 4;
    const Outcome o = compare(sp, mine(sp, false), gp);
    EXPECT_EQ(o.checked, sp.size());
    EXPECT_EQ(o.mismatches, 0u) << "theta " << theta;
    if (comm().size > 1) {
      EXPECT_GT(o.st.moved_spheres, 0.0);
    }
  }
}

TEST(MpiGravityLet, CoincidentSpheresEveryOneOnOneRankAndFewSpheres) {
  // 300 spheres at one point and 300 in a 1e-9 m cluster: leaves at max_depth hold more than a group
  Spheres sp = debris(500);
  const std::size_t n0 = sp.size();
  for (std::size_t k = 0; k < 600; ++k) {
    const Vec3 x = k < 300 ? Vec3(3.0, 3.0, 3.0) : Vec3(-5.0, 1.0, 2.0) + 1e-9 * Vec3(k % 7, k % 5, k % 3);
    sp.push(n0 + k, x, Vec3::Zero(), Vec3::Zero(), 1000.0, 0.5);
  }
  GravityParams gp;
  gp.max_depth = 12;
  Outcome o = compare(sp, mine(sp, true), gp);
  EXPECT_EQ(o.mismatches, 0u);
  EXPECT_EQ(o.checked, sp.size());
  // every sphere on the last rank (a collapse): the others own none and get none back
  std::vector<std::uint32_t> all;
  if (comm().rank == comm().size - 1)
    for (std::uint32_t i = 0; i < sp.size(); ++i) all.push_back(i);
  o = compare(sp, all, gp);
  EXPECT_EQ(o.mismatches, 0u);
  EXPECT_EQ(o.checked, sp.size());
  // fewer spheres than a group: the root is the only group, on one rank
  Spheres few = lattice_pile(2.0, 1.0, 2000.0, 0.05, 3);
  ASSERT_LE(few.size(), 64u);
  o = compare(few, mine(few, false), GravityParams{});
  EXPECT_EQ(o.mismatches, 0u);
  EXPECT_EQ(o.checked, few.size());
}

TEST(MpiGravityLet, NonFinitePositionOnOneRankFailsEveryRank) {
  Spheres sp = debris(200);
  std::vector<std::uint32_t> own = mine(sp, true);
  if (comm().rank == comm().size - 1) sp.x[own.front()] = Vec3(std::nan(""), 0.0, 0.0);
  std::vector<std::uint64_t> gidx(sp.size());
  for (std::size_t i = 0; i < sp.size(); ++i) gidx[i] = i;
  mpi::DistributedTree let(comm(), GravityParams{});
  std::vector<Vec3> acc(sp.size());
  std::string what;
  try {
    let.compute(sp, own, acc, nullptr, gidx);
  } catch (const common::NumericalError& e) {
    what = e.what();
  }
  EXPECT_NE(what.find("non-finite position"), std::string::npos) << "rank " << comm().rank << ": '" << what << "'";
  if (comm().rank == comm().size - 1) {
    EXPECT_NE(what.find("sphere id"), std::string::npos);
  }
}
