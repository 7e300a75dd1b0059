/// @file test_subset_cache.cpp
/// take_subset / keep_subset (level_rules.hpp): the pair subset of a multi-rate evaluation kept per
/// synchronisation level must equal a fresh multirate_subset whenever it is reused, and must be
/// rebuilt when the pair list, the active spheres or any active sphere's step changed. Checked on
/// a scripted sequence over a small pile against multirate_subset computed from scratch.
#include <gtest/gtest.h>

#include <vector>

#include "ssdem/contacts.hpp"
#include "ssdem/generators.hpp"
#include "ssdem/level_rules.hpp"

using namespace ssdem;

namespace {

struct Step {
  int tz;
  std::vector<std::uint32_t> active;
  std::vector<std::int64_t> topen;  // per sphere
  std::int64_t step;
  bool rebuild_list;
  bool expect_reuse;
};

}  // namespace

TEST(SubsetCache, ReusedOnlyForTheSameInputsAndEqualToAFreshSubset) {
  Spheres sp = lattice_pile(3.0, 1.0, 2000.0, 0.05, 3);
  const std::size_t n = sp.size();
  ContactSystem cs(gravel_preset(1e6), {}, 0.25);
  cs.update_neighbors(sp, true);
  ASSERT_GT(cs.pair_count(), n);
  const double h = 1e-3;
  std::vector<std::uint32_t> evens, all;
  for (std::uint32_t i = 0; i < n; ++i) {
    all.push_back(i);
    if (i % 2 == 0) evens.push_back(i);
  }
  std::vector<std::int64_t> t0(n, 96), t1(n, 96);
  t1[4] = 98;  // sphere 4 (active in both sets) promoted: a shorter step
  const std::vector<Step> script = {
      {2, evens, t0, 100, false, false},  // first: built
      {3, all, t0, 104, false, false},    // another tz: built
      {2, evens, t0, 100, false, true},   // same inputs as the first: reused
      {3, all, t0, 104, false, true},     // and the second
      {2, evens, t1, 100, false, false},  // sphere 4's step changed: rebuilt
      {2, evens, t1, 100, false, true},
      {2, all, t1, 100, false, false},    // other active spheres: rebuilt
      {2, all, t1, 100, true, false},     // the pair list rebuilt (new version): rebuilt
      {2, all, t1, 100, false, true},
  };
  SubsetCache cache;
  std::vector<std::size_t> off, off2;
  std::size_t reuses = 0;
  for (std::size_t k = 0; k < script.size(); ++k) {
    const Step& s = script[k];
    if (s.rebuild_list) cs.update_neighbors(sp, true);
    std::vector<std::uint8_t> sync(n, 0);
    for (std::uint32_t i : s.active) sync[i] = 1;
    ContactSystem::Subset got, fresh;
    take_subset(cache, s.tz, cs, s.active, sync, s.topen, s.step, h, off, got);
    multirate_subset(cs, s.active, sync, s.topen, s.step, h, off2, fresh);
    EXPECT_EQ(got.pairs, fresh.pairs) << "script step " << k;
    EXPECT_EQ(got.hpair, fresh.hpair) << "script step " << k;
    EXPECT_EQ(cache.reuses - reuses, s.expect_reuse ? 1u : 0u) << "script step " << k;
    reuses = cache.reuses;
    keep_subset(cache, s.tz, got);
  }
  // a subset taken and never given back (an evaluation that threw) is rebuilt, not reused
  std::vector<std::uint8_t> sync(n, 1);
  ContactSystem::Subset lost, again;
  take_subset(cache, 2, cs, all, sync, t1, 100, h, off, lost);
  const std::size_t builds = cache.builds;
  take_subset(cache, 2, cs, all, sync, t1, 100, h, off, again);
  EXPECT_EQ(cache.builds, builds + 1);
  EXPECT_EQ(again.pairs, lost.pairs);
}
