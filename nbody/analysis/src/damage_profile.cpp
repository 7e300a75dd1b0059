/// @file damage_profile.cpp
/// Implementation of analysis/damage_profile.hpp; the governing equations, sources and deviations are documented there.
#include "analysis/damage_profile.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace analysis {

namespace {
std::vector<ProfileBin> bin_values(const std::vector<double>& coord, const std::vector<std::size_t>& items,
                                   const double* mass, const double* damage, int nbins, double lo, double hi) {
  if (nbins < 1) throw std::invalid_argument("damage profile: bins must be >= 1");
  if (!(lo < hi)) {
    lo = std::numeric_limits<double>::infinity();
    hi = -lo;
    for (std::size_t k = 0; k < items.size(); ++k) {
      lo = std::min(lo, coord[k]);
      hi = std::max(hi, coord[k]);
    }
    if (items.empty()) lo = 0.0, hi = 1.0;
    if (!(lo < hi)) hi = lo + 1.0;  // all items at one coordinate: one unit-wide range
  }
  std::vector<ProfileBin> b(static_cast<std::size_t>(nbins));
  const double w = (hi - lo) / nbins;
  for (int k = 0; k < nbins; ++k) {
    b[k].lo = lo + k * w;
    b[k].hi = (k == nbins - 1) ? hi : lo + (k + 1) * w;
  }
  std::vector<double> md(static_cast<std::size_t>(nbins), 0.0);
  for (std::size_t k = 0; k < items.size(); ++k) {
    const double s = coord[k];
    if (s < lo || s > hi) continue;
    int j = static_cast<int>(std::floor((s - lo) / w));
    j = std::clamp(j, 0, nbins - 1);
    const std::size_t i = items[k];
    b[j].count += 1;
    b[j].mass += mass[i];
    md[j] += mass[i] * damage[i];
  }
  for (int k = 0; k < nbins; ++k)
    b[k].mean = b[k].mass > 0 ? md[k] / b[k].mass : std::numeric_limits<double>::quiet_NaN();
  return b;
}
}  // namespace

std::vector<ProfileBin> axial_profile(const double* position, const double* mass, const double* damage,
                                      std::size_t n, const ProfileSpec& spec, const char* select) {
  const double an = spec.axis.norm();
  if (!(an > 0)) throw std::invalid_argument("damage profile: zero axis");
  const Eigen::Vector3d a = spec.axis / an;
  std::vector<double> coord;
  std::vector<std::size_t> items;
  for (std::size_t i = 0; i < n; ++i) {
    if (select && !select[i]) continue;
    const Eigen::Vector3d d = Eigen::Vector3d(position + 3 * i) - spec.origin;
    const double s = d.dot(a);
    if (spec.cylinder_radius > 0 && (d - s * a).norm() > spec.cylinder_radius) continue;
    coord.push_back(s);
    items.push_back(i);
  }
  return bin_values(coord, items, mass, damage, spec.bins, spec.lo, spec.hi);
}

std::vector<ProfileBin> radial_profile(const double* position, const double* mass, const double* damage,
                                       std::size_t n, const ProfileSpec& spec, const char* select) {
  std::vector<double> coord;
  std::vector<std::size_t> items;
  for (std::size_t i = 0; i < n; ++i) {
    if (select && !select[i]) continue;
    coord.push_back((Eigen::Vector3d(position + 3 * i) - spec.origin).norm());
    items.push_back(i);
  }
  ProfileSpec s = spec;
  if (!(s.lo < s.hi)) {  // shells start at the centre
    double hi = 0.0;
    for (double r : coord) hi = std::max(hi, r);
    s.lo = 0.0;
    s.hi = hi > 0 ? hi : 1.0;
  }
  return bin_values(coord, items, mass, damage, s.bins, s.lo, s.hi);
}

}  // namespace analysis
