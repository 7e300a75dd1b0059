/// @file frame_transport.hpp
/// Transport of tangent-plane history with a contact frame whose normal turned from n_old to n
/// over one step (Schwartz, Richardson & Michel 2012, Granular Matter 14:363, eqs 17-19; pkdgrav
/// DoDEM): rotate about nbar = (n_old + n)/|.| by (h/2) w_sum.nbar (w_sum: the sum of the two
/// half-step spins; a wall: the sphere's), then by the rotation taking n_old to n. That second
/// rotation, about a = n_old x n (|a| = sin, c = n_old.n = cos), is Rodrigues' formula without
/// normalising the axis:
///   R v = v + a x v + a x (a x v) / (1 + c)        (since (1 - c) / sin^2 = 1 / (1 + c)),
/// used for turns below 90 degrees (every resolved contact); larger turns use the normalised axis
///   R v = v c + (k x v) s + k (k.v)(1 - c)        (Rodrigues, unit axis k, angle with cos c, sin s).
/// Written in lane arithmetic (lanes.hpp): FrameTransportT<double> for one contact (the bonds,
/// through FrameTransport), FrameTransportT<Lanes> for a pack of contacts (the pair kernel), with
/// identical results lane by lane.
#pragma once
#include <cmath>

#include "ssdem/contact/lanes.hpp"

namespace ssdem {

/// Rodrigues rotation of v about unit axis k by angle (cos c, sin s).
template <class R>
[[gnu::always_inline]] inline V3<R> rotate_about(const V3<R>& v, const V3<R>& k, const R& c, const R& s) {
  return v * c + k.cross(v) * s + k * (k.dot(v) * (1.0 - c));
}

/// cos and sin of x: Taylor polynomials (to x^10 and x^9) for |x| < 1/16, where the first omitted
/// term is below 3e-20 of the result (so they agree with libm to rounding); libm beyond. The
/// transport angle of a resolved contact is tiny; this saves a libm call per contact and step.
template <class R>
[[gnu::always_inline]] inline void small_sincos_taylor(const R& x, R& c, R& s) {
  const R x2 = x * x;  // Horner in x^2 with the Taylor coefficients
  s = x + x * x2 * (-1.0 / 6 + x2 * (1.0 / 120 + x2 * (-1.0 / 5040 + x2 * (1.0 / 362880))));
  c = 1.0 + x2 * (-0.5 + x2 * (1.0 / 24 + x2 * (-1.0 / 720 + x2 * (1.0 / 40320 + x2 * (-1.0 / 3628800)))));
}
[[gnu::always_inline]] inline void small_sincos(double x, double& c, double& s) {
  if (std::abs(x) < 0.0625) {
    small_sincos_taylor(x, c, s);
  } else {
    c = std::cos(x);
    s = std::sin(x);
  }
}
[[gnu::always_inline]] inline void small_sincos(const Lanes& x, Lanes& c, Lanes& s) {
  small_sincos_taylor(x, c, s);
  const LaneMask big = mnot(labs(x) < 0.0625);
  if (any(big))
    for (int l = 0; l < kLanes; ++l)
      if (big[l]) {
        c[l] = std::cos(x[l]);
        s[l] = std::sin(x[l]);
      }
}

template <class R>
struct FrameTransportT {
  using M = MaskOf<R>;
  M spin, tilt, wide;
  V3<R> nbar, a;
  R ca, sa, ic;  // spin cos/sin; tilt: 1/(1 + c), or c for a wide turn
  [[gnu::always_inline]] FrameTransportT(const V3<R>& no, const V3<R>& n, const V3<R>& w_sum, const R& h) {
    const V3<R> nb = no + n;
    const R l = lsqrt(nb.squaredNorm());
    const R ang = 0.5 * h * w_sum.dot(nb) / l;
    spin = mand(l > 0.0, ang != 0.0);
    nbar = nb / l;
    small_sincos(select(spin, ang, splat<R>(0.0)), ca, sa);
    a = no.cross(n);
    tilt = a.squaredNorm() > 0.0;
    const R c = no.dot(n);
    const M narrow = c > 0.0;
    wide = mand(tilt, mnot(narrow));
    ic = select(narrow, 1.0 / (1.0 + c), c);
  }
  [[gnu::always_inline]] V3<R> operator()(V3<R> v) const {
    if (any(spin)) v = select(spin, rotate_about(v, nbar, ca, sa), v);
    if (any(tilt)) {
      const V3<R> av = a.cross(v);
      V3<R> t = v + (av + a.cross(av) * ic);
      if (any(wide)) {
        const R sn = lsqrt(a.squaredNorm());
        t = select(wide, rotate_about(v, a / sn, ic, sn), t);
      }
      v = select(tilt, t, v);
    }
    return v;
  }
};

/// One contact (or bond) with Eigen vectors.
struct FrameTransport {
  FrameTransportT<double> t;
  FrameTransport(const Vec3& no, const Vec3& n, const Vec3& w_sum, double h)
      : t(V3<double>(no), V3<double>(n), V3<double>(w_sum), h) {}
  Vec3 operator()(const Vec3& v) const { return t(V3<double>(v)).eigen(); }
};

}  // namespace ssdem
