/// @file drift_schedule.hpp
/// When each sphere's re-insertion test can next fire, in multi-rate steps: the contact list
/// (ContactSystem, contacts.hpp "Scheduled tests") then tests only the spheres kicked since the
/// previous base step and those due now, instead of every sphere at every base step.
///
/// Between two of its kicks a sphere drifts at one velocity v: after m more base steps of
/// x += h v it lies at x + m u, u = h v (exact arithmetic). Its test |x - x_ref| > D (D its
/// re-insertion distance) can first fire at the smallest m with |d + m u| > D', d = x - x_ref,
/// D' = D - delta: |d + m u|^2 is a convex quadratic in m, below D'^2 at m = 0, so the test is
/// due at the larger root m* of |d + m u|^2 = D'^2, and no earlier. The sphere is tested again at
/// floor(m*) (>= 1; one call early at most), and not at all if its next kick comes first.
/// delta bounds the rounding: each drift rounds a component by at most ulp(|x| + 2|u|) and the
/// test's own subtraction and squares add a few ulp of D, so over H calls
///   delta = 4 H 2^-52 (|x|_inf + |x_ref|_inf + (H + 2) |u|_inf) + 1e-12 D,
/// about eight times the bound. A sphere whose schedule says "not yet" has not moved past D in
/// floating point either: the re-insertions, and so the list and every result, are those of the
/// test of every sphere at every step, bit for bit (tests/nbody/test_drift_schedule.cpp).
/// When it pays: planning a kicked sphere reads six per-sphere arrays at scattered places (about
/// 14 ns), where the test of every sphere streams two (0.6 ns per sphere on 2 threads): the
/// schedule pays when fewer than about 1/20 of the spheres are kicked per step (measured in
/// nbody/README.md, "Scheduled tests"). So each gravity block (from one call that names no kicks
/// to the next) is planned only when the block before kicked fewer than 1/32 of the spheres per
/// call on average; otherwise, and in the first block, every sphere is tested at every call.
/// Kicks: the caller names the spheres whose velocity changed since the previous call, and each
/// one's level l: its velocity then holds through the next 2^l - 1 calls at least (multirate.hpp:
/// a sphere synchronised now is kicked again when it next closes, 2^l base steps on, or earlier
/// if promoted, which makes it active and so named then).
#pragma once
#include <cstdint>
#include <vector>

#include "ssdem/spheres.hpp"

namespace ssdem {

class DriftSchedule {
 public:
  /// Longest wait before a sphere's plan is renewed (calls): the ring's length by default.
  static constexpr std::int64_t kDefaultRing = 4096;
  explicit DriftSchedule(std::int64_t ring = kDefaultRing) : ring_len_(ring < 2 ? 2 : ring) {}
  std::int64_t ring_length() const { return ring_len_; }

  /// Forget every plan: the next call tests every sphere (after a test without kick information,
  /// a rebuild without it, or a change of the sphere count).
  void invalidate() { valid_ = false; }
  bool valid() const { return valid_; }

  /// Opens the next call for n spheres. Returns true when the caller tests every sphere: kicked ==
  /// null (every sphere may have been kicked: a block opens, and whether it is planned is decided),
  /// no valid plans, or a block that is not planned; the caller then plans every sphere if
  /// planning(). Otherwise appends to `out` the kicked spheres and those due now, each once, and
  /// returns false. level[i]: sphere i's level (its velocity holds through 2^level[i] - 1 more
  /// calls once kicked).
  bool open(std::size_t n, const std::uint32_t* kicked, std::size_t nkicked, const std::uint8_t* level,
            std::vector<std::uint32_t>& out);
  /// Calls before sphere i's test may fire (>= 1), from its position x, reference position xr,
  /// drift per call u and re-insertion distance D, looking `horizon` calls ahead; horizon + 1:
  /// not within them.
  std::int64_t wait(const Vec3& x, const Vec3& xr, const Vec3& u, double D, std::int64_t horizon) const;
  /// Calls sphere i may wait before its next kick (its velocity is known that far).
  std::int64_t horizon(std::uint32_t i) const { return until_[i] - now_ - 1; }
  /// Enters sphere i's next test, m = wait(...) calls from now (none if beyond its horizon;
  /// a renewal after ring_length() - 1 calls if the horizon is longer; at the next call if the
  /// horizon has passed, which a caller that names every kick never makes happen).
  void enter(std::uint32_t i, std::int64_t m);
  /// Whether this block is planned (open() decides it when a block opens).
  bool planning() const { return planning_; }
  /// After a call that tested and entered every sphere.
  void set_valid() { valid_ = planning_; }
  /// Bytes per sphere held (plans; the ring's entries are counted at their current size).
  double bytes_per_sphere(std::size_t n) const;

 private:
  std::int64_t ring_len_;
  bool valid_ = false, planning_ = false;
  std::int64_t now_ = 0;
  std::int64_t kicked_sum_ = 0, calls_ = 0;  // over the block so far: kicks named, calls
  std::vector<std::int64_t> due_;    // call of the sphere's next test, -1: none entered
  std::vector<std::int64_t> until_;  // call at which it is kicked next at the latest
  std::vector<std::vector<std::uint32_t>> ring_;  // entries by call mod ring_len_ (stale ones skipped)
};

}  // namespace ssdem
