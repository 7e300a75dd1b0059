/// @file lanes.hpp
/// The arithmetic the contact parts are written in, so that one source serves one pair
/// (R = double, with bool masks and plain branches) and a pack of kLanes pairs evaluated together
/// (R = Lanes, a GCC/Clang vector of doubles: one SIMD instruction per operation, masks instead
/// of branches). The pack kernel does in each lane exactly the IEEE operations of the one-pair
/// kernel, in the same order (no fused multiply-add: the build does not enable it), so both give
/// bit-identical results, and so do builds with 2 (SSE2) and 4 (AVX) lanes. The nbody target is
/// compiled with -ffp-contract=off so that no compiler fuses them where FMA exists (aarch64,
/// -march=native). Lanes that a mask discards may divide by zero or take the root of a negative
/// number: a build that traps floating-point exceptions would trap there.
///   V3<R>            a 3-vector of R (dot and squaredNorm summed left to right, as Eigen does)
///   select(m, a, b)  a where m, else b (lane-wise)
///   any(m), none(m)  over the lanes
///   lsqrt, lmin, labs  lane-wise sqrt (correctly rounded), std::min semantics, |x|
///   splat<R>(x)      x in every lane
///   lane(r, l), set_lane(r, l, x)  read / write lane l (one pair: the value itself)
#pragma once
#include <cmath>
#include <type_traits>
#include <utility>

#include "ssdem/spheres.hpp"

#if defined(__SSE2__)
#include <immintrin.h>
#endif

namespace ssdem {

#if defined(__AVX__)
constexpr int kLanes = 4;  // internal linkage: a translation unit sees its own width
typedef double Lanes __attribute__((vector_size(32)));
#else
constexpr int kLanes = 2;
typedef double Lanes __attribute__((vector_size(16)));
#endif
/// What a lane-wise comparison of two packs gives (all bits set where true).
using LaneMask = decltype(Lanes{} < Lanes{});

template <class R>
inline constexpr bool is_pack = std::is_same_v<R, Lanes>;
template <class R>
using MaskOf = std::conditional_t<is_pack<R>, LaneMask, bool>;

[[gnu::always_inline]] inline double lane(const double& r, int) { return r; }
[[gnu::always_inline]] inline bool lane(bool m, int) { return m; }
[[gnu::always_inline]] inline void set_lane(double& r, int, double x) { r = x; }
[[gnu::always_inline]] inline double lane(const Lanes& r, int l) { return r[l]; }
[[gnu::always_inline]] inline void set_lane(Lanes& r, int l, double x) { r[l] = x; }
[[gnu::always_inline]] inline bool lane(const LaneMask& m, int l) { return m[l] != 0; }

[[gnu::always_inline]] inline double select(bool m, double a, double b) { return m ? a : b; }
[[gnu::always_inline]] inline Lanes select(const LaneMask& m, const Lanes& a, const Lanes& b) {
  return m ? a : b;
}
[[gnu::always_inline]] inline bool any(bool m) { return m; }
[[gnu::always_inline]] inline bool any(const LaneMask& m) {
#if defined(__AVX__)
  return _mm256_movemask_pd(__m256d(m)) != 0;
#elif defined(__SSE2__)
  return _mm_movemask_pd(__m128d(m)) != 0;
#else
  for (int l = 0; l < kLanes; ++l)
    if (m[l]) return true;
  return false;
#endif
}
[[gnu::always_inline]] inline bool none(bool m) { return !m; }
[[gnu::always_inline]] inline bool none(const LaneMask& m) { return !any(m); }
[[gnu::always_inline]] inline bool mnot(bool m) { return !m; }
[[gnu::always_inline]] inline LaneMask mnot(const LaneMask& m) { return ~m; }
[[gnu::always_inline]] inline bool mand(bool a, bool b) { return a && b; }
[[gnu::always_inline]] inline LaneMask mand(const LaneMask& a, const LaneMask& b) { return a & b; }

[[gnu::always_inline]] inline double lsqrt(double x) { return std::sqrt(x); }
[[gnu::always_inline]] inline Lanes lsqrt(const Lanes& x) {
#if defined(__AVX__)
  return Lanes(_mm256_sqrt_pd(__m256d(x)));
#elif defined(__SSE2__)
  return Lanes(_mm_sqrt_pd(__m128d(x)));
#else
  Lanes r;
  for (int l = 0; l < kLanes; ++l) r[l] = std::sqrt(x[l]);
  return r;
#endif
}
/// std::min(a, b): b if b < a, else a.
template <class R>
[[gnu::always_inline]] inline R lmin(const R& a, const R& b) {
  return select(b < a, b, a);
}
/// |x| (a negative zero stays negative: only compared, never stored).
template <class R>
[[gnu::always_inline]] inline R labs(const R& x) {
  return select(x < 0.0, -x, x);
}

/// The pack {f(0), ..., f(kLanes - 1)}, built in registers (setting lanes one by one through
/// memory would stall on store forwarding).
template <class F, std::size_t... L>
[[gnu::always_inline]] inline Lanes lanes_from_impl(const F& f, std::index_sequence<L...>) {
  return Lanes{f(static_cast<int>(L))...};
}
template <class F>
[[gnu::always_inline]] inline Lanes lanes_from(const F& f) {
  return lanes_from_impl(f, std::make_index_sequence<kLanes>{});
}
template <class F, std::size_t... L>
[[gnu::always_inline]] inline LaneMask mask_from_impl(const F& f, std::index_sequence<L...>) {
  return LaneMask{(f(static_cast<int>(L)) ? -1 : 0)...};
}
/// The mask whose lane l is f(l).
template <class F>
[[gnu::always_inline]] inline LaneMask mask_from(const F& f) {
  return mask_from_impl(f, std::make_index_sequence<kLanes>{});
}

/// x in every lane (a negative zero stays negative).
template <class R>
[[gnu::always_inline]] inline R splat(double x) {
  if constexpr (is_pack<R>)
    return lanes_from([&](int) { return x; });
  else
    return x;
}

/// A 3-vector of R.
template <class R>
struct V3 {
  R x, y, z;
  V3() = default;
  [[gnu::always_inline]] V3(const R& a, const R& b, const R& c) : x(a), y(b), z(c) {}
  /// From an Eigen vector (one pair).
  template <class Q = R, std::enable_if_t<!is_pack<Q>, int> = 0>
  [[gnu::always_inline]] V3(const Vec3& v) : x(v[0]), y(v[1]), z(v[2]) {}
  [[gnu::always_inline]] static V3 zero() { return V3(splat<R>(0.0), splat<R>(0.0), splat<R>(0.0)); }
  template <class Q = R, std::enable_if_t<!is_pack<Q>, int> = 0>
  [[gnu::always_inline]] Vec3 eigen() const { return Vec3(x, y, z); }
  [[gnu::always_inline]] R dot(const V3& o) const { return x * o.x + y * o.y + z * o.z; }
  [[gnu::always_inline]] R squaredNorm() const { return x * x + y * y + z * z; }
  [[gnu::always_inline]] V3 cross(const V3& o) const {
    return V3(y * o.z - z * o.y, z * o.x - x * o.z, x * o.y - y * o.x);
  }
  [[gnu::always_inline]] V3 operator+(const V3& o) const { return V3(x + o.x, y + o.y, z + o.z); }
  [[gnu::always_inline]] V3 operator-(const V3& o) const { return V3(x - o.x, y - o.y, z - o.z); }
  [[gnu::always_inline]] V3 operator-() const { return V3(-x, -y, -z); }
  [[gnu::always_inline]] V3 operator*(const R& s) const { return V3(x * s, y * s, z * s); }
  [[gnu::always_inline]] V3 operator/(const R& s) const { return V3(x / s, y / s, z / s); }
  [[gnu::always_inline]] friend V3 operator*(const R& s, const V3& v) { return V3(s * v.x, s * v.y, s * v.z); }
  /// Lane l as an Eigen vector, and setting it (pack).
  [[gnu::always_inline]] Vec3 at(int l) const { return Vec3(lane(x, l), lane(y, l), lane(z, l)); }
  [[gnu::always_inline]] void set(int l, const Vec3& v) {
    set_lane(x, l, v[0]);
    set_lane(y, l, v[1]);
    set_lane(z, l, v[2]);
  }
};
/// The pack of 3-vectors {f(0), ..., f(kLanes - 1)} (f returns an Eigen vector or a reference).
template <class F>
[[gnu::always_inline]] inline V3<Lanes> v3_from(const F& f) {
  return V3<Lanes>(lanes_from([&](int l) { return f(l)[0]; }), lanes_from([&](int l) { return f(l)[1]; }),
                   lanes_from([&](int l) { return f(l)[2]; }));
}
template <class R, class M>
[[gnu::always_inline]] inline V3<R> select(const M& m, const V3<R>& a, const V3<R>& b) {
  return V3<R>(select(m, a.x, b.x), select(m, a.y, b.y), select(m, a.z, b.z));
}

}  // namespace ssdem
