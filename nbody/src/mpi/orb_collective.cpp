/// @file orb_collective.cpp
/// OrbTree::collective (orb.hpp): the orthogonal recursive bisection built level by level from
/// each rank's own positions, the same cuts as OrbTree(x of all spheres, P).
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

#include "ordered_bits.hpp"
#include "ssdem/mpi/orb.hpp"

namespace ssdem::mpi {
OrbTree OrbTree::collective(Comm& comm, const std::vector<Vec3>& x) {
  OrbTree t;
  const int P = comm.size;
  t.nodes_.push_back(Node{});
  struct Active {
    int node, r0, r1;
  };
  std::vector<Active> level;
  if (P > 1) level.push_back(Active{0, 0, P});
  std::vector<int> at(x.size(), P > 1 ? 0 : -1);  // index into `level` of each own sphere's node
  const double inf = std::numeric_limits<double>::infinity();
  while (!level.empty()) {
    const std::size_t m = level.size();
    // bounding boxes (max of -lo, hi) and counts
    std::vector<double> box(6 * m, -inf);
    std::vector<long long> cnt(m, 0);
    for (std::size_t i = 0; i < x.size(); ++i) {
      if (at[i] < 0) continue;
      double* b = &box[6 * static_cast<std::size_t>(at[i])];
      for (int k = 0; k < 3; ++k) {
        b[k] = std::max(b[k], -x[i][k]);
        b[3 + k] = std::max(b[3 + k], x[i][k]);
      }
      ++cnt[at[i]];
    }
    comm.max(box.data(), static_cast<int>(box.size()));
    comm.sum(cnt.data(), static_cast<int>(m));
    std::vector<int> axis(m, 0);
    std::vector<long long> want(m, 0);
    std::vector<std::uint64_t> klo(m, 0), khi(m, 0);
    for (std::size_t j = 0; j < m; ++j) {
      const int nr = level[j].r1 - level[j].r0, nl = nr / 2;
      if (cnt[j] == 0) continue;
      const Vec3 lo(-box[6 * j], -box[6 * j + 1], -box[6 * j + 2]), hi(box[6 * j + 3], box[6 * j + 4], box[6 * j + 5]);
      (hi - lo).maxCoeff(&axis[j]);
      want[j] = std::llround(static_cast<double>(cnt[j]) * nl / static_cast<double>(nr));
      klo[j] = key_of(lo[axis[j]]);
      khi[j] = key_of(hi[axis[j]]);
    }
    // the want-th smallest coordinate (0-based): the least key K with #(key <= K) > want
    std::vector<long long> c(m);
    for (;;) {
      bool open = false;
      std::vector<std::uint64_t> mid(m);
      for (std::size_t j = 0; j < m; ++j) {
        mid[j] = klo[j] + (khi[j] - klo[j]) / 2;
        open = open || (cnt[j] > 0 && want[j] < cnt[j] && klo[j] < khi[j]);
      }
      if (!open) break;  // the same on every rank: the bounds are
      std::fill(c.begin(), c.end(), 0);
      for (std::size_t i = 0; i < x.size(); ++i)
        if (at[i] >= 0 && key_of(x[i][axis[at[i]]]) <= mid[at[i]]) ++c[at[i]];
      comm.sum(c.data(), static_cast<int>(m));
      for (std::size_t j = 0; j < m; ++j) {
        if (klo[j] >= khi[j]) continue;
        if (c[j] > want[j])
          khi[j] = mid[j];
        else
          klo[j] = mid[j] + 1;
      }
    }
    // below the split value: count and largest coordinate
    std::vector<long long> below(m, 0);
    std::vector<double> lower(m, -inf);
    for (std::size_t i = 0; i < x.size(); ++i) {
      if (at[i] < 0) continue;
      const int j = at[i];
      const double v = x[i][axis[j]];
      if (want[j] < cnt[j] && v < value_of(klo[j])) {
        ++below[j];
        lower[j] = std::max(lower[j], v);
      }
    }
    comm.sum(below.data(), static_cast<int>(m));
    comm.max(lower.data(), static_cast<int>(m));
    std::vector<Active> next;
    std::vector<int> child_lo(m, -1), child_hi(m, -1);
    for (std::size_t j = 0; j < m; ++j) {
      const Active a = level[j];
      const int nl = (a.r1 - a.r0) / 2;
      double cut = 0.0;
      if (cnt[j] > 0) {
        if (want[j] >= cnt[j]) {
          cut = std::nextafter(box[6 * j + 3 + axis[j]], INFINITY);
        } else {
          const double up = value_of(klo[j]);
          cut = below[j] > 0 ? 0.5 * (lower[j] + up) : up;
          if (!(cut > (below[j] > 0 ? lower[j] : -INFINITY))) cut = up;
        }
      }
      t.nodes_[a.node].axis = axis[j];
      t.nodes_[a.node].cut = cut;
      const int lo = static_cast<int>(t.nodes_.size());
      t.nodes_.push_back(Node{});
      t.nodes_.back().rank = a.r0;
      const int hi = static_cast<int>(t.nodes_.size());
      t.nodes_.push_back(Node{});
      t.nodes_.back().rank = a.r0 + nl;
      t.nodes_[a.node].lo = lo;
      t.nodes_[a.node].hi = hi;
      if (nl > 1) {
        child_lo[j] = static_cast<int>(next.size());
        next.push_back(Active{lo, a.r0, a.r0 + nl});
      }
      if (a.r1 - a.r0 - nl > 1) {
        child_hi[j] = static_cast<int>(next.size());
        next.push_back(Active{hi, a.r0 + nl, a.r1});
      }
    }
    for (std::size_t i = 0; i < x.size(); ++i) {
      if (at[i] < 0) continue;
      const int j = at[i];
      const Node& nd = t.nodes_[level[j].node];
      at[i] = x[i][nd.axis] < nd.cut ? child_lo[j] : child_hi[j];
    }
    level.swap(next);
  }
  return t;
}

std::vector<std::pair<int, double>> OrbTree::cuts() const {
  std::vector<std::pair<int, double>> out;
  if (nodes_.empty()) return out;
  std::vector<int> stack{0};
  while (!stack.empty()) {
    const int k = stack.back();
    stack.pop_back();
    if (nodes_[k].lo < 0) continue;
    out.emplace_back(nodes_[k].axis, nodes_[k].cut);
    stack.push_back(nodes_[k].hi);
    stack.push_back(nodes_[k].lo);
  }
  return out;
}

}  // namespace ssdem::mpi
