/// @file fof.cpp
/// Implementation of analysis/fof.hpp; the governing equations, sources and deviations are documented there.
#include "analysis/fof.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <numeric>
#include <stdexcept>

namespace analysis {

std::size_t FofResult::singles() const {
  return static_cast<std::size_t>(std::count(clump_count.begin(), clump_count.end(), 1));
}

double default_link_length(const double* radius, std::size_t n, double fraction) {
  if (n == 0) return 0.0;
  std::vector<double> r(radius, radius + n);
  const std::size_t mid = n / 2;
  std::nth_element(r.begin(), r.begin() + static_cast<std::ptrdiff_t>(mid), r.end());
  double med = r[mid];
  if (n % 2 == 0) {
    const double lower = *std::max_element(r.begin(), r.begin() + static_cast<std::ptrdiff_t>(mid));
    med = 0.5 * (med + lower);
  }
  return fraction * med;
}

namespace {

struct CellKey {
  std::int64_t x, y, z;
  bool operator<(const CellKey& o) const {
    if (x != o.x) return x < o.x;
    if (y != o.y) return y < o.y;
    return z < o.z;
  }
  bool operator==(const CellKey& o) const { return x == o.x && y == o.y && z == o.z; }
};

/// Lock-free union–find; the root of a set is always its smallest element.
class ConcurrentUnionFind {
 public:
  explicit ConcurrentUnionFind(std::size_t n) : parent_(n) {
    for (std::size_t i = 0; i < n; ++i) parent_[i].store(static_cast<std::int64_t>(i), std::memory_order_relaxed);
  }
  std::int64_t find(std::int64_t x) {
    while (true) {
      std::int64_t p = parent_[x].load(std::memory_order_acquire);
      if (p == x) return x;
      const std::int64_t gp = parent_[p].load(std::memory_order_acquire);
      if (gp != p) {
        // Path halving: x -> gp is still a pointer to an ancestor (never breaks the invariant).
        parent_[x].compare_exchange_weak(p, gp, std::memory_order_acq_rel);
      }
      x = gp;
    }
  }
  void unite(std::int64_t a, std::int64_t b) {
    while (true) {
      std::int64_t ra = find(a), rb = find(b);
      if (ra == rb) return;
      if (ra < rb) std::swap(ra, rb);  // link the larger root under the smaller
      std::int64_t expected = ra;
      if (parent_[ra].compare_exchange_strong(expected, rb, std::memory_order_acq_rel)) return;
    }
  }

 private:
  std::vector<std::atomic<std::int64_t>> parent_;
};

}  // namespace

FofResult friends_of_friends(const double* position, const double* radius, const double* mass,
                             std::size_t n, double eps) {
  FofResult out;
  if (n == 0) return out;
  double rmax = 0.0;
  double lo[3] = {position[0], position[1], position[2]};
  for (std::size_t i = 0; i < n; ++i) {
    rmax = std::max(rmax, radius[i]);
    for (int d = 0; d < 3; ++d) lo[d] = std::min(lo[d], position[3 * i + d]);
  }
  const double reach = 2.0 * rmax + eps;  // largest centre distance that can link
  const std::int64_t ni = static_cast<std::int64_t>(n);

  ConcurrentUnionFind uf(n);
  if (reach > 0.0) {
    const double h = reach;
    std::vector<std::pair<CellKey, std::int64_t>> keyed(n);
#pragma omp parallel for schedule(static)
    for (std::int64_t i = 0; i < ni; ++i) {
      const double* x = position + 3 * i;
      keyed[i] = {CellKey{static_cast<std::int64_t>(std::floor((x[0] - lo[0]) / h)),
                          static_cast<std::int64_t>(std::floor((x[1] - lo[1]) / h)),
                          static_cast<std::int64_t>(std::floor((x[2] - lo[2]) / h))},
                  i};
    }
    std::sort(keyed.begin(), keyed.end(), [](const auto& a, const auto& b) {
      if (a.first == b.first) return a.second < b.second;
      return a.first < b.first;
    });
    // Unique cells and their ranges in `keyed`.
    std::vector<CellKey> cells;
    std::vector<std::int64_t> start;
    for (std::size_t k = 0; k < n; ++k) {
      if (k == 0 || !(keyed[k].first == keyed[k - 1].first)) {
        cells.push_back(keyed[k].first);
        start.push_back(static_cast<std::int64_t>(k));
      }
    }
    start.push_back(ni);
    const std::int64_t nc = static_cast<std::int64_t>(cells.size());
    // Sphere data in cell order for locality.
    std::vector<double> xs(3 * n), rs(n);
    std::vector<std::int64_t> ids(n);
#pragma omp parallel for schedule(static)
    for (std::int64_t k = 0; k < ni; ++k) {
      const std::int64_t i = keyed[k].second;
      ids[k] = i;
      rs[k] = radius[i];
      for (int d = 0; d < 3; ++d) xs[3 * k + d] = position[3 * i + d];
    }
    auto linked = [&](std::int64_t a, std::int64_t b) {
      const double dx = xs[3 * a] - xs[3 * b], dy = xs[3 * a + 1] - xs[3 * b + 1], dz = xs[3 * a + 2] - xs[3 * b + 2];
      const double lim = rs[a] + rs[b] + eps;
      return lim > 0.0 && dx * dx + dy * dy + dz * dz < lim * lim;
    };
    // The 13 forward neighbour cells (lexicographically larger keys) lie in 4 columns (dx, dy) =
    // (0,1), (1,-1), (1,0), (1,1) with dz = -1..1, each contiguous in the sorted cell array, plus
    // (0,0,+1), which if occupied is the next cell. One binary search per column.
    static const int cols[4][2] = {{0, 1}, {1, -1}, {1, 0}, {1, 1}};
    auto pair_cells = [&](std::int64_t c, std::int64_t d) {
      for (std::int64_t a = start[c]; a < start[c + 1]; ++a)
        for (std::int64_t b = start[d]; b < start[d + 1]; ++b)
          if (linked(a, b)) uf.unite(ids[a], ids[b]);
    };
#pragma omp parallel for schedule(dynamic, 256)
    for (std::int64_t c = 0; c < nc; ++c) {
      const std::int64_t b0 = start[c], b1 = start[c + 1];
      for (std::int64_t a = b0; a < b1; ++a)
        for (std::int64_t b = a + 1; b < b1; ++b)
          if (linked(a, b)) uf.unite(ids[a], ids[b]);
      const CellKey& k = cells[c];
      if (c + 1 < nc && cells[c + 1] == CellKey{k.x, k.y, k.z + 1}) pair_cells(c, c + 1);
      for (const auto& o : cols) {
        const CellKey lo{k.x + o[0], k.y + o[1], k.z - 1};
        auto it = std::lower_bound(cells.begin(), cells.end(), lo);
        for (; it != cells.end() && it->x == lo.x && it->y == lo.y && it->z <= k.z + 1; ++it)
          pair_cells(c, it - cells.begin());
      }
    }
  }

  // Roots are component minima: deterministic. Accumulate clump masses in index order.
  std::vector<std::int64_t> root(n);
#pragma omp parallel for schedule(static)
  for (std::int64_t i = 0; i < ni; ++i) root[i] = uf.find(i);
  std::vector<std::int64_t> slot(n, -1);
  std::vector<double> cmass;
  std::vector<std::int64_t> ccount, cfirst;
  for (std::size_t i = 0; i < n; ++i) {
    const std::int64_t r = root[i];
    if (slot[r] < 0) {
      slot[r] = static_cast<std::int64_t>(cmass.size());
      cmass.push_back(0.0);
      ccount.push_back(0);
      cfirst.push_back(static_cast<std::int64_t>(i));
    }
    cmass[slot[r]] += mass[i];
    ccount[slot[r]] += 1;
  }
  const std::size_t m = cmass.size();
  std::vector<std::int64_t> order(m);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](std::int64_t a, std::int64_t b) {
    if (cmass[a] != cmass[b]) return cmass[a] > cmass[b];
    return cfirst[a] < cfirst[b];
  });
  std::vector<std::int64_t> rank(m);
  for (std::size_t k = 0; k < m; ++k) rank[order[k]] = static_cast<std::int64_t>(k);
  out.clump_mass.resize(m);
  out.clump_count.resize(m);
  out.clump_first.resize(m);
  for (std::size_t k = 0; k < m; ++k) {
    out.clump_mass[k] = cmass[order[k]];
    out.clump_count[k] = ccount[order[k]];
    out.clump_first[k] = cfirst[order[k]];
  }
  out.clump_of.resize(n);
#pragma omp parallel for schedule(static)
  for (std::int64_t i = 0; i < ni; ++i) out.clump_of[i] = rank[slot[root[i]]];
  return out;
}

}  // namespace analysis
