/// @file xdmf.hpp
/// XDMF 3 sidecars so ParaView/VisIt open particle and sphere files with all their fields
/// (ecosystem.md §1.2): Polyvertex topology, XYZ geometry, one Attribute per dataset.
#pragma once
#include <cstddef>
#include <string>
#include <vector>

namespace common {

struct XdmfAttribute {
  std::string name;       ///< attribute name shown in ParaView
  std::string h5path;     ///< dataset path inside the HDF5 file, e.g. "/particles/mass"
  std::size_t ncomp = 1;  ///< 1 scalar, 3 vector, 6 Tensor6, other: Matrix
  std::string number_type = "Float";  ///< Float, Int, UInt
  int precision = 8;
};

struct XdmfGrid {
  std::string name;
  double time = 0.0;
  std::size_t count = 0;
  std::string h5file;         ///< file name as referenced from the .xmf (relative)
  std::string position_path;  ///< N x 3 float64 dataset
  std::vector<XdmfAttribute> attributes;
};

/// The XDMF text of one grid (or a temporal collection of several).
std::string xdmf_text(const std::vector<XdmfGrid>& grids);
/// Atomically write `xmf_path`.
void write_xdmf(const std::string& xmf_path, const std::vector<XdmfGrid>& grids);
/// Sidecar path for an HDF5 file: same stem, ".xmf".
std::string xdmf_path_for(const std::string& h5_path);

}  // namespace common
