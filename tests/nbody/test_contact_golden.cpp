// The one-pair contact kernel (contact_pair, contact_law.hpp) against the kernel it replaced: the
// FNV-1a hash of every output bit (force, torques, overlap, dissipation, contact flag and the
// whole history row) over 4096 pairs per set of parts (awkward_pairs.hpp) must equal the hash the
// scalar kernel of commit f9f1418 gave for the same cases (the constants below were printed by
// this test built against that commit). With test_contact_lanes (every lane of a pack = this
// one-pair kernel), this pins the vectorised kernel to the pre-vectorisation results bit for bit
// (with the edge impulses off, which that kernel did not have).
// libm enters only beyond the Taylor range of the transport angle, where glibc's sin and cos are
// correctly rounded.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <random>

#include "awkward_pairs.hpp"
#include "ssdem/contacts.hpp"

using namespace ssdem;

namespace {
struct Hash {
  std::uint64_t h = 1469598103934665603ull;
  void add(const void* p, std::size_t n) {
    const auto* b = static_cast<const unsigned char*>(p);
    for (std::size_t k = 0; k < n; ++k) h = (h ^ b[k]) * 1099511628211ull;
  }
  void add(double x) { add(&x, sizeof x); }
  void add(const Vec3& v) {
    add(v[0]);
    add(v[1]);
    add(v[2]);
  }
};

std::uint64_t hash_kernel(const ContactParams& p, std::uint64_t seed) {
  const ContactCoeffs coeffs(p);
  std::mt19937_64 g(seed);
  ContactHistory hist(p.parts);
  constexpr int kPairs = 4096;
  hist.assign(kPairs);
  Hash hs;
  dispatch_parts(p.parts, [&](auto parts) {
    constexpr unsigned PARTS = decltype(parts)::value;
    for (int q = 0; q < kPairs; ++q) {
      const test::AwkwardPair c = test::awkward_pair(g, p.parts, p.kn > 0 ? p.kn : 1e9);
      for (int i = 0; i < kHistVec; ++i)
        if (!hist.vec_col(i).empty()) hist.vec_col(i)[q] = c.hist.v[i].eigen();
      for (int i = 0; i < kHistScal; ++i)
        if (!hist.scal_col(i).empty()) hist.scal_col(i)[q] = c.hist.q[i];
      bool act = c.active;
      PairResult res;
      const PairIn<double>& in = c.in;
      const bool con = contact_pair<PARTS, false>(coeffs, in.rho.eigen(), in.sp, in.sn, in.mu, in.vp.eigen(),
                                                  in.vn.eigen(), in.wp.eigen(), in.wn.eigen(), in.vp_half.eigen(),
                                                  in.vn_half.eigen(), in.wp_half.eigen(), in.wn_half.eigen(), in.h,
                                                  act, hist.row(q), res);
      hs.add(res.F);
      hs.add(res.Tp);
      hs.add(res.Tn);
      hs.add(res.overlap);
      hs.add(res.diss);
      const unsigned char flags = static_cast<unsigned char>((con ? 1 : 0) | (act ? 2 : 0));
      hs.add(&flags, 1);
      for (int i = 0; i < kHistVec; ++i)
        if (!hist.vec_col(i).empty()) hs.add(hist.vec_col(i)[q]);
      for (int i = 0; i < kHistScal; ++i)
        if (!hist.scal_col(i).empty()) hs.add(hist.scal_col(i)[q]);
    }
    return 0;
  });
  return hs.h;
}
}  // namespace

TEST(ContactGolden, OnePairKernelGivesThePreviousKernelsBits) {
  // the previous kernel had no edge impulses (contact.resolve_edges = false gives its bits; the
  // edges are verified against the exact restitution in test_contact_edges.cpp)
  ContactParams gravel = gravel_preset(1e9);
  gravel.resolve_edges = false;
  ContactParams pk = gravel;
  pk.slip = SlipRule::pkdgrav;
  ContactParams hz = gravel;
  hz.parts = kPartHertz | kPartDamping | kPartTangential | kPartRolling | kPartTwisting;
  hz.E = 1e9;
  hz.vmax = 1.0;
  ContactParams co = gravel;
  co.parts = kPartTangential | kPartCohesion;
  co.sigma_c = 1e3;
  ContactParams lin = gravel;
  lin.parts = kPartDamping;
  const ContactParams sets[] = {gravel, pk, hz, co, lin};
  // hashes of commit f9f1418's scalar kernel on these cases (x86-64, GCC 12, no FMA)
  const std::uint64_t expected[] = {0xeb87135e34466481ull, 0x3456911e2d9f98c6ull, 0xfeaf9f2885b4f2d6ull,
                                   0x1eb192b9fbd67f19ull, 0x5b28d98ff506805aull};
  for (int k = 0; k < 5; ++k) {
    const std::uint64_t got = hash_kernel(sets[k], 100 + k);
    EXPECT_EQ(got, expected[k]) << "set " << k << ": 0x" << std::hex << got;
  }
}
