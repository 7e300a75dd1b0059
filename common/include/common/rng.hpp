/// @file rng.hpp
/// Counter-based random numbers keyed by (seed, particle id, stream), so that every particle's
/// random draws are independent of thread count, particle order and domain decomposition.
/// The generator is SplitMix64 (Steele, Lea & Flood 2014, "Fast splittable pseudorandom number
/// generators", OOPSLA) applied to a hashed key; uniform doubles use the top 53 bits.
#pragma once
#include <cmath>
#include <cstdint>

namespace common {

/// One avalanche round of SplitMix64's output function.
constexpr std::uint64_t mix64(std::uint64_t z) {
  z += 0x9E3779B97F4A7C15ull;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

/// A private random stream for one particle: the same (seed, id, stream) always gives the same
/// sequence.
class KeyedRng {
 public:
  KeyedRng(std::uint64_t seed, std::uint64_t id, std::uint64_t stream = 0)
      : state_(mix64(mix64(seed ^ 0xA0761D6478BD642Full) ^ mix64(id + 0x3C6EF372FE94F82Bull) ^
                     mix64(stream * 0x9E3779B97F4A7C15ull + 1))) {}

  std::uint64_t next_u64() {
    state_ += 0x9E3779B97F4A7C15ull;
    std::uint64_t z = state_;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  /// Uniform on [0, 1).
  double uniform() { return static_cast<double>(next_u64() >> 11) * 0x1.0p-53; }
  /// Uniform on (0, 1] (safe for log).
  double uniform_open0() { return 1.0 - uniform(); }
  /// Standard normal (Box–Muller, one value per call).
  double normal() {
    const double u1 = uniform_open0(), u2 = uniform();
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(6.283185307179586 * u2);
  }
  /// Poisson-distributed count with the given mean: Knuth's product method for mean < 30,
  /// otherwise a rounded normal approximation with continuity correction (clamped at 0).
  std::uint64_t poisson(double mean) {
    if (!(mean > 0.0)) return 0;
    if (mean < 30.0) {
      const double L = std::exp(-mean);
      std::uint64_t k = 0;
      double p = 1.0;
      do {
        ++k;
        p *= uniform();
      } while (p > L);
      return k - 1;
    }
    const double x = std::floor(mean + std::sqrt(mean) * normal() + 0.5);
    return x < 0.0 ? 0 : static_cast<std::uint64_t>(x);
  }

 private:
  std::uint64_t state_;
};

}  // namespace common
