/// @file field.hpp
/// A named per-item (particle or sphere) array with a unit, used for optional state datasets.
#pragma once
#include <cstddef>
#include <string>
#include <vector>

namespace common {

/// `values` holds N * ncomp doubles, item-major (row i = values[i*ncomp .. i*ncomp+ncomp-1]),
/// exactly the layout of an N x ncomp HDF5 dataset (ncomp = 1: 1-D dataset of length N).
struct Field {
  std::string name;  ///< dataset name, e.g. "damage", "stress"
  std::string unit;  ///< SI unit, "1" for dimensionless
  std::size_t ncomp = 1;
  std::vector<double> values;
  std::string description;  ///< optional, written as a `description` attribute

  std::size_t count() const { return ncomp ? values.size() / ncomp : 0; }
};

}  // namespace common
