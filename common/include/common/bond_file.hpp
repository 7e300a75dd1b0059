/// @file bond_file.hpp
/// The optional `/bonds` group of an `ssdem.spheres` file (sphere_file.hpp): parallel bonds
/// between spheres of the file, keyed by sphere ids (mpm2spheres writes the bonds of the
/// hand-off, ssdem-grav reads them as its initial bond set and writes them into its snapshots
/// with their broken flags). The mechanics (force law, breakage, energy) are in
/// nbody/include/ssdem/bonds.hpp (Potyondy & Cundall 2004 parallel bond); this file is the contract:
///
///   /bonds  attrs: description
///     id_a, id_b      uint64 (B)      1       ids of the two spheres (in /spheres/id, a != b;
///                                             an unordered pair appears once)
///     sphere_index    uint64 (B, 2)   1       rows of id_a, id_b in /spheres (the XDMF Polyline
///                                             connectivity; must agree with the ids)
///     kn, ks          float64 (B)     N/m^3   normal / shear stiffness per unit area, [0, 1e30]
///     sigma_c, tau_c  float64 (B)     Pa      tensile / shear strength, [0, 1e300]
///     radius          float64 (B)     m       bond radius R_b, (0, 1e12]
///     length0         float64 (B)     m       length at rest L0, (0, 1e12]
///     broken          float64 (B)     1       optional: 0 intact, 1 broken (absent: all intact)
///
/// No bonds: no `/bonds` group (and nothing is allocated for it). Bonds of a file carry no shear
/// force or moments: a run starting from a file starts its bonds with zero shear and bending
/// (ssdem-grav checkpoints keep the full bond state in /ssdem_state/bonds instead).
/// The XDMF sidecar of a file with bonds is a spatial collection of two grids: `spheres`
/// (Polyvertex) and `bonds` (Polyline, 2 nodes per element, on the same positions), so ParaView
/// draws each bond as a line, with its fields as cell attributes.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "common/h5.hpp"

namespace common {

/// One bond column: dataset `/bonds/<name>`, valid range [lo, hi] (lo_open: (lo, hi]).
struct BondColumn {
  const char* name;
  const char* unit;
  double lo, hi;
  bool lo_open;
};

inline constexpr BondColumn kBondKn{"kn", "N/m^3", 0.0, 1e30, false};
inline constexpr BondColumn kBondKs{"ks", "N/m^3", 0.0, 1e30, false};
inline constexpr BondColumn kBondSigmaC{"sigma_c", "Pa", 0.0, 1e300, false};
inline constexpr BondColumn kBondTauC{"tau_c", "Pa", 0.0, 1e300, false};
inline constexpr BondColumn kBondRadius{"radius", "m", 0.0, 1e12, true};
inline constexpr BondColumn kBondLength0{"length0", "m", 0.0, 1e12, true};

/// Bonds of a sphere file (structure of arrays; empty = no /bonds group).
struct BondTable {
  std::vector<std::uint64_t> id_a, id_b;
  std::vector<double> kn, ks, sigma_c, tau_c, radius, length0;
  std::vector<double> broken;  ///< 0/1 per bond; empty = all intact

  std::size_t size() const { return id_a.size(); }
  bool empty() const { return id_a.empty(); }
  /// Append an intact bond.
  void add(std::uint64_t a, std::uint64_t b, double kn_, double ks_, double sc, double tc, double rb, double L0);
  /// f(const BondColumn&, vector<double>&) for each float column except `broken`, in file order.
  template <class F, class... S>
  static void zip_columns(F&& f, S&... s) {
    f(kBondKn, s.kn...);
    f(kBondKs, s.ks...);
    f(kBondSigmaC, s.sigma_c...);
    f(kBondTauC, s.tau_c...);
    f(kBondRadius, s.radius...);
    f(kBondLength0, s.length0...);
  }
};

/// Write `/bonds` into an open file; `sphere_ids` are /spheres/id (row order). InputError if a
/// bond names an id that is not there or the columns have different lengths.
void write_bonds(hid_t file, const BondTable& b, const std::vector<std::uint64_t>& sphere_ids);
/// Write `/bonds` into an open file, this process's rows `rows` of it: b holds those rows, `index`
/// their sphere rows (2 per bond: the rows of id_a and id_b in /spheres), with the broken column
/// if `broken` (the same on every process: a process may hold no row). Every process calls it
/// (the MPI writer, common/mpi/sphere_file_mpi.hpp). False if a data write failed.
bool write_bond_rows(hid_t file, const BondTable& b, const std::vector<std::uint64_t>& index, const h5::RowBlock& rows,
                     bool broken);
/// Read and validate `/bonds` if the file has it (else an empty table): every column present
/// with B rows, values finite and in range, ids in `sphere_ids`, a != b, no pair twice,
/// sphere_index agreeing with the ids, broken 0 or 1. InputError naming `path`, the dataset, the
/// row and the valid range (exit 2).
BondTable read_bonds(hid_t file, const std::string& path, const std::vector<std::uint64_t>& sphere_ids);

}  // namespace common
