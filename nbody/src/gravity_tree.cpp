/// @file gravity_tree.cpp
/// Octree build and multipole moments (gravity_tree.hpp), shared by TreeGravity and the MPI ranks'
/// distributed tree; TreeGravity::build, the serial root.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "common/status.hpp"
#include "ssdem/gravity.hpp"

namespace ssdem {

void TreeGravity::build(const Spheres& sp) {
  const std::size_t n = sp.size();
  tree::Data& d = d_;
  d.nodes.clear();
  d.leaves.clear();
  d.groups.clear();
  d.perm.resize(n);
  for (std::size_t i = 0; i < n; ++i) d.perm[i] = static_cast<std::uint32_t>(i);
  d.px.resize(n);
  d.py.resize(n);
  d.pz.resize(n);
  d.pm.resize(n);
  d.ph.resize(n);
  d.scratch.resize(n);
  d.stats = {};
  if (n == 0) return;
  Vec3 lo = sp.x[0], hi = sp.x[0];
  for (std::size_t i = 0; i < n; ++i) {
    if (!sp.x[i].allFinite())
      throw common::NumericalError("gravity tree: non-finite position of sphere id " +
                                   std::to_string(sp.id[i]));
    lo = lo.cwiseMin(sp.x[i]);
    hi = hi.cwiseMax(sp.x[i]);
  }
  Vec3 c;
  double half;
  tree::tree_root(lo, hi, c, half);
  double smax = 0;
  for (double s : sp.s) smax = std::max(smax, s);
  d.root_half = std::max(half, smax);  // kernel length unit (gravity_walk.cpp)
  d.nodes.reserve(2 * n / std::max(1, p_.bucket) + 16);
  d.nodes.emplace_back();
  tree::build_subtree(d, p_, tree::Source{sp.x.data(), sp.m.data(), sp.s.data()}, 0, 0,
                      static_cast<std::uint32_t>(n), c, half, 0, false);
}

namespace tree {

void build_subtree(Data& d, const GravityParams& p, const Source& src, std::uint32_t self,
                   std::uint32_t start, std::uint32_t count, const Vec3& c, double half, int depth,
                   bool in_group) {
  d.stats.depth = std::max<std::size_t>(d.stats.depth, static_cast<std::size_t>(depth));
  d.nodes[self].start = start;
  d.nodes[self].count = count;
  // sink groups: the largest subtrees with at most `group` spheres, or leaves larger than that
  const bool group_here = tree_is_group(p, count, depth, in_group);
  if (group_here) d.groups.push_back(self);
  if (tree_splits(p, count, depth)) {
    std::array<std::uint32_t, 9> cnt{};
    auto oct = [&](std::uint32_t i) { return tree_octant(src.x[i], c); };
    for (std::uint32_t t = start; t < start + count; ++t) ++cnt[oct(d.perm[t]) + 1];
    for (int o = 0; o < 8; ++o) cnt[o + 1] += cnt[o];
    std::array<std::uint32_t, 8> fill;
    for (int o = 0; o < 8; ++o) fill[o] = cnt[o];
    for (std::uint32_t t = start; t < start + count; ++t) {
      const std::uint32_t i = d.perm[t];
      d.scratch[start + fill[oct(i)]++] = i;
    }
    std::copy(d.scratch.begin() + start, d.scratch.begin() + start + count, d.perm.begin() + start);
    int nch = 0;
    for (int o = 0; o < 8; ++o) nch += cnt[o + 1] > cnt[o];
    const std::uint32_t first = static_cast<std::uint32_t>(d.nodes.size());
    d.nodes[self].child = static_cast<std::int32_t>(first);
    d.nodes[self].nchild = static_cast<std::uint8_t>(nch);
    d.nodes.resize(d.nodes.size() + nch);
    int k = 0;
    for (int o = 0; o < 8; ++o) {
      if (cnt[o + 1] == cnt[o]) continue;
      build_subtree(d, p, src, first + k, start + cnt[o], cnt[o + 1] - cnt[o], tree_child_centre(c, half, o),
                    0.5 * half, depth + 1, in_group || group_here);
      ++k;
    }
  } else {
    d.leaves.push_back(self);
    for (std::uint32_t t = start; t < start + count; ++t) {
      const std::uint32_t i = d.perm[t];
      d.px[t] = src.x[i].x();
      d.py[t] = src.x[i].y();
      d.pz[t] = src.x[i].z();
      d.pm[t] = src.m[i];
      d.ph[t] = src.s[i];
    }
  }
  moments(d, self);
  d.stats.nodes = d.nodes.size();
  d.stats.leaves = d.leaves.size();
}

void moments(Data& d, std::uint32_t self) {
  const std::vector<double>&px = d.px, &py = d.py, &pz = d.pz, &pm = d.pm, &ph = d.ph;
  Node& nd = d.nodes[self];
  double M = 0;
  Vec3 com = Vec3::Zero();
  double q[6] = {0, 0, 0, 0, 0, 0};
  if (nd.child < 0) {
    Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity());
    Vec3 hi = -lo;
    double hmax = 0;
    for (std::uint32_t t = nd.start; t < nd.start + nd.count; ++t) {
      const Vec3 x(px[t], py[t], pz[t]);
      M += pm[t];
      com += pm[t] * x;
      lo = lo.cwiseMin(x);
      hi = hi.cwiseMax(x);
      hmax = std::max(hmax, ph[t]);
    }
    com /= M;
    double b2 = 0;
    for (std::uint32_t t = nd.start; t < nd.start + nd.count; ++t) {
      const Vec3 e = Vec3(px[t], py[t], pz[t]) - com;
      const double m = pm[t], dd = e.squaredNorm();
      q[0] += m * (3 * e.x() * e.x() - dd);
      q[1] += m * (3 * e.y() * e.y() - dd);
      q[2] += m * (3 * e.z() * e.z() - dd);
      q[3] += m * 3 * e.x() * e.y();
      q[4] += m * 3 * e.x() * e.z();
      q[5] += m * 3 * e.y() * e.z();
      b2 = std::max(b2, dd);
    }
    nd.lo = lo;
    nd.hi = hi;
    nd.hmax = hmax;
    nd.bmax = std::sqrt(b2);
  } else {
    Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity());
    Vec3 hi = -lo;
    double hmax = 0;
    for (int k = 0; k < nd.nchild; ++k) {
      const Node& ch = d.nodes[nd.child + k];
      M += ch.mass;
      com += ch.mass * ch.com;
      lo = lo.cwiseMin(ch.lo);
      hi = hi.cwiseMax(ch.hi);
      hmax = std::max(hmax, ch.hmax);
    }
    com /= M;
    double bmax = 0;
    for (int k = 0; k < nd.nchild; ++k) {
      const Node& ch = d.nodes[nd.child + k];
      const Vec3 e = ch.com - com;
      const double m = ch.mass, dd = e.squaredNorm();
      q[0] += ch.q[0] + m * (3 * e.x() * e.x() - dd);
      q[1] += ch.q[1] + m * (3 * e.y() * e.y() - dd);
      q[2] += ch.q[2] + m * (3 * e.z() * e.z() - dd);
      q[3] += ch.q[3] + m * 3 * e.x() * e.y();
      q[4] += ch.q[4] + m * 3 * e.x() * e.z();
      q[5] += ch.q[5] + m * 3 * e.y() * e.z();
      bmax = std::max(bmax, std::sqrt(dd) + ch.bmax);
    }
    // never larger than the farthest corner of the particles' bounding box
    const Vec3 far = (com - lo).cwiseAbs().cwiseMax((hi - com).cwiseAbs());
    nd.bmax = std::min(bmax, far.norm());
    nd.lo = lo;
    nd.hi = hi;
    nd.hmax = hmax;
  }
  nd.mass = M;
  nd.com = com;
  for (int k = 0; k < 6; ++k) nd.q[k] = q[k];
}

}  // namespace tree
}  // namespace ssdem
