// The one-pair contact kernel (contact_pair, contact_law.hpp) against the kernel it replaced: the
// FNV-1a hash of every output bit (force, torques, overlap, dissipation, contact flag and the
// whole history row) over 4096 pairs per set of parts must equal the hash the scalar kernel of
// commit f9f1418 gave for the same cases (the constants below were printed by this file built
// against that commit). With test_contact_lanes (every lane of a pack = this one-pair kernel),
// this pins the vectorised kernel to the pre-vectorisation results bit for bit. The cases use
// only the raw mt19937_64 stream (no <random> distributions, whose algorithms are the library's
// choice) and libm only beyond the Taylor range of the transport angle, where glibc's sin and cos
// are correctly rounded.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <random>

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

// uniform in [0, 1) from the top 53 bits; a unit vector from three of them (rejection-free: any
// non-zero vector normalised; a zero one cannot occur with these offsets)
double uni(std::mt19937_64& g) { return static_cast<double>(g() >> 11) * 0x1.0p-53; }
Vec3 unit(std::mt19937_64& g) {
  const double a = uni(g) - 0.5, b = uni(g) - 0.5, c = uni(g) - 0.5 + 1e-9;  // in this order
  const Vec3 v(a, b, c);
  return v / v.norm();
}

std::uint64_t hash_kernel(const ContactParams& p, std::uint64_t seed) {
  const ContactCoeffs c(p);
  std::mt19937_64 g(seed);
  ContactHistory hist(p.parts);
  constexpr int kPairs = 4096;
  hist.assign(kPairs);
  Hash hs;
  dispatch_parts(p.parts, [&](auto parts) {
    constexpr unsigned PARTS = decltype(parts)::value;
    for (int q = 0; q < kPairs; ++q) {
      const double sp = 0.5 + uni(g), sn = 0.5 + uni(g);
      const Vec3 dir = unit(g);
      const Vec3 rho = dir * ((sp + sn) * (0.97 + 0.04 * uni(g)));
      const double m1 = 1.0 + uni(g), m2 = 1.0 + uni(g), m3 = 2.0 + uni(g);
      const double mu = m1 * m2 / m3;
      const double h = 1e-3 * (0.5 + uni(g));
      const double ws = uni(g) < 0.125 ? 300.0 : 1e-2;
      auto vec = [&](double s) {
        const Vec3 e = unit(g);
        return Vec3(e * (s * uni(g)));
      };
      const Vec3 vp = vec(1e-3), vn = vec(1e-3), wp = vec(ws), wn = vec(ws), vph = vec(1e-3), vnh = vec(1e-3);
      const Vec3 wph = uni(g) < 0.1 ? Vec3::Zero() : vec(ws);
      const Vec3 wnh = uni(g) < 0.1 ? Vec3(-wph) : vec(ws);
      // history: n_old near n, equal to it, or turned past 90 degrees; springs from small to far
      // beyond the friction limits
      const double r = uni(g);
      const Vec3 e = unit(g);
      const Vec3 no = r < 0.1 ? dir : (r < 0.2 ? Vec3(-dir + 0.3 * e).normalized() : Vec3(dir + 0.01 * e).normalized());
      const double b1 = 1.0 + uni(g), b2 = uni(g) < 0.5 ? 1e-6 : 1e-1;
      const double big = b1 * b2 * 1e9 / (p.kn > 0 ? p.kn : 1e9);
      for (int i = 0; i < kHistVec; ++i)
        if (!hist.vec_col(i).empty()) hist.vec_col(i)[q] = i == 0 ? no : vec(big);
      for (int i = 0; i < kHistScal; ++i)
        if (!hist.scal_col(i).empty()) hist.scal_col(i)[q] = (uni(g) - 0.5) * big;  // one draw each
      bool act = uni(g) < 0.7;
      PairResult res;
      const bool con = contact_pair<PARTS, false>(c, rho, sp, sn, mu, vp, vn, wp, wn, vph, vnh, wph, wnh, h, act,
                                                  hist.row(q), res);
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
  const ContactParams gravel = gravel_preset(1e9);
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
