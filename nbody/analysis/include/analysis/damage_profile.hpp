/// @file damage_profile.hpp
/// Mass-weighted damage profiles (El Mir, Ramesh & Richardson 2019, Fig. 6).
///
/// Axial profile: s_i = (x_i - o)·â is the coordinate along the axis â through the origin o;
/// optionally only items within a cylinder |(x_i - o) - s_i â| <= R_cyl count. In bin b:
///     D̄_b = Σ_{i∈b} m_i D_i / Σ_{i∈b} m_i                                           (1)
/// Radial profile: the same with r_i = |x_i - o| in spherical shells.
/// Bins are uniform on [lo, hi]; items outside are ignored; an item exactly at hi falls in the
/// last bin. If lo >= hi the range is the extent of the (selected) data. Empty bins report
/// mass 0 and mean NaN (written as empty in CSV / null in JSON).
/// Sums are serial in item order (deterministic).
#pragma once
#include <Eigen/Core>
#include <cstddef>
#include <string>
#include <vector>

namespace analysis {

struct ProfileBin {
  double lo = 0.0, hi = 0.0;
  std::size_t count = 0;
  double mass = 0.0;
  double mean = 0.0;  ///< mass-weighted mean damage (NaN when empty)
  double centre() const { return 0.5 * (lo + hi); }
};

struct ProfileSpec {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();  ///< normalised internally
  int bins = 20;
  double lo = 0.0, hi = 0.0;     ///< lo >= hi: automatic range
  double cylinder_radius = 0.0;  ///< axial only; <= 0: no restriction
};

/// Axial profile (1). `select` (may be null) marks the items to include.
std::vector<ProfileBin> axial_profile(const double* position, const double* mass, const double* damage,
                                      std::size_t n, const ProfileSpec& spec, const char* select = nullptr);
/// Radial-shell profile about spec.origin (axis and cylinder ignored).
std::vector<ProfileBin> radial_profile(const double* position, const double* mass, const double* damage,
                                       std::size_t n, const ProfileSpec& spec, const char* select = nullptr);

}  // namespace analysis
