/// @file test_mpi_movers.cpp
/// The mover check's rule that lets every rank skip it (domain_movers.cpp, movers_far_apart):
/// every MPI test of this executable runs with DomainSim::audit_movers, so that a step the rule
/// rules out is tested by the ranks anyway and a near pair it missed fails the run; and two
/// fragments owned by different ranks that collide 10 m from both ranks' boxes, which only the
/// rule's mover-mover clause sees: the run equals one rank bit for bit.
#include <gtest/gtest.h>

#include <cstdio>

#include "mpi_support.hpp"
#include "ssdem/mpi/domain_sim.hpp"

using namespace ssdem;

namespace {
[[maybe_unused]] const bool kAudit = [] {
  mpi::DomainSim::audit_movers = true;
  return true;
}();
}  // namespace

TEST(MpiMovers, TwoFragmentsOfTwoRanksMeetFarFromEveryBox) {
  // A slab of 20 x 3 spheres of 1 m along x at y = 0 (the ORB cuts it across x) and two fragments
  // at (-/+10, 30, 0), one on each side of the cut, flying at (+/-20, 20, 0) m/s: they meet head-on
  // at (0, 40, 0) after ~0.45 s, 10 m from the boxes the ranks had at the exchange (which reach
  // y = 30, the fragments' own start). No gravity; soft contacts (5 % overlap, 10 steps).
  Spheres sp = ssdem_test::slab_of_spheres();
  const double m = sp.m[0];
  sp.push(424241, Vec3(-10.0, 30.0, 0.0), Vec3(20.0, 20.0, 0.0), Vec3::Zero(), m, 1.0);
  sp.push(424242, Vec3(10.0, 30.0, 0.0), Vec3(-20.0, 20.0, 0.0), Vec3::Zero(), m, 1.0);
  const DtAdvice adv = choose_kn_dt(m, 1.0, 40.0, 1.0, 0.05, 10);
  SimConfig cfg;
  cfg.self_gravity = false;
  cfg.contacts = true;
  cfg.contact = gravel_preset(adv.kn);
  cfg.dt = 0.9 * adv.dt;
  const int steps = static_cast<int>(0.6 / cfg.dt);  // through the collision (~0.45-0.5 s)
  for (bool mr : {false, true}) {
    cfg.multirate = mr;
    std::int64_t exchanges = 0, checks = 0, reductions = 0;
    const SimState end = ssdem_test::compare(sp, cfg, steps, mr ? "two fragments meet (multi-rate)" : "two fragments meet",
                                             [&](const mpi::DomainSim& d) {
                                               exchanges = d.stats().exchanges;
                                               checks = d.stats().mover_checks;
                                               reductions = d.stats().mover_reductions;
                                             });
    if (ssdem_test::world().rank == 0) {
      double vx = 0;
      for (std::size_t i = 0; i < end.sp.size(); ++i)
        if (end.sp.id[i] == 424241) vx = end.sp.v[i].x();
      std::printf("  %d steps: %lld exchanges, %lld mover checks, %lld reduced; fragment 424241's v_x %.3f m/s\n", steps,
                  static_cast<long long>(exchanges), static_cast<long long>(checks), static_cast<long long>(reductions), vx);
      EXPECT_LT(vx, 0.0);  // they bounced (head-on, equal masses: v_x reversed)
    }
    if (ssdem_test::world().size == 2) {
      EXPECT_GE(exchanges, 1);  // the pair became near: the rule could not rule it out
      EXPECT_GT(reductions, 0);
      EXPECT_LT(reductions, checks);  // far apart most of the flight
    }
  }
}
