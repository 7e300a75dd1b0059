/// @file pair_grid.cpp
/// The contact list's cell grids (pair_grid.hpp): cell keys, insertion and removal of a sphere
/// (in the ordinary grid, or in the isolated spheres' grid when it holds a margin), the test for
/// isolation, the searches around the re-inserted spheres, and the neighbourhood of a point
/// (MPI movers).
#include <cmath>
#include <stdexcept>

#include "omp_team.hpp"
#include "pair_grid.hpp"

namespace ssdem {
using grid::cell_key;
using grid::kCellMax;
using grid::kNone;

std::uint64_t ContactSystem::cell_of(const Vec3& x, double edge) const {
  // floor(x / c) offset by 2^20 and clamped to 21 bits per axis (monotone, so spheres within one
  // cell edge of each other still land in the same or adjacent cells; NaN goes to cell 0).
  auto q = [&](double v) -> std::int64_t {
    const double f = std::floor(v / edge) + static_cast<double>(std::int64_t{1} << 20);
    if (!(f > 0.0)) return 0;
    if (f >= static_cast<double>(kCellMax)) return kCellMax;
    return static_cast<std::int64_t>(f);
  };
  return cell_key(q(x.x()), q(x.y()), q(x.z()));
}

void ContactSystem::link(std::uint32_t i) {
  const bool f = fast_[i] != 0;
  const std::uint64_t k = cell_of(xref_[i], f ? fcell_ : cell_);
  ckey_[i] = k;
  std::uint32_t& head = (f ? fhead_ : head_).get_or_insert(k, kNone);
  next_[i] = head;
  prev_[i] = kNone;
  if (head != kNone) prev_[head] = i;
  head = i;
  fhead_count_ += f;
}

void ContactSystem::unlink(std::uint32_t i) {
  CellTable& t = fast_[i] ? fhead_ : head_;
  if (prev_[i] != kNone) {
    next_[prev_[i]] = next_[i];
  } else {
    if (next_[i] == kNone)
      t.erase(ckey_[i]);
    else
      *t.find(ckey_[i]) = next_[i];
  }
  if (next_[i] != kNone) prev_[next_[i]] = prev_[i];
  next_[i] = prev_[i] = kNone;
  fhead_count_ -= fast_[i];
}

bool ContactSystem::isolated(const Spheres& sp, std::uint32_t i) const {
  bool found = false;
  visit_near(sp, i, margin_, [&](std::uint32_t) { return found = true; });
  return !found;
}

// The searches read the grids only, so they run first and on a team (in any order: the keys are
// sorted by the caller); the margins are then given in ascending order as one loop of search and
// margin per sphere would: a sphere with a pair within reach is not isolated; one that takes the
// margin has no partner within s_i + s_j + k + M, so it is not found by the others' searches
// either way; and a margin only widens its holder's reach, so a sphere that was not isolated
// before the margins of this call is not isolated after them, and one that was is tested again
// only if an earlier sphere of the call took a margin. Same pairs and margins with any thread
// count.
void ContactSystem::search_moved(const Spheres& sp, std::vector<std::uint64_t>& nk) {
  const std::size_t m = moved_.size();
  iso_.assign(m, 0);
  auto search = [&](std::size_t r, std::vector<std::uint64_t>& out) {
    const std::uint32_t i = moved_[r];
    const std::size_t before = out.size();
    for_each_near(sp, i, [&](std::uint32_t j) { out.push_back(grid::pair_key(i, j)); });
    if (margins_on_ && out.size() == before && isolated(sp, i)) iso_[r] = 1;
  };
  // A search reads 27-152 cells of tables and positions at scattered places: 1.5-3 us on the
  // 2.42 km 375 m row, as much as a few hundred of the items of TeamThresholds::items. The
  // isolation tests (125 more cells) cluster where the lone spheres lie in memory, so the
  // searches are handed out in small chunks rather than in blocks.
  constexpr std::size_t kItemsPerSearch = 256;
  if (use_team(kItemsPerSearch * m)) {
    nk_part_.resize(static_cast<std::size_t>(omp_get_max_threads()));
#pragma omp parallel
    {
      std::vector<std::uint64_t>& out = nk_part_[static_cast<std::size_t>(omp_get_thread_num())].keys;
      out.clear();
#pragma omp for schedule(dynamic, 4) nowait
      for (std::size_t r = 0; r < m; ++r) search(r, out);
    }
    for (auto& part : nk_part_) {
      nk.insert(nk.end(), part.keys.begin(), part.keys.end());
      part.keys.clear();
    }
  } else {
    for (std::size_t r = 0; r < m; ++r) search(r, nk);
  }
  bool margins_given = false;
  for (std::size_t r = 0; r < m; ++r) {
    const std::uint32_t i = moved_[r];
    if (!iso_[r] || (margins_given && !isolated(sp, i))) continue;
    unlink(i);
    fast_[i] = 1;
    link(i);
    ++promotions_;
    margins_given = true;
  }
}

void ContactSystem::near_point(const Vec3& x, std::vector<std::uint32_t>& out) const {
  if (fhead_count_ > 0)
    throw std::logic_error("ContactSystem::near_point: isolated spheres hold margins (set_margins(false) first)");
  std::uint64_t keys[27];
  const int nk = grid::ring_keys(head_, cell_of(x, cell_), 1, keys, 0);
  for (int q = 0; q < nk; ++q) {
    const std::uint32_t* head = head_.find(keys[q]);
    if (!head) continue;
    for (std::uint32_t j = *head; j != kNone; j = next_[j]) out.push_back(j);
  }
}

}  // namespace ssdem
