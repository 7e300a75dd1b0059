/// @file ordered_bits.hpp
/// A double's bit pattern mapped so that unsigned order is numeric order: the collective selections
/// (the ORB cuts, orb_collective.cpp; the k-th smallest, sphere_summary_mpi.cpp) bisect on it.
#pragma once
#include <bit>
#include <cstdint>

namespace ssdem::mpi {

/// key_of(a) < key_of(b) iff a < b, for finite a, b (-0 as +0: they compare equal, as in a sort).
inline std::uint64_t key_of(double v) {
  v += 0.0;  // -0 -> +0
  const std::uint64_t b = std::bit_cast<std::uint64_t>(v);
  return (b >> 63) ? ~b : b | (std::uint64_t{1} << 63);
}
/// The double of a key (the inverse of key_of on its range).
inline double value_of(std::uint64_t k) {
  const std::uint64_t b = (k >> 63) ? k & ~(std::uint64_t{1} << 63) : ~k;
  return std::bit_cast<double>(b);
}

}  // namespace ssdem::mpi
