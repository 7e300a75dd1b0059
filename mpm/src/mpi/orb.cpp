/// @file orb.cpp
/// Orthogonal recursive bisection of the background grid (mpm/mpi/orb.hpp for the rule): the
/// tree of cuts from weight histograms level by level, the owner of a cell, the boxes ranks own
/// and hold, and the tree's file form.
#include "mpm/mpi/orb.hpp"

#include <algorithm>
#include <cstdio>
#include <string>

#include "common/status.hpp"

namespace mpmfrag::mpi {

long long Box::size() const {
  if (empty()) return 0;
  return static_cast<long long>(hi[0] - lo[0]) * (hi[1] - lo[1]) * (hi[2] - lo[2]);
}

int nearest_cut(const std::vector<long long>& w, long long num, long long den, int lo, int hi) {
  const int n = static_cast<int>(w.size());
  __int128 total = 0;
  for (long long v : w) total += v;
  const __int128 target = total * num;  // compare den * S(P) with total * num: exact
  __int128 cum = 0;
  int c = 0;
  while (c < n && cum * den < target) cum += w[c++];
  int pick = c;
  if (c > 0) {
    const __int128 over = cum * den - target, under = target - (cum - w[c - 1]) * den;
    if (under < over) pick = c - 1;
  }
  return std::clamp(pick, lo, hi);
}

int Orb::owner(const Eigen::Vector3i& c) const {
  std::size_t k = 0;
  int r0 = 0, n = nranks;
  while (n > 1) {
    const Split& s = split[k];
    if (c[s.axis] < s.cut) {
      k += 1;
      n = s.left;
    } else {
      k += static_cast<std::size_t>(s.left);  // past the node and its lower subtree's left - 1 splits
      r0 += s.left;
      n -= s.left;
    }
  }
  return r0;
}

Box Orb::held(int r) const {
  Box b = own_[static_cast<std::size_t>(r)];
  for (int d = 0; d < 3; ++d) {
    b.lo[d] = std::max(0, b.lo[d] - halo);
    b.hi[d] = std::min(shape[d], b.hi[d] + halo);
  }
  return b;
}

bool Orb::set(std::vector<Split> s) {
  const int n = static_cast<int>(s.size()) + 1;
  std::vector<Box> own(static_cast<std::size_t>(n), Box{});
  std::size_t k = 0;
  bool ok = true;
  // preorder walk with an explicit stack of (box, first rank, ranks)
  struct Item {
    Box box;
    int r0, n;
  };
  std::vector<Item> stack{{Box{Eigen::Vector3i::Zero(), shape}, 0, n}};
  while (ok && !stack.empty()) {
    const Item it = stack.back();
    stack.pop_back();
    if (it.n == 1) {
      own[static_cast<std::size_t>(it.r0)] = it.box;
      continue;
    }
    if (k >= s.size()) {
      ok = false;
      break;
    }
    const Split& sp = s[k++];
    if (sp.axis < 0 || sp.axis > 2 || sp.left < 1 || sp.left >= it.n || sp.cut - it.box.lo[sp.axis] < min_width ||
        it.box.hi[sp.axis] - sp.cut < min_width) {
      ok = false;
      break;
    }
    Box lower = it.box, upper = it.box;
    lower.hi[sp.axis] = sp.cut;
    upper.lo[sp.axis] = sp.cut;
    stack.push_back({upper, it.r0 + sp.left, it.n - sp.left});  // popped after the lower subtree
    stack.push_back({lower, it.r0, sp.left});
  }
  if (!ok || k != s.size()) return false;  // the tree as it was
  split = std::move(s);
  nranks = n;
  own_ = std::move(own);
  return true;
}

std::vector<std::int64_t> Orb::flat() const {
  std::vector<std::int64_t> v;
  for (const Split& s : split) v.insert(v.end(), {s.axis, s.cut, s.left});
  return v;
}

std::vector<Orb::Split> Orb::unflat(const std::vector<std::int64_t>& v) {
  std::vector<Split> s;
  for (std::size_t k = 0; k + 2 < v.size(); k += 3)
    s.push_back({static_cast<int>(v[k]), static_cast<int>(v[k + 1]), static_cast<int>(v[k + 2])});
  return s;
}

std::vector<Orb::Split> Orb::slabs(int axis, const std::vector<int>& cut) {
  std::vector<Split> s;  // a chain: each node gives its first rank the lowest slab
  for (std::size_t r = 1; r + 1 < cut.size(); ++r) s.push_back({axis, cut[r], 1});
  return s;
}

std::string Orb::describe() const {
  long long mx = 0, sum = 0;
  for (const Box& b : own_) {
    mx = std::max(mx, b.size());
    sum += b.size();
  }
  std::string out = std::to_string(nranks) + (nranks == 1 ? " box" : " boxes");
  if (nranks <= 4) {
    out += ':';
    for (const Box& b : own_) {
      char buf[96];
      std::snprintf(buf, sizeof buf, " [%d,%d)x[%d,%d)x[%d,%d)", b.lo[0], b.hi[0], b.lo[1], b.hi[1], b.lo[2], b.hi[2]);
      out += buf;
    }
  } else {
    char buf[96];
    std::snprintf(buf, sizeof buf, ", largest %.3g x the mean cells", sum > 0 ? static_cast<double>(mx) * nranks / sum : 0.0);
    out += buf;
  }
  return out;
}

Orb orb_cuts(const Eigen::Vector3i& shape, int ranks, int halo, int min_width, const OrbHistogram& hist) {
  struct Node {
    Box box;
    int r0, n;
    Orb::Split s;
    int lower = -1, upper = -1, request = -1;
  };
  std::vector<Node> nodes{{Box{Eigen::Vector3i::Zero(), shape}, 0, ranks, {}}};
  std::vector<int> level{0};
  // the request index of the unsplit node holding cell c at this level, or -1
  const auto locate = [&nodes](const Eigen::Vector3i& c) {
    int k = 0;
    while (nodes[static_cast<std::size_t>(k)].lower >= 0) {
      const Node& nd = nodes[static_cast<std::size_t>(k)];
      k = c[nd.s.axis] < nd.s.cut ? nd.lower : nd.upper;
    }
    return nodes[static_cast<std::size_t>(k)].request;
  };
  while (!level.empty()) {
    std::vector<OrbRequest> req;
    std::vector<int> which;
    for (const int k : level) {
      Node& nd = nodes[static_cast<std::size_t>(k)];
      if (nd.n < 2) continue;
      int a = 0;
      const Eigen::Vector3i wdt = nd.box.hi - nd.box.lo;
      for (int d = 1; d < 3; ++d)
        if (wdt[d] > wdt[a]) a = d;
      if (wdt[a] < 2 * min_width)
        throw common::InputError("the grid of " + std::to_string(shape[0]) + " x " + std::to_string(shape[1]) + " x " +
                                 std::to_string(shape[2]) + " nodes cannot give " + std::to_string(ranks) +
                                 " MPI ranks boxes of at least " + std::to_string(min_width) +
                                 " planes along their cuts; use fewer ranks or a finer [grid] cell_size");
      nd.s.axis = a;
      nd.request = static_cast<int>(req.size());
      req.push_back({nd.box, a});
      which.push_back(k);
    }
    if (req.empty()) break;
    const std::vector<std::vector<long long>> h = hist(req, locate);
    std::vector<int> next;
    for (std::size_t q = 0; q < which.size(); ++q) {
      const int k = which[q];
      Node nd = nodes[static_cast<std::size_t>(k)];
      const int a = nd.s.axis, width = nd.box.hi[a] - nd.box.lo[a];
      const int left = nd.n / 2, right = nd.n - left;
      int lo = min_width * left, hi = width - min_width * right;  // roomy: width >= W n
      if (lo > hi) {
        // a narrower box: each side keeps W ceil(k / c) planes, c the boxes of W x W the other two
        // axes offer, so that a side of k ranks can still be cut into k boxes; else W planes
        const int b = (a + 1) % 3, d = (a + 2) % 3;
        const int cap = std::max(1, ((nd.box.hi[b] - nd.box.lo[b]) / min_width) * ((nd.box.hi[d] - nd.box.lo[d]) / min_width));
        lo = min_width * ((left + cap - 1) / cap);
        hi = width - min_width * ((right + cap - 1) / cap);
        if (lo > hi) {
          lo = min_width;
          hi = width - min_width;
        }
      }
      if (h[q].size() != static_cast<std::size_t>(width)) throw std::logic_error("orb_cuts: a histogram of the wrong size");
      nd.s.cut = nd.box.lo[a] + nearest_cut(h[q], left, nd.n, lo, hi);
      nd.s.left = left;
      Box lower = nd.box, upper = nd.box;
      lower.hi[a] = nd.s.cut;
      upper.lo[a] = nd.s.cut;
      nd.lower = static_cast<int>(nodes.size());
      nd.upper = nd.lower + 1;
      nd.request = -1;
      nodes[static_cast<std::size_t>(k)] = nd;
      nodes.push_back({lower, nd.r0, left, {}});
      nodes.push_back({upper, nd.r0 + left, right, {}});
      next.push_back(nd.lower);
      next.push_back(nd.upper);
    }
    for (const int k : level) nodes[static_cast<std::size_t>(k)].request = -1;
    level = std::move(next);
  }
  // the splits in preorder
  std::vector<Orb::Split> s;
  std::vector<int> stack{0};
  while (!stack.empty()) {
    const Node& nd = nodes[static_cast<std::size_t>(stack.back())];
    stack.pop_back();
    if (nd.lower < 0) continue;
    s.push_back(nd.s);
    stack.push_back(nd.upper);
    stack.push_back(nd.lower);
  }
  Orb orb;
  orb.shape = shape;
  orb.halo = halo;
  orb.min_width = min_width;
  if (!orb.set(std::move(s))) throw std::logic_error("orb_cuts: the tree it built is not a partition");
  return orb;
}

}  // namespace mpmfrag::mpi
