/// @file pair_grid.cpp
/// The contact list's cell grids (pair_grid.hpp): cell keys, insertion and removal of a sphere
/// (in the ordinary grid, or in the isolated spheres' grid when it holds a margin), the test for
/// isolation, and the neighbourhood of a point (MPI movers).
#include <cmath>
#include <stdexcept>

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
