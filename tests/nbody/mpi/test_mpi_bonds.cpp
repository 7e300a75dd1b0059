/// @file test_mpi_bonds.cpp
/// Bonds over ssdem-grav's domain decomposition (nbody/include/ssdem/mpi/domain_sim.hpp, "Bonds")
/// against one rank, under mpirun -np 2 and -np 3 (label mpi). Two bonded cubes (parallel bonds of
/// bonds.hpp, frictional contacts) collide at 4 m/s: bonds cross the ORB cuts from the start,
/// break on impact (their stored energy to the released account), and spheres with bonds migrate
/// between ranks at the exchanges. Rank 0 runs the serial Simulation (one OpenMP thread) beside
/// the distributed run; tolerance 0: positions, velocities, spins, accelerations, the contact
/// history, every bond array (shear force, moments, frame, broken flag, released energy) and the
/// series row's bond terms (stored, released, counts) equal one rank's bit for bit; in single
/// rate, in multi-rate steps, and (single rate, larger cubes) with the ranks' bond loops on 2
/// threads (the parallel path).
#include <gtest/gtest.h>
#include <mpi.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "common/status.hpp"
#include "ssdem/bonds.hpp"
#include "ssdem/contact_params.hpp"
#include "ssdem/mpi/domain_sim.hpp"
#include "ssdem/simulation.hpp"

#include "mpi_support.hpp"

using namespace ssdem;

namespace {
using ssdem_test::state_diff;
using ssdem_test::world;

constexpr double kS = 0.5, kRho = 2000.0;

// n^3 spheres of radius kS, spacing 2 kS (1 + 0.002) from `origin`, velocity v plus a jitter.
void add_cube(Spheres& sp, int n, const Vec3& origin, const Vec3& v, std::uint64_t id0) {
  const double m = kRho * 4.0 / 3.0 * M_PI * kS * kS * kS, h = 2 * kS * 1.002;
  std::uint64_t id = id0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k, ++id) {
        const double a = std::sin(12.9898 * id + 1.0), b = std::sin(78.233 * id + 2.0), c = std::sin(37.719 * id + 3.0);
        sp.push(id, origin + h * Vec3(i, j, k), v + 1e-2 * Vec3(a, b, c), 1e-2 / kS * Vec3(b, c, a), m, kS);
      }
}

// Two cubes 0.3 m apart closing at 4 m/s; bonds of strength `strength` [Pa]; dt an awkward
// fraction of the shortest contact or bond mode.
SimConfig bonded_cubes(Spheres& sp, double strength, int n1 = 6, int n2 = 5) {
  add_cube(sp, n1, Vec3::Zero(), Vec3(2.0, 0, 0), 0);
  add_cube(sp, n2, Vec3(n1 * 1.002 + 0.3, 1.3, 0.7), Vec3(-2.0, 0, 0), 100000);
  BondParams bp;
  bp.kn = 1e7;
  bp.ks = 0.5e7;
  bp.sigma_c = bp.tau_c = strength;
  SimConfig c;
  c.contacts = true;
  c.contact = gravel_preset(1e7 * M_PI * kS * kS);
  c.bonds = generate_bonds(sp, bp);
  const double tau = std::min(c.contact.contact_time(0.5 * sp.m[0]), shortest_bond_time(c.bonds, sp));
  c.dt = 0.77 * tau / 30.0;
  c.gravity_every = 5;
  return c;
}

// Largest difference of two bond sets (every array); -1 if their layouts differ.
double bond_diff(const BondSet& a, const BondSet& b) {
  if (a.size() != b.size() || a.id_a != b.id_a || a.id_b != b.id_b || a.broken != b.broken) return -1;
  double d = std::fabs(a.released_base - b.released_base);
  for (std::size_t k = 0; k < a.size(); ++k)
    d = std::max({d, (a.Fs[k] - b.Fs[k]).norm(), (a.Mb[k] - b.Mb[k]).norm(), (a.n_old[k] - b.n_old[k]).norm(),
                  std::fabs(a.Mt[k] - b.Mt[k]), std::fabs(a.released[k] - b.released[k])});
  return d;
}

// Run `steps` steps distributed and (rank 0) serially, with series rows every 100 steps: states,
// bonds and the rows' bond terms equal one rank's bit for bit; returns the broken count (rank 0).
std::size_t compare_bonded(const Spheres& sp, const SimConfig& cfg, int steps, const char* what, int threads = 1) {
  mpi::DomainSim dsim(world(), sp, cfg);
  std::unique_ptr<Simulation> ref;
  if (world().rank == 0) ref = std::make_unique<Simulation>(sp, cfg);
  const std::size_t cross0 = dsim.cross_rank_bonds();
  if (world().size > 1) {
    EXPECT_GT(cross0, 0u) << "the test needs bonds across the ORB cut";
  }
  EXPECT_EQ(dsim.global_bonds(), cfg.bonds.size());
  if (threads > 1) {  // every rank on the parallel path (BondSystem: from 2 048 intact bonds)
    EXPECT_GE(dsim.local_bonds(), 2048u) << "rank " << world().rank;
  }
  int rows = 0, spread = 0;
  for (int k = 1; k <= steps; ++k) {
    omp_set_num_threads(threads);  // the ranks' threads; the reference on one
    dsim.step();
    omp_set_num_threads(1);
    if (ref) ref->step();
    if (k % 100 != 0) continue;
    const Diagnostics d = dsim.diagnostics();  // collective; the same bits on every rank
    ++rows;
    if (!ref) continue;
    const Diagnostics w = ref->diagnostics();
    if (cfg.multirate) {  // levels in use (the distributed ones equal them: compared at the end)
      std::vector<int> used(kMaxLevel + 1, 0);
      for (std::uint8_t l : ref->levels()) used[l] = 1;
      spread = std::max(spread, static_cast<int>(std::count(used.begin(), used.end(), 1)));
    }
    std::printf("%s, step %d: bonds %zu, broken %zu, stored %.17g J, released %.17g J, elastic %.17g J\n", what, k,
                d.bonds, d.bonds_broken, d.bond_elastic, d.bond_released, d.elastic);
    EXPECT_EQ(d.bonds, w.bonds);
    EXPECT_EQ(d.bonds_broken, w.bonds_broken);
    EXPECT_EQ(d.bond_elastic, w.bond_elastic);
    EXPECT_EQ(d.bond_released, w.bond_released);
    EXPECT_EQ(d.elastic, w.elastic);
    EXPECT_EQ(d.kinetic, w.kinetic);
  }
  EXPECT_EQ(rows, steps / 100);
  const mpi::DomainStats& st = dsim.stats();
  const SimState got = dsim.gather_state();
  if (!ref) return 0;
  const SimState want = ref->state();
  const double ds = state_diff(got, want), db = bond_diff(got.bonds, want.bonds);
  const std::size_t broken = want.bonds.broken_count();
  std::printf("%s, %d ranks, %d steps: %zu bonds (%zu across ranks at the start), %zu broken; %lld exchanges, "
              "%lld rebalances; max |difference| vs one rank: state %.3g, bonds %.3g\n",
              what, world().size, steps, want.bonds.size(), cross0, broken, static_cast<long long>(st.exchanges),
              static_cast<long long>(st.rebalances), ds, db);
  EXPECT_GT(st.exchanges, 3);
  EXPECT_EQ(ds, 0.0);
  EXPECT_EQ(db, 0.0);
  EXPECT_EQ(got.bonds.released_total(), want.bonds.released_total());
  if (cfg.multirate) {
    EXPECT_EQ(got.level, want.level);
    std::printf("most levels in use at a row: %d\n", spread);
    EXPECT_GE(spread, 2);  // spheres on different levels
  }
  return broken;
}
}  // namespace

TEST(MpiBonds, BondedCubesBreakingAcrossDomainsEqualOneRank) {
  Spheres sp;
  const SimConfig cfg = bonded_cubes(sp, 2e4);
  const std::size_t broken = compare_bonded(sp, cfg, 400, "bonded cubes");
  if (world().rank == 0) {
    EXPECT_GT(broken, 0u);
    EXPECT_LT(broken, cfg.bonds.size());
  }
}

TEST(MpiBonds, MultirateBondLevelsAcrossDomainsEqualOneRank) {
  // the second cube's bonds 64x stiffer: its spheres on level 0, the first cube's on level 3
  // until the impact promotes the spheres near it; equalisation over bonds across the cuts
  Spheres sp;
  SimConfig cfg = bonded_cubes(sp, 2e4);
  for (std::size_t k = 0; k < cfg.bonds.size(); ++k)
    if (cfg.bonds.id_a[k] >= 100000) {
      cfg.bonds.kn[k] *= 64;
      cfg.bonds.ks[k] *= 64;
    }
  cfg.dt = 0.77 * shortest_bond_time(cfg.bonds, sp) / 30.0;
  cfg.multirate = true;
  cfg.pair_steps_per_contact = 30.0;
  cfg.gravity_every = 64;
  const std::size_t broken = compare_bonded(sp, cfg, 1600, "bonded cubes, multi-rate");
  if (world().rank == 0) {
    EXPECT_GT(broken, 0u);
  }
}

TEST(MpiBonds, ParallelBondLoopOnTwoThreadsPerRankEqualsOneRank) {
  // 14^3 + 10^3 bonded spheres (9 750 bonds, over 2 048 on every rank): each rank evaluates its
  // bonds on 2 threads (the parallel path of BondSystem), the reference on one thread (the serial
  // loop); tolerance 0
  Spheres sp;
  const SimConfig cfg = bonded_cubes(sp, 2e4, 14, 10);
  const std::size_t broken = compare_bonded(sp, cfg, 200, "bonded cubes, 2 threads per rank", 2);
  if (world().rank == 0) {
    EXPECT_GT(broken, 0u);
  }
}
