/// @file awkward_pairs.hpp
/// Contact cases chosen to reach every path of the pair kernel, shared by test_contact_golden (the
/// one-pair kernel against the kernel it replaced) and test_contact_lanes (packs against one pair):
/// unit-ish spheres with a gap from -3 % to +1 % of the reach (about one in five not touching),
/// velocities ~1e-3, spins ~1e-2 with one pair in eight spinning fast enough to leave the Taylor
/// range of the transport angle, zero or opposite half-step spins, history springs from small to
/// far beyond the friction limits, n_old near n, equal to it or turned past 90 degrees, and 70 %
/// of the pairs in contact at the previous step. Only the raw mt19937_64 stream is used (no
/// <random> distributions, whose algorithms are the library's choice), every draw in a fixed
/// order, so the golden hashes do not depend on the standard library or on argument order.
#pragma once
#include <random>

#include "ssdem/contact_law.hpp"

namespace ssdem::test {

struct AwkwardPair {
  PairIn<double> in;
  HistOf<double> hist;  ///< columns of the parts that are off stay zero
  bool active = false;
};

/// Uniform in [0, 1) from the top 53 bits.
inline double awkward_uni(std::mt19937_64& g) { return static_cast<double>(g() >> 11) * 0x1.0p-53; }
inline Vec3 awkward_unit(std::mt19937_64& g) {
  const double a = awkward_uni(g) - 0.5, b = awkward_uni(g) - 0.5, c = awkward_uni(g) - 0.5 + 1e-9;
  const Vec3 v(a, b, c);
  return v / v.norm();
}

/// The next case for a set of parts (history drawn for its enabled columns only) and stiffness kn.
inline AwkwardPair awkward_pair(std::mt19937_64& g, unsigned parts, double kn) {
  auto uni = [&] { return awkward_uni(g); };
  auto vec = [&](double s) {
    const Vec3 e = awkward_unit(g);
    return V3<double>(Vec3(e * (s * uni())));
  };
  AwkwardPair c{};
  const double sp = 0.5 + uni(), sn = 0.5 + uni();
  const Vec3 dir = awkward_unit(g);
  c.in.rho = V3<double>(Vec3(dir * ((sp + sn) * (0.97 + 0.04 * uni()))));
  c.in.sp = sp;
  c.in.sn = sn;
  const double m1 = 1.0 + uni(), m2 = 1.0 + uni(), m3 = 2.0 + uni();
  c.in.mu = m1 * m2 / m3;
  c.in.h = 1e-3 * (0.5 + uni());
  const double ws = uni() < 0.125 ? 300.0 : 1e-2;
  c.in.vp = vec(1e-3);
  c.in.vn = vec(1e-3);
  c.in.wp = vec(ws);
  c.in.wn = vec(ws);
  c.in.vp_half = vec(1e-3);
  c.in.vn_half = vec(1e-3);
  c.in.wp_half = uni() < 0.1 ? V3<double>::zero() : vec(ws);
  c.in.wn_half = uni() < 0.1 ? -c.in.wp_half : vec(ws);
  const double r = uni();
  const Vec3 e = awkward_unit(g);
  const Vec3 no = r < 0.1 ? dir : (r < 0.2 ? Vec3(-dir + 0.3 * e).normalized() : Vec3(dir + 0.01 * e).normalized());
  const double b1 = 1.0 + uni(), b2 = uni() < 0.5 ? 1e-6 : 1e-1;
  const double big = b1 * b2 * 1e9 / kn;
  for (int i = 0; i < kHistVec; ++i)
    if (vec_column_enabled(i, parts)) c.hist.v[i] = i == 0 ? V3<double>(no) : vec(big);
  for (int i = 0; i < kHistScal; ++i)
    if (scal_column_enabled(i, parts)) c.hist.q[i] = (uni() - 0.5) * big;
  c.active = uni() < 0.7;
  return c;
}

}  // namespace ssdem::test
