/// @file test_mpi_domain.cpp
/// ssdem-grav's domain decomposition (nbody/include/ssdem/mpi/domain_sim.hpp) against one rank.
/// Run under `mpirun -np 2` and `-np 3` (label mpi). Rank 0 runs the serial Simulation (one
/// OpenMP thread, the reference summation order) beside the distributed run and compares the
/// gathered state: positions, velocities, spins, accelerations and contact history must be equal
/// bit for bit (the stated tolerance is 0: every summation runs in global-index order, see the
/// header), and the conserved totals (mass, momentum, angular momentum) therefore equal too.
/// Scenes: a self-gravitating frictional pile with the tree and the error-controlled cadence; a
/// two-body reaccumulation whose contacts cross domain boundaries; a Kepler orbit whose bodies
/// change ranks (with 3 ranks one rank owns nothing); a fragment crossing domains at 5 km/s in
/// one step; repeated runs; a restart of a gathered state.
#include <gtest/gtest.h>
#include <mpi.h>
#include <omp.h>

#include <cmath>
#include <cstdio>

#include "../kepler_pair.hpp"
#include "common/rng.hpp"
#include "ssdem/contact_params.hpp"
#include "ssdem/dt_rule.hpp"
#include "ssdem/generators.hpp"
#include "ssdem/mpi/domain_sim.hpp"
#include "ssdem/simulation.hpp"

using namespace ssdem;

namespace {
mpi::Comm& world() {
  static mpi::Comm c(MPI_COMM_WORLD);
  return c;
}

// G = 1 pile of 0.1-radius spheres with random velocities (0.3 v_esc) and spins.
Spheres pile(double R = 0.75, std::uint64_t first_id = 0) {
  Spheres sp = lattice_pile(R, 0.1, 1.0, 0.05, 3, Vec3::Zero(), first_id);
  const double M = total_mass(sp), vesc = std::sqrt(2 * M / R);
  for (std::size_t i = 0; i < sp.size(); ++i) {
    common::KeyedRng rng(17, sp.id[i]);
    sp.v[i] = 0.3 * vesc * Vec3(rng.normal(), rng.normal(), rng.normal()) / std::sqrt(3.0);
    sp.w[i] = Vec3(rng.normal(), rng.normal(), rng.normal());
  }
  return sp;
}
SimConfig config(const Spheres& sp, double vmax, bool tree, bool adaptive) {
  const DtAdvice adv = choose_kn_dt(sp.m[0], 0.1, vmax, 1.0, 0.01, 30);
  SimConfig c;
  c.self_gravity = true;
  c.direct_gravity = !tree;
  c.gravity.G = 1.0;
  c.adaptive_gravity = adaptive;
  c.gravity_every = 3;
  c.contacts = true;
  c.contact = gravel_preset(adv.kn);
  c.dt = 0.77 * adv.dt;  // not a round number of steps per contact
  return c;
}

struct Totals {
  double m = 0;
  Vec3 P = Vec3::Zero(), L = Vec3::Zero();
};
Totals totals(const SimState& s) {
  Totals t;
  for (std::size_t i = 0; i < s.sp.size(); ++i) {
    t.m += s.sp.m[i];
    t.P += s.sp.m[i] * s.sp.v[i];
    t.L += s.sp.m[i] * s.sp.x[i].cross(s.sp.v[i]) + 0.4 * s.sp.m[i] * s.sp.s[i] * s.sp.s[i] * s.sp.w[i];
  }
  return t;
}

// Largest difference between the distributed (gathered) and the one-rank state; -1 if the
// layouts differ. Rank 0 only.
double max_diff(const SimState& a, const SimState& b) {
  if (a.sp.size() != b.sp.size() || a.history.size() != b.history.size() || a.step != b.step) return -1;
  double d = 0;
  for (std::size_t i = 0; i < a.sp.size(); ++i) {
    if (a.sp.id[i] != b.sp.id[i]) return -1;
    d = std::max({d, (a.sp.x[i] - b.sp.x[i]).norm(), (a.sp.v[i] - b.sp.v[i]).norm(), (a.sp.w[i] - b.sp.w[i]).norm(),
                  (a.a[i] - b.a[i]).norm()});
  }
  for (std::size_t k = 0; k < a.history.size(); ++k) {
    if (a.history[k].id_a != b.history[k].id_a || a.history[k].id_b != b.history[k].id_b) return -1;
    for (std::size_t q = 0; q < a.history[k].v.size(); ++q)
      d = std::max(d, (a.history[k].v[q] - b.history[k].v[q]).norm());
  }
  return d;
}

// Run `steps` steps distributed and (rank 0) serially; expect bit-identical states and totals.
// `each` is called at the start and after every distributed step.
template <class F>
SimState compare(const Spheres& sp, const SimConfig& cfg, int steps, const char* what, F&& each) {
  mpi::DomainSim dsim(world(), sp, cfg);
  std::unique_ptr<Simulation> ref;
  if (world().rank == 0) ref = std::make_unique<Simulation>(sp, cfg);
  each(dsim);
  for (int k = 0; k < steps; ++k) {
    dsim.step();
    if (ref) ref->step();
    each(dsim);
  }
  SimState got = dsim.gather_state();
  if (ref) {
    const SimState want = ref->state();
    const double d = max_diff(got, want);
    const Totals tg = totals(got), tw = totals(want);
    std::printf("%s, %d ranks, %d steps: max |difference| vs one rank %.3g; mass %.17g vs %.17g, |dP| %.3g, "
                "|dL| %.3g; %zu contacts\n",
                what, world().size, steps, d, tg.m, tw.m, (tg.P - tw.P).norm(), (tg.L - tw.L).norm(), got.history.size());
    EXPECT_EQ(d, 0.0) << what;
    EXPECT_EQ(tg.m, tw.m);
    EXPECT_EQ((tg.P - tw.P).norm(), 0.0);
    EXPECT_EQ((tg.L - tw.L).norm(), 0.0);
  }
  return got;
}
int total_int(int v) {
  MPI_Allreduce(MPI_IN_PLACE, &v, 1, MPI_INT, MPI_SUM, MPI_COMM_WORLD);
  return v;
}
}  // namespace

TEST(MpiDomain, SelfGravitatingPileTreeAdaptiveCadenceEqualsOneRank) {
  const Spheres sp = pile();
  const SimConfig cfg = config(sp, std::sqrt(2 * total_mass(sp) / 0.75), true, true);
  std::size_t min_own = sp.size(), max_ghosts = 0;
  compare(sp, cfg, 400, "pile (tree, adaptive cadence)", [&](const mpi::DomainSim& d) {
    min_own = std::min(min_own, d.owned());
    max_ghosts = std::max(max_ghosts, d.ghosts());
  });
  EXPECT_GT(min_own, sp.size() / (2 * world().size));  // every rank holds a share (ORB by count)
  EXPECT_GT(max_ghosts, 0u);
}

TEST(MpiDomain, TwoBodyReaccumulationContactsAcrossDomainsEqualOneRank) {
  // body 2 placed 0.1 sphere radius from body 1's surface, closing at 1.5 (G = 1 units)
  Spheres a = pile(0.6);
  const Spheres b = pile(0.45);
  double gap = INFINITY;
  for (std::size_t i = 0; i < a.size(); ++i)
    for (std::size_t j = 0; j < b.size(); ++j)
      gap = std::min(gap, (b.x[j] + Vec3(1.0, 0.15, 0.0) - a.x[i]).norm() - a.s[i] - b.s[j]);
  std::uint64_t first2 = 0;  // body 2's ids start above body 1's (append_body)
  for (auto id : a.id) first2 = std::max(first2, id + 1);
  append_body(a, b, Vec3(1.0 - gap + 0.01, 0.15, 0.0), Vec3(-1.5, 0.0, 0.0));
  const SimConfig cfg = config(a, 2.0, false, false);
  int steps_crossing = 0, between = 0, calls = 0;
  std::size_t most = 0;
  compare(a, cfg, 900, "two-body reaccumulation (direct gravity, every 3)", [&](const mpi::DomainSim& d) {
    const std::size_t c = d.cross_rank_contacts();  // contacts whose spheres live on different ranks
    steps_crossing += c > 0;
    most = std::max(most, c);
    if (calls++ % 10 != 0) return;
    // the bodies touch: contacts between spheres of body 1 and body 2
    const SimState s = d.gather_state();
    int b = 0;
    for (const HistoryRecord& r : s.history) b += (r.id_a < first2) != (r.id_b < first2);
    between = std::max(between, b);
  });
  if (world().rank == 0) {
    std::printf("steps with contacts across ranks: %d of 901, at most %zu; most contacts between the bodies %d\n",
                steps_crossing, most, between);
    EXPECT_GT(between, 0);
  }
  EXPECT_GT(steps_crossing, 200);
}

TEST(MpiDomain, OrbitBodiesChangeRanksAndARankMayBeEmpty) {
  // G = M = 1 Kepler orbit, e = 0.5, two bodies without contacts; gravity every step
  const Spheres sp = kepler_pair(0.5, 1e-3, 7, 9);
  const SimConfig cfg = kepler_config(997);
  int changes = 0, last = -1, empty = 0;
  compare(sp, cfg, 997, "Kepler orbit e = 0.5, one period", [&](const mpi::DomainSim& d) {
    const int o = d.owner_of_id(7);
    if (last >= 0 && o != last) ++changes;
    last = o;
    empty += total_int(d.owned() == 0 ? 1 : 0);
  });
  if (world().rank == 0)
    std::printf("orbit: owner of body 7 changed %d times; rank-steps with no sphere %d\n", changes, empty);
  EXPECT_GE(changes, 2);
  if (world().size >= 3) {
    EXPECT_GE(empty, 997);
  }  // two bodies, three ranks: a rank is always empty
}

TEST(MpiDomain, TwoSpheresCollideWithMoreRanksThanSpheres) {
  // a head-on contact of two spheres (G = 1 units) on 2 or 3 ranks: with 3 a rank never has a
  // sphere or a ghost and still takes part in every exchange, halo and reduction
  Spheres sp;
  sp.push(1, Vec3(-0.105, 0.01, 0), Vec3(0.5, 0, 0), Vec3(0, 0, 3), 0.004, 0.1);
  sp.push(2, Vec3(0.105, 0, 0), Vec3(-0.5, 0, 0), Vec3::Zero(), 0.004, 0.1);
  const SimConfig cfg = config(sp, 1.0, false, false);
  int empty = 0, crossing = 0;
  const SimState st = compare(sp, cfg, 300, "two spheres, head-on contact", [&](const mpi::DomainSim& d) {
    empty += total_int(d.owned() == 0 ? 1 : 0);
    crossing += d.cross_rank_contacts() > 0;
  });
  if (world().rank == 0) {
    std::printf("two spheres: rank-steps without spheres %d, steps with the contact across ranks %d\n", empty, crossing);
    EXPECT_LT(st.sp.v[0].x(), 0.0);  // they bounced
  }
  EXPECT_GT(crossing, 10);
  if (world().size >= 3) {
    EXPECT_GE(empty, 301);
  }
}

TEST(MpiDomain, FragmentCrossesEveryDomainAt5kmsInOneStep) {
  // SI: a 8 m pile of 1 m spheres (2000 kg/m^3) and a 1 m fragment at 5 km/s beside it; one step
  // (dt ~ 0.03 s) carries it 150 m, across every domain (the pile is 16 m wide)
  Spheres sp = lattice_pile(8.0, 1.0, 2000.0, 0.05, 5);
  for (std::size_t i = 0; i < sp.size(); ++i) {
    common::KeyedRng rng(3, sp.id[i]);
    sp.v[i] = 0.01 * Vec3(rng.normal(), rng.normal(), rng.normal());
  }
  sp.push(424242, Vec3(-60.0, 12.0, 0.0), Vec3(5000.0, 0.0, 0.0), Vec3::Zero(), sp.m[0], 1.0);
  const DtAdvice adv = choose_kn_dt(sp.m[0], 1.0, 0.05, 1.0, 0.01, 30);
  SimConfig cfg;
  cfg.self_gravity = true;
  cfg.adaptive_gravity = true;
  cfg.contacts = true;
  cfg.contact = gravel_preset(adv.kn);
  cfg.dt = 0.9 * adv.dt;
  ASSERT_GT(5000.0 * cfg.dt, 20.0);
  int changes = 0, last = -1;
  compare(sp, cfg, 40, "pile + 5 km/s fragment", [&](const mpi::DomainSim& d) {
    const int o = d.owner_of_id(424242);
    if (last >= 0 && o != last) ++changes;
    last = o;
  });
  if (world().rank == 0) std::printf("fragment: %.1f m per step, owner changed %d times\n", 5000.0 * cfg.dt, changes);
  EXPECT_GE(changes, 1);
}

TEST(MpiDomain, RepeatedRunsOnTwoThreadsPerRankBitIdentical) {
  const Spheres sp = pile(0.6);
  const SimConfig cfg = config(sp, 1.5, true, false);
  omp_set_num_threads(2);
  SimState st[2];
  for (auto& s : st) {
    mpi::DomainSim d(world(), sp, cfg);
    for (int k = 0; k < 200; ++k) d.step();
    s = d.gather_state();
  }
  omp_set_num_threads(1);
  if (world().rank == 0) {
    EXPECT_EQ(max_diff(st[0], st[1]), 0.0);
  }
}

TEST(MpiDomain, RestartOnFewerRanksContinuesBitIdentically) {
  // N ranks for 150 steps, then the gathered state (a checkpoint's content) restarts on M = N - 1
  // ranks (a sub-communicator) for 150 more: equal to 300 steps on one rank.
  const Spheres sp = pile(0.6);
  const SimConfig cfg = config(sp, 1.5, true, true);
  SimState mid;
  {
    mpi::DomainSim d(world(), sp, cfg);
    while (d.step_count() < 150 || !d.at_gravity_boundary()) d.step();  // checkpoints lie on block boundaries
    mid = d.gather_state();
  }
  // every rank of the restart gets the full state (as every rank reads the checkpoint file)
  std::vector<char> blob;
  int n = static_cast<int>(mid.sp.size()), nh = static_cast<int>(mid.history.size());
  MPI_Bcast(&n, 1, MPI_INT, 0, MPI_COMM_WORLD);
  MPI_Bcast(&nh, 1, MPI_INT, 0, MPI_COMM_WORLD);
  if (world().rank != 0) {
    mid.sp.resize(n);
    for (auto* v : {&mid.a, &mid.alpha, &mid.ag, &mid.a_prev, &mid.alpha_prev}) v->resize(n);
    mid.history.resize(nh);
  }
  for (auto* v : {&mid.sp.x, &mid.sp.v, &mid.sp.w, &mid.a, &mid.alpha, &mid.ag, &mid.a_prev, &mid.alpha_prev})
    MPI_Bcast(v->data(), 3 * n, MPI_DOUBLE, 0, MPI_COMM_WORLD);
  MPI_Bcast(mid.sp.m.data(), n, MPI_DOUBLE, 0, MPI_COMM_WORLD);
  MPI_Bcast(mid.sp.s.data(), n, MPI_DOUBLE, 0, MPI_COMM_WORLD);
  MPI_Bcast(mid.sp.id.data(), n, MPI_UINT64_T, 0, MPI_COMM_WORLD);
  MPI_Bcast(mid.history.data(), static_cast<int>(nh * sizeof(HistoryRecord)), MPI_BYTE, 0, MPI_COMM_WORLD);
  MPI_Bcast(&mid.step, 1, MPI_INT64_T, 0, MPI_COMM_WORLD);
  MPI_Bcast(&mid.time, 1, MPI_DOUBLE, 0, MPI_COMM_WORLD);
  MPI_Bcast(&mid.gravity_step, 1, MPI_INT64_T, 0, MPI_COMM_WORLD);
  MPI_Bcast(&mid.gravity_block, 1, MPI_INT, 0, MPI_COMM_WORLD);
  const int m = std::max(1, world().size - 1);
  MPI_Comm sub;
  MPI_Comm_split(MPI_COMM_WORLD, world().rank < m ? 0 : MPI_UNDEFINED, world().rank, &sub);
  SimState fin;
  if (sub != MPI_COMM_NULL) {
    mpi::Comm c(sub);
    mpi::DomainSim d(c, mid, cfg);
    while (d.step_count() < 300) d.step();
    fin = d.gather_state();
    MPI_Comm_free(&sub);
  }
  if (world().rank == 0) {
    Simulation ref(sp, cfg);
    for (int k = 0; k < 300; ++k) ref.step();
    const double dd = max_diff(fin, ref.state());
    std::printf("restart %d -> %d ranks at step %lld: max |difference| vs 300 steps on one rank %.3g\n",
                world().size, m, static_cast<long long>(mid.step), dd);
    EXPECT_EQ(dd, 0.0);
  }
}

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  omp_set_num_threads(1);  // the one-rank reference sums in index order
  ::testing::InitGoogleTest(&argc, argv);
  if (world().rank != 0) {
    auto& l = ::testing::UnitTest::GetInstance()->listeners();
    delete l.Release(l.default_result_printer());
  }
  int rc = RUN_ALL_TESTS();
  MPI_Allreduce(MPI_IN_PLACE, &rc, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
  MPI_Finalize();
  return rc;
}
