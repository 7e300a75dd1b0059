/// @file finite.hpp
/// NaN/Inf guards: never let a non-finite value pass silently.
#pragma once
#include <cmath>
#include <cstddef>
#include <string>

namespace common {

/// Index of the first non-finite value in [data, data+n), or n if all are finite.
inline std::size_t first_non_finite(const double* data, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i)
    if (!std::isfinite(data[i])) return i;
  return n;
}

}  // namespace common
