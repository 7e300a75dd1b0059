/// @file face_bonds.cpp
/// Bonds between face-adjacent hand-off spheres with the damage law of face_bonds.hpp.
#include "handoff/face_bonds.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>

#include "common/status.hpp"

namespace handoff {

double bond_damage_factor(double D, double D_c) {
  const double d = std::clamp(D, 0.0, 1.0);
  return d < D_c ? 1.0 - d / D_c : 0.0;
}

common::BondTable face_bonds(const common::SphereSet& s, const HandoffBondParams& p, const std::string& file) {
  common::BondTable b;
  const std::size_t n = s.count();
  if (n == 0) return b;
  const common::Field* dmg = s.field("damage");
  if (!dmg || dmg->ncomp != 1)
    throw common::InputError(file, "bonds.enabled",
                             "bonds from the hand-off need the damage of the spheres (a snapshot with "
                             "/particles/damage and `damage` in the carry list)");
  const double r = s.radius[0], e = 2.0 * r;
  // lattice coordinates relative to the first sphere (21 bits per axis, offset to be non-negative)
  constexpr std::int64_t kOff = std::int64_t(1) << 20;
  std::vector<std::uint64_t> key(n);
  for (std::size_t i = 0; i < n; ++i) {
    if (std::fabs(s.radius[i] - r) > 1e-9 * r)
      throw common::InputError(file, "/spheres/radius", "bonds from the hand-off need spheres of one radius (row " +
                                                            std::to_string(i) + ")");
    std::uint64_t k = 0;
    for (int d = 0; d < 3; ++d) {
      const double u = (s.position[3 * i + d] - s.position[d]) / e;
      const double q = std::round(u);
      if (std::fabs(u - q) > 1e-6 || std::fabs(q) >= static_cast<double>(kOff))
        throw common::InputError(file, "/spheres/position", "sphere at row " + std::to_string(i) +
                                                                " is not on the hand-off lattice of edge " + std::to_string(e) + " m");
      k = (k << 21) | static_cast<std::uint64_t>(static_cast<std::int64_t>(q) + kOff);
    }
    key[i] = k;
  }
  std::unordered_map<std::uint64_t, std::size_t> at;
  at.reserve(2 * n);
  for (std::size_t i = 0; i < n; ++i) at.emplace(key[i], i);
  const std::uint64_t step[3] = {std::uint64_t(1) << 42, std::uint64_t(1) << 21, 1};
  for (std::size_t i = 0; i < n; ++i) {
    for (int d = 0; d < 3; ++d) {
      const auto it = at.find(key[i] + step[d]);
      if (it == at.end()) continue;
      const std::size_t j = it->second;
      const double f = bond_damage_factor(std::max(dmg->values[i], dmg->values[j]), p.damage_critical);
      if (!(f > 0.0)) continue;
      b.add(s.id[i], s.id[j], f * p.kn, f * p.ks, f * p.sigma_c, f * p.tau_c, p.radius_ratio * r, e);
    }
  }
  return b;
}

}  // namespace handoff
