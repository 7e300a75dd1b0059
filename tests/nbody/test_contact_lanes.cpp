// The contact kernel in packs of pairs (contact/lanes.hpp, contact_law.hpp contact_lanes,
// pair_batch.hpp): every lane must give exactly, bit for bit, what the one-pair kernel gives
// (forces, torques, dissipation, contact flag and history), for every set of parts, on awkward
// inputs: contacts that start, go on and end in one pack, stick and slip, spins that send the
// transport angle past the Taylor range (libm path), turns wider than 90 degrees, zero spins
// and no tilt. Then ContactSystem::compute (packs, gathered and scattered) against a loop of the
// one-pair kernel over the same pairs, summed per sphere in compute's order, over steps in which
// contacts open and close. The cases are awkward_pairs.hpp's. This file is compiled twice when SUITE_SIMD gives AVX2 (4 lanes, and
// the baseline's 2), so both widths are checked.
#include <gtest/gtest.h>

#include <bit>
#include <map>
#include <random>

#include "awkward_pairs.hpp"
#include "ssdem/contacts.hpp"

using namespace ssdem;

namespace {
bool same(double a, double b) { return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b); }
bool same(const Vec3& a, const Vec3& b) { return same(a[0], b[0]) && same(a[1], b[1]) && same(a[2], b[2]); }

using Case = test::AwkwardPair;

template <unsigned PARTS>
void check_parts(const ContactParams& p, std::uint64_t seed) {
  const ContactCoeffs c(p);
  std::mt19937_64 g(seed);
  constexpr int kPacks = 512;
  int contacts = 0, released = 0, started = 0;
  for (int b = 0; b < kPacks; ++b) {
    Case cs[kLanes];
    for (auto& x : cs) x = test::awkward_pair(g, PARTS, p.kn > 0 ? p.kn : 1e9);
    // one pair at a time
    PairOut<double> o1[kLanes];
    HistOf<double> h1[kLanes];
    bool c1[kLanes];
    for (int l = 0; l < kLanes; ++l) {
      h1[l] = cs[l].hist;
      c1[l] = contact_lanes<PARTS, false>(c, cs[l].in, cs[l].active, h1[l], o1[l]);
      contacts += c1[l];
      released += cs[l].active && !c1[l];
      started += !cs[l].active && c1[l];
    }
    // the pack
    const auto pk = [&](auto get) { return lanes_from([&](int l) { return get(cs[l]); }); };
    const auto pv = [&](auto get) { return v3_from([&](int l) { return get(cs[l]).eigen(); }); };
    PairIn<Lanes> in;
    in.rho = pv([](const Case& x) { return x.in.rho; });
    in.sp = pk([](const Case& x) { return x.in.sp; });
    in.sn = pk([](const Case& x) { return x.in.sn; });
    in.mu = pk([](const Case& x) { return x.in.mu; });
    in.h = pk([](const Case& x) { return x.in.h; });
    in.vp = pv([](const Case& x) { return x.in.vp; });
    in.vn = pv([](const Case& x) { return x.in.vn; });
    in.wp = pv([](const Case& x) { return x.in.wp; });
    in.wn = pv([](const Case& x) { return x.in.wn; });
    in.vp_half = pv([](const Case& x) { return x.in.vp_half; });
    in.vn_half = pv([](const Case& x) { return x.in.vn_half; });
    in.wp_half = pv([](const Case& x) { return x.in.wp_half; });
    in.wn_half = pv([](const Case& x) { return x.in.wn_half; });
    HistOf<Lanes> hp;
    for (int i = 0; i < kHistVec; ++i) hp.v[i] = v3_from([&](int l) { return cs[l].hist.v[i].eigen(); });
    for (int i = 0; i < kHistScal; ++i) hp.q[i] = lanes_from([&](int l) { return cs[l].hist.q[i]; });
    PairOut<Lanes> op;
    const LaneMask cp = contact_lanes<PARTS, false>(c, in, mask_from([&](int l) { return cs[l].active; }), hp, op);
    for (int l = 0; l < kLanes; ++l) {
      SCOPED_TRACE("pack " + std::to_string(b) + " lane " + std::to_string(l));
      ASSERT_EQ(lane(cp, l), c1[l]);
      ASSERT_TRUE(same(lane(op.diss, l), o1[l].diss)) << lane(op.diss, l) << " vs " << o1[l].diss;
      if (!c1[l] && cs[l].active && c.edges) {  // released: its edge force, no torque
        ASSERT_TRUE(same(op.F.at(l), o1[l].F.eigen())) << op.F.at(l).transpose() << " vs " << o1[l].F.eigen().transpose();
        ASSERT_TRUE(same(op.Tp.at(l), Vec3::Zero()) && same(o1[l].Tp.eigen(), Vec3::Zero()));
        continue;
      }
      if (!c1[l]) continue;
      ASSERT_TRUE(same(op.F.at(l), o1[l].F.eigen())) << op.F.at(l).transpose() << " vs " << o1[l].F.eigen().transpose();
      ASSERT_TRUE(same(op.Tp.at(l), o1[l].Tp.eigen()));
      ASSERT_TRUE(same(op.Tn.at(l), o1[l].Tn.eigen()));
      ASSERT_TRUE(same(lane(op.overlap, l), o1[l].overlap));
      for (int i = 0; i < kHistVec; ++i)
        if (vec_column_enabled(i, PARTS)) {
          ASSERT_TRUE(same(hp.v[i].at(l), h1[l].v[i].eigen())) << "column " << i;
        }
      for (int i = 0; i < kHistScal; ++i)
        if (scal_column_enabled(i, PARTS)) {
          ASSERT_TRUE(same(lane(hp.q[i], l), h1[l].q[i])) << "column " << i;
        }
    }
  }
  // the cases cover what they claim: starts, releases and most pairs in contact
  EXPECT_GT(started, kPacks * kLanes / 10);
  EXPECT_GT(released, kPacks * kLanes / 20);
  EXPECT_GT(contacts, kPacks * kLanes / 2);
}
}  // namespace

TEST(ContactLanes, EveryLaneIsBitIdenticalToTheOnePairKernel) {
  SCOPED_TRACE("lanes " + std::to_string(kLanes));
  ContactParams gravel = gravel_preset(1e9);
  check_parts<kPartDamping | kPartTangential | kPartRolling | kPartTwisting>(gravel, 1);
  ContactParams pk = gravel;
  pk.slip = SlipRule::pkdgrav;
  check_parts<kPartDamping | kPartTangential | kPartRolling | kPartTwisting>(pk, 2);
  ContactParams hz = gravel;
  hz.parts = kPartHertz | kPartDamping | kPartTangential | kPartRolling | kPartTwisting;
  hz.E = 1e9;
  hz.vmax = 1.0;
  check_parts<kPartHertz | kPartDamping | kPartTangential | kPartRolling | kPartTwisting>(hz, 3);
  ContactParams co = gravel;
  co.parts = kPartTangential | kPartCohesion;
  co.sigma_c = 1e3;
  check_parts<kPartTangential | kPartCohesion>(co, 4);
  ContactParams lin = gravel;
  lin.parts = kPartDamping;
  check_parts<kPartDamping>(lin, 5);
}

// compute() in packs against the one-pair kernel over the same pair list, per sphere in compute's
// order (pairs where the sphere is the j member, ascending, then those where it is the i member):
// forces, torques and dissipated energy; every other step through a multi-rate Subset with a
// step of its own for each pair.
TEST(ContactLanes, ComputeInPacksMatchesTheOnePairLoopBitForBit) {
  std::mt19937_64 g(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Spheres sp;
  const int n = 9 * 9 * 9;  // a jittered cubic lattice of spheres, some touching, some not
  for (int k = 0; k < n; ++k) {
    const Vec3 x(2.0 * (k % 9) + 0.03 * u(g), 2.0 * ((k / 9) % 9) + 0.03 * u(g), 2.0 * (k / 81) + 0.03 * u(g));
    sp.push(k, x, Vec3(u(g), u(g), u(g)) * 1e-2, Vec3(u(g), u(g), u(g)) * 1e-2, 4000.0 * (1.0 + 0.1 * u(g)),
            1.0 + 0.01 * u(g));
  }
  const ContactParams p = gravel_preset(1e6);
  ContactSystem cs(p, {}, 0.2);
  ContactHistory ref(p.parts);
  const ContactCoeffs coeffs(p);
  const double h = 1e-2;
  std::vector<Vec3> F, T;
  int changes = 0;
  std::map<std::pair<std::size_t, std::size_t>, std::size_t> prev;  // pair -> its row in ref
  for (int step = 0; step < 60; ++step) {
    for (int k = 0; k < n; ++k) sp.x[k] += sp.v[k] * h;
    cs.update_neighbors(sp, true);  // rebuilt every step: the reference history follows by pair
    const std::size_t P = cs.pair_count();
    ContactHistory nref(p.parts);
    nref.assign(P);
    std::map<std::pair<std::size_t, std::size_t>, std::size_t> now;
    for (std::size_t q = 0; q < P; ++q) {
      const auto key = std::make_pair<std::size_t, std::size_t>(cs.pair_i()[q], cs.pair_j()[q]);
      now[key] = q;
      if (auto it = prev.find(key); it != prev.end() && ref.active[it->second]) nref.copy_row(q, ref, it->second);
    }
    prev = now;
    ref = nref;
    const std::vector<Vec3> vp = sp.v, wp = sp.w;
    std::vector<double> diss(n, 0.0), hp(P, h);
    if (step % 2 == 1) {
      ContactSystem::Subset sub;
      for (std::size_t q = 0; q < P; ++q) {
        sub.pairs.push_back(static_cast<std::uint32_t>(q));
        hp[q] = h * (0.5 + 0.5 * (u(g) + 1.0));
        sub.hpair.push_back(hp[q]);
      }
      for (int k = 0; k < n; ++k) {
        sub.spheres.push_back(static_cast<std::uint32_t>(k));
        sub.hsphere.push_back(h);
      }
      cs.compute(sp, vp, wp, sub, F, T, diss.data());
    } else {
      cs.compute(sp, vp, wp, h, F, T, diss.data());
    }
    std::vector<Vec3> pF(P), pTp(P), pTn(P);
    std::vector<double> pD(P);
    std::vector<char> on(P);
    dispatch_parts(p.parts, [&](auto parts) {
      for (std::size_t q = 0; q < P; ++q) {
        const std::size_t i = cs.pair_i()[q], j = cs.pair_j()[q];
        bool act = ref.active[q];
        PairResult r;
        const double mu = sp.m[i] * sp.m[j] / (sp.m[i] + sp.m[j]);
        on[q] = contact_pair<decltype(parts)::value, false>(coeffs, sp.x[j] - sp.x[i], sp.s[i], sp.s[j], mu, vp[i],
                                                            vp[j], wp[i], wp[j], sp.v[i], sp.v[j], sp.w[i], sp.w[j],
                                                            hp[q], act, ref.row(q), r);
        changes += (act != (ref.active[q] != 0));
        on[q] = on[q] || (ref.active[q] && coeffs.edges);  // released: its edge force counts
        ref.active[q] = act;
        pF[q] = r.F;
        pTp[q] = r.Tp;
        pTn[q] = r.Tn;
        pD[q] = r.diss;
      }
      return 0;
    });
    for (int k = 0; k < n; ++k) {
      Vec3 f = Vec3::Zero(), t = Vec3::Zero();
      double dk = 0.0;
      for (std::size_t q = 0; q < P; ++q)
        if (cs.pair_j()[q] == static_cast<std::uint32_t>(k)) {
          if (on[q]) {
            f -= pF[q];
            t += pTn[q];
          }
          dk += 0.5 * pD[q];
        }
      for (std::size_t q = 0; q < P; ++q)
        if (cs.pair_i()[q] == static_cast<std::uint32_t>(k)) {
          if (on[q]) {
            f += pF[q];
            t += pTp[q];
          }
          dk += 0.5 * pD[q];
        }
      ASSERT_TRUE(same(diss[k], 0.0 + dk)) << "step " << step << " sphere " << k;
      ASSERT_TRUE(same(F[k], f)) << "step " << step << " sphere " << k << ": " << F[k].transpose() << " vs "
                                  << f.transpose();
      ASSERT_TRUE(same(T[k], t)) << "step " << step << " sphere " << k;
    }
    // spin the spheres and stir the velocities a little, so that contacts slide, open and close
    for (int k = 0; k < n; ++k) {
      sp.v[k] += (F[k] / sp.m[k]) * h + Vec3(u(g), u(g), u(g)) * 1e-3;
      sp.w[k] += T[k] * (h / (0.4 * sp.m[k] * sp.s[k] * sp.s[k]));
    }
  }
  EXPECT_GT(changes, 20);  // contacts started and ended during the run
}
