/// @file test_mpi_failure_check.cpp
/// ssdem-grav's end-of-step failure check on MPI ranks (domain_sim.cpp check_state, verdict)
/// against one rank, under mpirun -np 2 and -np 3 (label mpi). Inside a gravity block the ranks
/// decide the check together at the next base step's movers allgather, so every rank must fail
/// with the one-rank message (the worst overlapping pair's ids, or the first non-finite sphere in
/// index order, and the step), at the one-rank step or one base step later. Only a failing rank
/// sends its part: a healthy hot pile sends none over 300 steps (inside and at the ends of
/// gravity blocks), a failing run at least one.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "common/status.hpp"
#include "ssdem/mpi/domain_sim.hpp"
#include "ssdem/simulation.hpp"

#include "mpi_support.hpp"

using namespace ssdem;

namespace {
using ssdem_test::pile_config;
using ssdem_test::world;

struct Failure {
  std::string what;        ///< the NumericalError's message ("" if none)
  std::int64_t step = -1;  ///< the step count when it was thrown
};
template <class Sim>
Failure run_until_failure(Sim& sim, int steps) {
  try {
    for (int k = 0; k < steps; ++k) sim.step();
  } catch (const common::NumericalError& e) {
    return Failure{e.what(), sim.step_count()};
  }
  return Failure{};
}
Failure one_rank_failure(const Spheres& sp, const SimConfig& cfg, int steps) {
  Simulation ref(sp, cfg);
  return run_until_failure(ref, steps);
}
// Every rank fails with the one-rank message, at its step or one base step later.
void expect_failure_as_one_rank(const Spheres& sp, const SimConfig& cfg, int steps, const Failure& one,
                                const char* what) {
  mpi::DomainSim d(world(), sp, cfg);
  const Failure many = run_until_failure(d, steps);
  EXPECT_EQ(many.what, one.what) << "rank " << world().rank;
  EXPECT_TRUE(many.step == one.step || many.step == one.step + 1) << many.step << " vs " << one.step;
  long long parts = d.stats().check_parts;
  world().sum(&parts, 1);
  EXPECT_GE(parts, 1);  // the failing rank's part travelled
  if (world().rank == 0)
    std::printf("%s: one rank fails at step %lld (%s); %d ranks at %lld\n", what, static_cast<long long>(one.step),
                one.what.c_str(), world().size, static_cast<long long>(many.step));
}
}  // namespace

TEST(MpiDomain, RunawayOverlapInsideAGravityBlockFailsAtTheOneRankStep) {
  // Two spheres meeting at 60 (G = 1 units) with k_n chosen for 1: a runaway overlap inside a
  // long gravity block.
  Spheres sp;
  sp.push(1, Vec3(-0.102, 0.0, 0), Vec3(30.0, 0, 0), Vec3::Zero(), 0.004, 0.1);
  sp.push(2, Vec3(0.102, 0.0, 0), Vec3(-30.0, 0, 0), Vec3::Zero(), 0.004, 0.1);
  SimConfig cfg = pile_config(sp, 1.0, false, false);
  cfg.gravity_every = 1000;
  cfg.max_overlap_frac = 0.3;
  const Failure one = one_rank_failure(sp, cfg, 2000);
  ASSERT_FALSE(one.what.empty()) << "the one-rank run must fail";
  ASSERT_LT(one.step, 1000) << "inside the first gravity block";
  expect_failure_as_one_rank(sp, cfg, 2000, one, "runaway overlap");
}

TEST(MpiDomain, NonFiniteStateInsideAGravityBlockFailsWithTheOneRankMessage) {
  // Two spheres meeting with an absurd k_n: the contact force overflows to inf and the state
  // turns non-finite inside a long gravity block.
  Spheres sp;
  sp.push(1, Vec3(-0.1002, 0.0, 0), Vec3(1.0, 0, 0), Vec3::Zero(), 0.004, 0.1);  // they touch after a few steps
  sp.push(2, Vec3(0.1002, 0.0, 0), Vec3(-1.0, 0, 0), Vec3::Zero(), 0.004, 0.1);
  SimConfig cfg = pile_config(sp, 1.0, false, false);
  cfg.contact.kn = 1e308;
  cfg.min_steps_per_contact = 1e-300;  // let the dt rule pass this k_n
  cfg.max_overlap_frac = 1e300;        // the overlap check must not fire first
  cfg.gravity_every = 1000;
  const Failure one = one_rank_failure(sp, cfg, 500);
  ASSERT_NE(one.what.find("non-finite"), std::string::npos) << "the one-rank run must fail non-finite: '" << one.what << "'";
  ASSERT_GT(one.step, 1) << "after the first step, inside the first gravity block";
  expect_failure_as_one_rank(sp, cfg, 500, one, "non-finite");
}

TEST(MpiDomain, AHealthyRunSendsNoFailureCheckParts) {
  // A hot pile (contacts, overlaps well below the limit, a gravity block of 7 steps): the check
  // runs every step on every rank, and no rank has a part to send.
  const Spheres sp = ssdem_test::hot_pile(0.75, 11);
  SimConfig cfg = pile_config(sp, 2.0, true, false);
  cfg.gravity_every = 7;
  mpi::DomainSim d(world(), sp, cfg);
  for (int k = 0; k < 300; ++k) d.step();
  long long parts = d.stats().check_parts, movers = d.stats().mover_checks;
  world().sum(&parts, 1);
  world().sum(&movers, 1);
  EXPECT_EQ(parts, 0);
  if (world().rank == 0)
    std::printf("hot pile, 300 steps: %lld failure-check parts sent, %lld mover checks\n", parts, movers);
}
