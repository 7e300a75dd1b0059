/// @file multirate_bonds.cpp
/// Bonds in the multi-rate level rule (multirate.hpp, "Bonds"): the level of every bond,
///   l_b = max(0, floor(log2(tau_b / (N h)))),  tau_b = the bond's shortest mode half-period
/// (axial, shear, bending, twist of its two spheres: bonds.hpp, the quantity of the bond dt rule),
/// N = time.steps_per_contact, h the base step; the index of each sphere's bonds; and the bond
/// terms of the level rule (l_i <= l_b) and of the equalisation (l_a = l_b-ends = min(l_a, l_b,
/// l_bond) for every intact bond, whatever its gap). Built only when the scene has bonds.
#include <algorithm>
#include <memory>

#include "ssdem/bonds.hpp"
#include "ssdem/level_rules.hpp"

namespace ssdem {

BondLevels::BondLevels(const BondSystem& b, const Spheres& sp, LevelRules& lr) : b_(b), lr_(lr) {
  const std::size_t nb = b.index_a().size();
  blevel_.resize(nb);
  for (std::size_t k = 0; k < nb; ++k)
    blevel_[k] = static_cast<std::uint8_t>(lr.clock().level_of_time(b.mode_time(k, sp)));
  index();
}

void BondLevels::refresh() {
  if (b_.breaks() != seen_) index();
}

// min(c, l_b of sphere i's intact bonds)
int BondLevels::cap(std::uint32_t i, int c) const {
  for (std::uint32_t q = brow_[i]; q < brow_[i + 1] && c > 0; ++q) c = std::min<int>(c, blevel_[badj_[q]]);
  return c;
}

// min(t, min over i's intact bonds of min(l_partner, l_b)): the Jacobi bound of the equalisation
int BondLevels::bound(std::uint32_t i, int t) const {
  const auto& ia = b_.index_a();
  const auto& ib = b_.index_b();
  for (std::uint32_t q = brow_[i]; q < brow_[i + 1] && t > 0; ++q) {
    const std::uint32_t k = badj_[q];
    const std::uint32_t j = ia[k] == i ? ib[k] : ia[k];
    t = std::min({t, static_cast<int>(lr_.level[j]), static_cast<int>(blevel_[k])});
  }
  return t;
}

// Worklist step of the equalisation over sphere i's intact bonds: both ends to min(l_a, l_b, l_bond).
void BondLevels::enforce(std::uint32_t i, int tz, LevelRules& r) {
  const auto& ia = b_.index_a();
  const auto& ib = b_.index_b();
  for (std::uint32_t q = brow_[i]; q < brow_[i + 1]; ++q) {
    const std::uint32_t k = badj_[q];
    const std::uint32_t a = ia[k], b = ib[k];
    const int t = std::min({static_cast<int>(r.level[a]), static_cast<int>(r.level[b]), static_cast<int>(blevel_[k])});
    r.lower(a, t, tz);
    r.lower(b, t, tz);
  }
}

// The intact bonds of every sphere (CSR, ascending bond order): the level rules see intact bonds only.
void BondLevels::index() {
  const std::size_t n = lr_.level.size();
  const auto& ia = b_.index_a();
  const auto& ib = b_.index_b();
  const auto& broken = b_.bonds().broken;
  const std::size_t nb = ia.size();
  brow_.assign(n + 1, 0);
  for (std::size_t k = 0; k < nb; ++k)
    if (!broken[k]) {
      ++brow_[ia[k] + 1];
      ++brow_[ib[k] + 1];
    }
  for (std::size_t i = 0; i < n; ++i) brow_[i + 1] += brow_[i];
  badj_.resize(brow_[n]);
  bfill_.assign(brow_.begin(), brow_.end() - 1);
  for (std::size_t k = 0; k < nb; ++k)
    if (!broken[k]) {
      badj_[bfill_[ia[k]]++] = static_cast<std::uint32_t>(k);
      badj_[bfill_[ib[k]]++] = static_cast<std::uint32_t>(k);
    }
  seen_ = b_.breaks();
}

}  // namespace ssdem
