/// @file xdmf.hpp
/// XDMF 3 sidecars so ParaView/VisIt open particle and sphere files with all their fields
/// (ecosystem.md §1.2): Polyvertex topology, XYZ geometry, one Attribute per dataset. A grid with
/// `connectivity_path` set is a Polyline grid instead (2 nodes per element: the bonds of a sphere
/// file, bond_file.hpp), whose attributes are cell-centred; xdmf_text_spatial puts several grids
/// of one time (spheres and their bonds) into a spatial collection.
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
  std::string center = "Node";  ///< "Node" (per point) or "Cell" (per element of a Polyline grid)
};

struct XdmfGrid {
  std::string name;
  double time = 0.0;
  std::size_t count = 0;
  std::string h5file;         ///< file name as referenced from the .xmf (relative)
  std::string position_path;  ///< N x 3 float64 dataset
  std::vector<XdmfAttribute> attributes;
  std::string connectivity_path;  ///< Polyline grid: (elements x 2) uint64 rows of the positions; "" = Polyvertex
  std::size_t elements = 0;       ///< Polyline grid: number of line elements
};

/// The XDMF text of one grid (or a temporal collection of several).
std::string xdmf_text(const std::vector<XdmfGrid>& grids);
/// The XDMF text of several grids of the same time in one spatial collection (a sphere file with bonds).
std::string xdmf_text_spatial(const std::string& name, const std::vector<XdmfGrid>& grids);
/// Atomically write `xmf_path`.
void write_xdmf(const std::string& xmf_path, const std::vector<XdmfGrid>& grids);
/// Sidecar path for an HDF5 file: same stem, ".xmf".
std::string xdmf_path_for(const std::string& h5_path);

}  // namespace common
