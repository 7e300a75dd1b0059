/// @file multirate_levels.cpp
/// The multi-rate level rules (time.multirate = true): each listed pair's l_c, the new level of
/// the spheres synchronised at a base step, and the equalisation of near pairs to the fixed
/// point; rules and proofs in multirate.hpp, the bond part in multirate_bonds.cpp.
#include <omp.h>

#include <algorithm>
#include <cstdint>
#include <iterator>
#include <vector>

#include "ssdem/multirate.hpp"
#include "ssdem/simulation.hpp"

namespace ssdem {
namespace {
constexpr std::size_t kOmpMin = 2048;  // below this many spheres or pairs a loop runs serially
constexpr std::uint8_t kNone = 255;    // no wall in reach (wall_level)
}  // namespace

bool Simulation::near_pair(std::uint32_t i, std::uint32_t j) const {
  const double r = sp_.s[i] + sp_.s[j] + near_gap_;
  return (sp_.x[j] - sp_.x[i]).squaredNorm() < r * r;
}

int Simulation::pair_level(std::uint32_t i, std::uint32_t j) const {
  const double mi = sp_.m[i], mj = sp_.m[j];
  return clock_.level(mi * mj / (mi + mj), sp_.s[i] * sp_.s[j] / (sp_.s[i] + sp_.s[j]));
}

int Simulation::wall_level(std::uint32_t i) const {
  int l = kNone;
  for (const Plane& w : contacts_->walls())
    if ((sp_.x[i] - w.point).dot(w.normal) < sp_.s[i] + near_gap_) {
      l = std::min(l, clock_.level(sp_.m[i], sp_.s[i]));
      break;  // one wall law: the same level for every wall
    }
  return l;
}

// l_c of every listed pair, cached per pair (it depends only on the two masses and radii): the
// level rules below read it for every listed pair at every base step.
void Simulation::update_pair_levels() {
  if (!contacts_ || contacts_->list_version() == plev_version_) return;
  const auto& pi = contacts_->pair_i();
  const auto& pj = contacts_->pair_j();
  const std::size_t P = pi.size();
  plev_.resize(P);
#pragma omp parallel for schedule(static) if (P >= kOmpMin)
  for (std::size_t p = 0; p < P; ++p) plev_[p] = static_cast<std::uint8_t>(pair_level(pi[p], pj[p]));
  plev_version_ = contacts_->list_version();
}

// New levels of the spheres synchronised now (sync_ = 1): min(L, tz, l_c of near pairs/walls).
// Per sphere over its own pairs (both CSR directions): parallel, each sphere writes its own level.
// The distance test runs only for a pair whose l_c would lower the level.
void Simulation::assign_levels(int tz, int L) {
  const std::size_t n = sp_.size();
  const int top = std::min(tz, L);
  const bool ct = contacts_ != nullptr;
  const std::vector<std::uint32_t> none;
  const auto& pi = ct ? contacts_->pair_i() : none;
  const auto& pj = ct ? contacts_->pair_j() : none;
  const auto& ri = ct ? contacts_->row_i() : none;
  const auto& rj = ct ? contacts_->row_j() : none;
  const auto& jp = ct ? contacts_->jpair() : none;
  const bool walls = ct && !contacts_->walls().empty();
#pragma omp parallel for schedule(static) if (n >= kOmpMin)
  for (std::size_t k = 0; k < n; ++k) {
    if (!sync_[k]) continue;
    const auto i = static_cast<std::uint32_t>(k);
    int c = top;
    if (ct && c > 0) {
      for (std::uint32_t p = ri[i]; p < ri[i + 1] && c > 0; ++p)
        if (plev_[p] < c && near_pair(i, pj[p])) c = plev_[p];
      for (std::uint32_t q = rj[i]; q < rj[i + 1] && c > 0; ++q)
        if (plev_[jp[q]] < c && near_pair(pi[jp[q]], i)) c = plev_[jp[q]];
      if (walls && c > 0) c = std::min(c, wall_level(i));
      if (bonds_ && c > 0) c = bond_cap(i, c);
    }
    if (level_[k] != c) {
      level_[k] = static_cast<std::uint8_t>(c);
      lflag_[k] = 1;
    }
  }
}

// Lower sphere i to `target` (a sphere not synchronised now is promoted to min(target, tz)).
bool Simulation::lower_level(std::uint32_t i, int target, int tz, std::vector<std::uint32_t>& work) {
  if (level_[i] <= target) return false;
  lflag_[i] = 1;
  if (sync_[i]) {
    level_[i] = static_cast<std::uint8_t>(target);
  } else {
    level_[i] = static_cast<std::uint8_t>(std::min(target, tz));
    sync_[i] = 1;
    promoted_[i] = 1;
    ++lstats_.promotions;
  }
  work.push_back(i);
  return true;
}

// Near pairs: both on min(l_i, l_j, l_c) (walls: l_i <= l_c(wall)), to the fixed point.
// The rule is monotone (levels only drop; sphere i's bound f_i(min_j min(l_j, l_c(i, j))), with
// f_i(t) = t if i is synchronised, else min(t, tz)), so every order of applying it that stops at
// a fixed point stops at the same one: the largest fixed point below the starting levels.
// Only an unsettled pair, not (l_i = l_j <= l_c), can violate the rule; a settled pair holds it
// whether or not it is near. The unsettled pairs are kept from one base step to the next and
// updated from the pairs of the spheres whose level changed since (lflag_; rebuilt from all
// listed pairs when the list changes or more than 1/16 of the levels changed), so a pile at rest
// costs O(spheres) bytes per base step.
// The violations among them (the near ones) seed the serial worklist, with, where there are
// walls or bonds, the spheres above their wall or bond bound (a pair or bond with no lowered
// member satisfied the rule before and still does).
void Simulation::equalise_levels(int tz) {
  if (!contacts_) return;
  const auto& pi = contacts_->pair_i();
  const auto& pj = contacts_->pair_j();
  const auto& ri = contacts_->row_i();
  const auto& rj = contacts_->row_j();
  const auto& jp = contacts_->jpair();
  const bool walls = !contacts_->walls().empty();
  work_.clear();
  auto violated = [&](std::uint32_t p) {
    const std::uint32_t i = pi[p], j = pj[p];
    const int li = level_[i], lj = level_[j];
    const int t = std::min({li, lj, static_cast<int>(plev_[p])});
    return (t != li || t != lj) && near_pair(i, j);
  };
  auto enforce = [&](std::uint32_t p) {
    if (!violated(p)) return;
    const int t = std::min({static_cast<int>(level_[pi[p]]), static_cast<int>(level_[pj[p]]),
                            static_cast<int>(plev_[p])});
    lower_level(pi[p], t, tz, work_);
    lower_level(pj[p], t, tz, work_);
  };
  const std::size_t P = pi.size(), n = sp_.size();
  auto unsettled = [&](std::uint32_t p) {
    const int li = level_[pi[p]];
    return li != level_[pj[p]] || plev_[p] < li;
  };
  std::size_t nflag = 0;
  for (std::size_t i = 0; i < n; ++i) nflag += lflag_[i];
  // many changed levels (a body breaking up): one parallel scan of all pairs is cheaper
  if (!unsettled_valid_ || unsettled_version_ != contacts_->list_version() || 16 * nflag > n) {
    unsettled_.clear();
#pragma omp parallel if (P >= kOmpMin)
    {
      std::vector<std::uint32_t> mine;
#pragma omp for schedule(static) nowait
      for (std::size_t p = 0; p < P; ++p)
        if (unsettled(static_cast<std::uint32_t>(p))) mine.push_back(static_cast<std::uint32_t>(p));
#pragma omp critical(ssdem_level_unsettled)
      unsettled_.insert(unsettled_.end(), mine.begin(), mine.end());
    }
    std::sort(unsettled_.begin(), unsettled_.end());
    std::fill(lflag_.begin(), lflag_.end(), 0);
    unsettled_valid_ = true;
    unsettled_version_ = contacts_->list_version();
  } else if (nflag > 0) {  // (no level changed: the unsettled set is the same)
    fresh_.clear();
    for (std::uint32_t i = 0; i < n; ++i) {
      if (!lflag_[i]) continue;
      lflag_[i] = 0;
      for (std::uint32_t p = ri[i]; p < ri[i + 1]; ++p) fresh_.push_back(p);
      for (std::uint32_t q = rj[i]; q < rj[i + 1]; ++q) fresh_.push_back(jp[q]);
    }
    std::sort(fresh_.begin(), fresh_.end());
    cand_.clear();
    std::merge(unsettled_.begin(), unsettled_.end(), fresh_.begin(), fresh_.end(), std::back_inserter(cand_));
    cand_.erase(std::unique(cand_.begin(), cand_.end()), cand_.end());
    unsettled_.clear();
    for (std::uint32_t p : cand_)
      if (unsettled(p)) unsettled_.push_back(p);
  }
  seeds_.clear();
  const std::size_t U = unsettled_.size();
#pragma omp parallel if (U >= kOmpMin)
  {
    std::vector<std::uint32_t> mine;
#pragma omp for schedule(static) nowait
    for (std::size_t u = 0; u < U; ++u)
      if (violated(unsettled_[u])) mine.push_back(unsettled_[u]);
#pragma omp critical(ssdem_level_seeds)
    seeds_.insert(seeds_.end(), mine.begin(), mine.end());
  }
  std::sort(seeds_.begin(), seeds_.end());  // (the fixed point is order-free; this fixes the path)
  for (std::uint32_t p : seeds_) enforce(p);
  if (walls || bonds_) {
    lnew_.resize(n);
#pragma omp parallel for schedule(static) if (n >= kOmpMin)
    for (std::size_t k = 0; k < n; ++k) {
      const auto i = static_cast<std::uint32_t>(k);
      int t = level_[i];
      if (walls && t > 0) t = std::min(t, wall_level(i));
      if (bonds_ && t > 0) t = bond_bound(i, t);
      lnew_[k] = static_cast<std::uint8_t>(t);
    }
    for (std::uint32_t i = 0; i < n; ++i)
      if (lnew_[i] < level_[i]) lower_level(i, lnew_[i], tz, work_);
  }
  while (!work_.empty()) {
    const std::uint32_t k = work_.back();
    work_.pop_back();
    for (std::uint32_t p = ri[k]; p < ri[k + 1]; ++p) enforce(p);
    for (std::uint32_t q = rj[k]; q < rj[k + 1]; ++q) enforce(jp[q]);
    if (walls && level_[k] > 0) lower_level(k, wall_level(k), tz, work_);
    if (bonds_) enforce_bonds(k, tz);
  }
}

}  // namespace ssdem
