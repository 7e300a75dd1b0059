/// @file level_rules.hpp
/// The multi-rate level rules of multirate.hpp as one component, shared by the one-rank
/// integrator (Simulation) and the domain-decomposed one (mpi::DomainSim):
///   l_c(i, j) = max(0, floor(log2(tau_c(mu, R) / (N h))))          (each listed pair, cached)
///   new level at a sync (s+1):  l_i = min(L, tz(s+1), l_c of near pairs / walls / bonds)
///   equalisation: every near pair (and intact bond) on min(l_i, l_j, l_c), to the fixed point;
///     a sphere lowered while not synchronised is promoted to min(target, tz) (multirate.hpp).
/// The equalisation is monotone (levels only drop), so every order of applying it that stops at
/// a fixed point stops at the same one, the largest fixed point below the starting levels: a
/// domain decomposition reaches it by alternating local equalisations with halo updates of the
/// ghosts' levels (ghost := min(local, owner's), lower()) until no rank changes a ghost.
/// The component holds the per-sphere level arrays (level, sync, promoted, lflag) of the local
/// set and the caches (each listed pair's l_c, the unsettled pairs); the spheres and the pair list
/// are passed in, so after the local set or the list is rebuilt the caches follow by
/// list_version() or invalidate().
#pragma once
#include <cstdint>
#include <vector>

#include "ssdem/contacts.hpp"
#include "ssdem/multirate.hpp"
#include "ssdem/spheres.hpp"

namespace ssdem {

class LevelRules {
 public:
  /// The bond terms of the rules (multirate_bonds.cpp); absent without bonds.
  struct BondTerms {
    virtual ~BondTerms() = default;
    /// min(c, l_b of sphere i's intact bonds)
    virtual int cap(std::uint32_t i, int c) const = 0;
    /// min(t, min over i's intact bonds of min(l_partner, l_b)): the Jacobi bound
    virtual int bound(std::uint32_t i, int t) const = 0;
    /// worklist step over i's intact bonds: both ends to min(l_a, l_b, l_bond) (calls lower())
    virtual void enforce(std::uint32_t i, int tz, LevelRules& r) = 0;
  };

  /// Sizes the arrays for n spheres (levels from `levels` if it has n entries, else 0) and
  /// forgets the caches.
  void reset(std::size_t n, const std::vector<std::uint8_t>* levels = nullptr);
  void configure(const PairClock& clock, double near_gap) {
    clock_ = clock;
    near_gap_ = near_gap;
  }
  /// The caches (pair levels, unsettled pairs) no longer match the pair list.
  void invalidate() {
    plev_version_ = UINT64_MAX;
    unsettled_valid_ = false;
  }
  const PairClock& clock() const { return clock_; }

  /// At the opening of a gravity block of 2^L base steps: levels above L become L.
  void cap(int L);
  /// l_c of every listed pair (recomputed only when the list changed).
  void update_pair_levels(const Spheres& sp, const ContactSystem& cs);
  /// Start of a level decision at base substep s (tz = trailing level of s+1): sync = level <= tz,
  /// promoted = 0; and the new levels of the synchronised spheres (only where mask[i] != 0 when a
  /// mask is given). Call update_pair_levels first.
  void assign(const Spheres& sp, const ContactSystem* cs, int tz, int L, const BondTerms* bonds,
              const std::uint8_t* mask = nullptr);
  /// The spheres synchronised now, ascending: those of assign() and those promoted since.
  void active(std::vector<std::uint32_t>& out);
  /// Lower sphere i to `target` (promoted to min(target, tz) if not synchronised); true if lowered.
  bool lower(std::uint32_t i, int target, int tz);
  /// Equalise near pairs (and bonds) to the fixed point, seeded by the spheres flagged in lflag.
  void equalise(const Spheres& sp, const ContactSystem& cs, int tz, BondTerms* bonds);

  bool near_pair(const Spheres& sp, std::uint32_t i, std::uint32_t j) const {
    const double r = sp.s[i] + sp.s[j] + near_gap_;
    return (sp.x[j] - sp.x[i]).squaredNorm() < r * r;
  }
  int pair_level(const Spheres& sp, std::uint32_t i, std::uint32_t j) const;
  /// level of i's nearest-wall constraint (255: no wall near)
  int wall_level(const Spheres& sp, const ContactSystem& cs, std::uint32_t i) const;

  std::vector<std::uint8_t> level, sync, promoted;
  /// Level changed since the last equalisation; right after equalise(), exactly the spheres it
  /// lowered (it consumes the flags it starts from).
  std::vector<std::uint8_t> lflag;
  std::int64_t promotions = 0;      ///< promotions in the middle of a step (lower())

 private:
  std::vector<std::uint8_t> plev_;  ///< l_c of each listed pair (masses and radii are constant)
  std::vector<std::uint8_t> pmin_;  ///< per sphere the lowest plev_ of its listed pairs (255: none)
  std::uint64_t plev_version_ = UINT64_MAX;
  std::vector<std::uint8_t> lnew_;
  std::vector<std::uint32_t> work_, seeds_;
  std::vector<std::uint32_t> synced_, promo_;  ///< synchronised by assign(); promoted since (lower())
  std::vector<std::vector<std::uint32_t>> synced_by_thread_;
  /// per tz how many spheres assign() synchronised at its last call with that tz: whether the
  /// next call's pass over them gets a team (omp_team.hpp)
  std::size_t synced_at_tz_[kMaxLevel + 1] = {};
  /// per tz how unevenly the threads' blocks held those spheres at that call (whether the next
  /// call shares them by count: level_rules.cpp)
  std::size_t synced_skew_[kMaxLevel + 1] = {};
  std::vector<std::uint32_t> unsettled_, cand_, fresh_;  ///< pairs not on one level <= their l_c (ascending)
  std::uint64_t unsettled_version_ = 0;
  bool unsettled_valid_ = false;
  PairClock clock_;
  double near_gap_ = 0.0;
};

/// The pairs a multi-rate force evaluation computes: every listed pair with an active member,
/// in the order of the active spheres (a sphere's pairs as i, then as j where i is not
/// synchronised), each with the step of its synchronised member(s): min over them of
/// (step - topen) h. `off` is scratch. Pairs in contact have both members active (near pairs
/// share a level); a pair with one active member is evaluated so that a contact flag left from
/// its last evaluation is reset, never gathered stale.
void multirate_subset(const ContactSystem& cs, const std::vector<std::uint32_t>& active,
                      const std::vector<std::uint8_t>& sync, const std::vector<std::int64_t>& topen,
                      std::int64_t step, double h, std::vector<std::size_t>& off, ContactSystem::Subset& sub);

/// The pairs and steps of multirate_subset kept per synchronisation level tz (the coarsest level
/// synchronised at a base step), with the inputs they were built from: the pair list's version,
/// the active spheres (= the synchronised ones) and their steps step - topen, of which they are a
/// function. A remnant at rest repeats the inputs of a tz at every step with that tz (steps with
/// tz = 2, 3, 4, ... alternate, so one kept subset would never be reused).
struct SubsetCache {
  struct Entry {
    std::uint64_t version = ~std::uint64_t{0};
    std::vector<std::uint32_t> active;
    std::vector<std::int64_t> steps;
    std::vector<std::uint32_t> pairs;
    std::vector<double> hpair;
    std::vector<std::uint8_t> whole;
    bool lent = false;  ///< pairs/hpair are in the caller's subset (take_subset without keep_subset yet)
  };
  std::vector<Entry> by_tz;
  std::size_t reuses = 0, builds = 0;
};
/// Puts into sub.pairs / sub.hpair the subset of multirate_subset for a step synchronising levels
/// <= tz: the one kept for tz if it was built from the same inputs, else built anew (results are
/// identical either way). Give it back with keep_subset after the evaluation.
void take_subset(SubsetCache& c, int tz, const ContactSystem& cs, const std::vector<std::uint32_t>& active,
                 const std::vector<std::uint8_t>& sync, const std::vector<std::int64_t>& topen, std::int64_t step,
                 double h, std::vector<std::size_t>& off, ContactSystem::Subset& sub);
void keep_subset(SubsetCache& c, int tz, ContactSystem::Subset& sub);

class BondSystem;

/// The bond terms of the level rules (multirate.hpp, "Bonds"; multirate_bonds.cpp) over the bonds
/// of `b` and the spheres of `lr`: the level l_b of every bond and, per sphere, its intact bonds.
/// Simulation holds one over all the bonds, an MPI rank (mpi/domain_sim.hpp) one over the bonds
/// it holds (those with an own end). Both references must outlive it.
class BondLevels final : public LevelRules::BondTerms {
 public:
  BondLevels(const BondSystem& b, const Spheres& sp, LevelRules& lr);
  /// Rebuild the index of intact bonds if a bond broke since it was built (broken bonds leave
  /// the rules at the next level decision).
  void refresh();
  int cap(std::uint32_t i, int c) const override;
  int bound(std::uint32_t i, int t) const override;
  void enforce(std::uint32_t i, int tz, LevelRules& r) override;
  const std::vector<std::uint8_t>& levels() const { return blevel_; }
  /// Bytes held (levels and index).
  double bytes() const {
    return static_cast<double>(blevel_.size() + 4 * (brow_.size() + badj_.size() + bfill_.size()));
  }

 private:
  void index();
  const BondSystem& b_;
  LevelRules& lr_;
  std::vector<std::uint8_t> blevel_;                ///< level l_b of each bond
  std::vector<std::uint32_t> brow_, badj_, bfill_;  ///< CSR: the intact bonds of each sphere (ascending)
  std::size_t seen_ = 0;                            ///< BondSystem::breaks() when the CSR was built
};

}  // namespace ssdem
