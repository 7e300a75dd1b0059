/// @file exact_sum.hpp
/// A sum of doubles that does not depend on the order of its terms: every term is added exactly
/// into a fixed-point accumulator that spans the whole double range, and the total is rounded to
/// a double once, at the end (Kulisch's long accumulator; Kulisch & Miranker 1981, ch. 6).
///
/// Why: a series row (energies, momentum) summed term by term in one loop on one rank cannot be
/// reproduced by ranks that each hold part of the terms, nor by threads, because floating-point
/// addition is not associative. With exact sums each rank adds its own terms, the accumulators
/// are added (integer addition is associative: an MPI_SUM of their limbs), and every
/// decomposition gives the same bits as one rank. The result is also the correctly rounded sum
/// (round to nearest, ties to even; a total in the subnormal range is exact, every sum of doubles
/// being a multiple of 2^-1074) of the exact terms, so a total far smaller than its terms
/// (momentum of a body at rest, an energy change) keeps every digit the terms carry.
///
/// Representation: a double is m 2^e with an integer m < 2^53 and e in [-1074, 971]; its bit
/// position p = e + 1074 lies in [0, 2045], so m 2^p fits in bits [0, 2098). The accumulator keeps
/// that integer in base-2^32 digits held in int64 limbs (kLimbs of them, with headroom for 2^64
/// terms of the largest double): an addition splits m 2^(p mod 32) into three 32-bit pieces and
/// adds (or subtracts) them to three limbs, with no carry. Limbs are normalised (carries
/// propagated, every limb but the last in [0, 2^32)) every 2^20 additions, far before one could
/// overflow,
/// and before the value is read or the limbs are shared. Infinities and NaNs are not added to
/// the digits: they are summed apart, and value() returns that sum when there was one.
/// Cost: a few integer operations per term (about 3 ns), 560 bytes per accumulator.
#pragma once
#include <array>
#include <cstdint>

namespace common {

class ExactSum {
 public:
  static constexpr int kLimbs = 70;

  void add(double x);
  ExactSum& operator+=(double x) {
    add(x);
    return *this;
  }
  /// Add another accumulator's terms (exact).
  void merge(const ExactSum& o);
  /// The correctly rounded sum of every term added (±inf beyond the double range; NaN or ±inf if
  /// such a term was added).
  double value() const;

  /// The normalised limbs and the non-finite sum, for sharing between ranks: the limbs of several
  /// accumulators may be summed element-wise (kLimbs int64 values each; fewer than 2^31 of
  /// them) and loaded back with from_limbs, which equals merging the accumulators.
  std::array<std::int64_t, kLimbs> limbs() const;
  double special() const { return special_; }
  bool has_special() const { return has_special_; }
  static ExactSum from_limbs(const std::int64_t* limbs, double special, bool has_special);

 private:
  void normalise();
  std::array<std::int64_t, kLimbs> d_{};
  std::uint32_t pending_ = 0;  ///< additions since the last normalisation
  double special_ = 0.0;       ///< sum of the non-finite terms
  bool has_special_ = false;
};

}  // namespace common
