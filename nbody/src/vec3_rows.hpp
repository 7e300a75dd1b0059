/// @file vec3_rows.hpp
/// Vec3 arrays as the (n x 3) float64 rows of HDF5 datasets, and back (io.cpp, io_bonds.cpp).
#pragma once
#include <vector>

#include "ssdem/spheres.hpp"

namespace ssdem::io_rows {

inline std::vector<double> flat(const std::vector<Vec3>& v) {
  std::vector<double> out(3 * v.size());
  for (std::size_t i = 0; i < v.size(); ++i)
    for (int k = 0; k < 3; ++k) out[3 * i + k] = v[i][k];
  return out;
}
inline std::vector<double> flat(const std::vector<double>& v) { return v; }
inline std::vector<Vec3> unflat(const std::vector<double>& f) {
  std::vector<Vec3> v(f.size() / 3);
  for (std::size_t i = 0; i < v.size(); ++i) v[i] = Vec3(f[3 * i], f[3 * i + 1], f[3 * i + 2]);
  return v;
}

}  // namespace ssdem::io_rows
