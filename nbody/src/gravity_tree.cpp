/// @file gravity_tree.cpp
/// Octree build and multipole moments of TreeGravity (gravity.hpp).
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "common/status.hpp"
#include "ssdem/gravity.hpp"

namespace ssdem {

void TreeGravity::build(const Spheres& sp) {
  const std::size_t n = sp.size();
  nodes_.clear();
  leaves_.clear();
  groups_.clear();
  perm_.resize(n);
  for (std::size_t i = 0; i < n; ++i) perm_[i] = static_cast<std::uint32_t>(i);
  px_.resize(n);
  py_.resize(n);
  pz_.resize(n);
  pm_.resize(n);
  ph_.resize(n);
  scratch_.resize(n);
  stats_ = {};
  if (n == 0) return;
  Vec3 lo = sp.x[0], hi = sp.x[0];
  for (std::size_t i = 0; i < n; ++i) {
    if (!sp.x[i].allFinite())
      throw common::NumericalError("gravity tree: non-finite position of sphere id " +
                                   std::to_string(sp.id[i]));
    lo = lo.cwiseMin(sp.x[i]);
    hi = hi.cwiseMax(sp.x[i]);
  }
  const Vec3 c = 0.5 * (lo + hi);
  const double half = 0.5 * (hi - lo).maxCoeff() * (1.0 + 1e-12) + 1e-300;
  double smax = 0;
  for (double s : sp.s) smax = std::max(smax, s);
  root_half_ = std::max(half, smax);  // kernel length unit (gravity_walk.cpp)
  // Fill tree-order arrays lazily: build_node permutes perm_, data copied after.
  sp_ = &sp;
  nodes_.reserve(2 * n / std::max(1, p_.bucket) + 16);
  nodes_.emplace_back();
  build_node(0, 0, static_cast<std::uint32_t>(n), c, half, 0, false);
  sp_ = nullptr;
  stats_.nodes = nodes_.size();
  stats_.leaves = leaves_.size();
}

std::uint32_t TreeGravity::build_node(std::uint32_t self, std::uint32_t start, std::uint32_t count,
                                      const Vec3& c, double half, int depth, bool in_group) {
  const Spheres& sp = *sp_;
  stats_.depth = std::max<std::size_t>(stats_.depth, static_cast<std::size_t>(depth));
  nodes_[self].start = start;
  nodes_[self].count = count;
  // sink groups: the largest subtrees with at most `group` spheres, or leaves larger than that
  const bool group_here = !in_group && (static_cast<int>(count) <= std::max(p_.group, p_.bucket) ||
                                        !(static_cast<int>(count) > p_.bucket && depth < p_.max_depth));
  if (group_here) groups_.push_back(self);
  if (static_cast<int>(count) > p_.bucket && depth < p_.max_depth) {
    std::array<std::uint32_t, 9> cnt{};
    auto oct = [&](std::uint32_t i) {
      const Vec3& x = sp.x[i];
      return (x.x() > c.x() ? 1 : 0) | (x.y() > c.y() ? 2 : 0) | (x.z() > c.z() ? 4 : 0);
    };
    for (std::uint32_t t = start; t < start + count; ++t) ++cnt[oct(perm_[t]) + 1];
    for (int o = 0; o < 8; ++o) cnt[o + 1] += cnt[o];
    std::array<std::uint32_t, 8> fill;
    for (int o = 0; o < 8; ++o) fill[o] = cnt[o];
    for (std::uint32_t t = start; t < start + count; ++t) {
      const std::uint32_t i = perm_[t];
      scratch_[start + fill[oct(i)]++] = i;
    }
    std::copy(scratch_.begin() + start, scratch_.begin() + start + count, perm_.begin() + start);
    int nch = 0;
    for (int o = 0; o < 8; ++o) nch += cnt[o + 1] > cnt[o];
    const std::uint32_t first = static_cast<std::uint32_t>(nodes_.size());
    nodes_[self].child = static_cast<std::int32_t>(first);
    nodes_[self].nchild = static_cast<std::uint8_t>(nch);
    nodes_.resize(nodes_.size() + nch);
    int k = 0;
    for (int o = 0; o < 8; ++o) {
      if (cnt[o + 1] == cnt[o]) continue;
      const double hh = 0.5 * half;
      const Vec3 cc(c.x() + ((o & 1) ? hh : -hh), c.y() + ((o & 2) ? hh : -hh),
                    c.z() + ((o & 4) ? hh : -hh));
      build_node(first + k, start + cnt[o], cnt[o + 1] - cnt[o], cc, hh, depth + 1, in_group || group_here);
      ++k;
    }
  } else {
    leaves_.push_back(self);
    for (std::uint32_t t = start; t < start + count; ++t) {
      const std::uint32_t i = perm_[t];
      px_[t] = sp.x[i].x();
      py_[t] = sp.x[i].y();
      pz_[t] = sp.x[i].z();
      pm_[t] = sp.m[i];
      ph_[t] = sp.s[i];
    }
  }
  moments(self);
  return self;
}

void TreeGravity::moments(std::uint32_t self) {
  Node& nd = nodes_[self];
  double M = 0;
  Vec3 com = Vec3::Zero();
  double q[6] = {0, 0, 0, 0, 0, 0};
  if (nd.child < 0) {
    Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity());
    Vec3 hi = -lo;
    double hmax = 0;
    for (std::uint32_t t = nd.start; t < nd.start + nd.count; ++t) {
      const Vec3 x(px_[t], py_[t], pz_[t]);
      M += pm_[t];
      com += pm_[t] * x;
      lo = lo.cwiseMin(x);
      hi = hi.cwiseMax(x);
      hmax = std::max(hmax, ph_[t]);
    }
    com /= M;
    double b2 = 0;
    for (std::uint32_t t = nd.start; t < nd.start + nd.count; ++t) {
      const Vec3 d = Vec3(px_[t], py_[t], pz_[t]) - com;
      const double m = pm_[t], dd = d.squaredNorm();
      q[0] += m * (3 * d.x() * d.x() - dd);
      q[1] += m * (3 * d.y() * d.y() - dd);
      q[2] += m * (3 * d.z() * d.z() - dd);
      q[3] += m * 3 * d.x() * d.y();
      q[4] += m * 3 * d.x() * d.z();
      q[5] += m * 3 * d.y() * d.z();
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
      const Node& ch = nodes_[nd.child + k];
      M += ch.mass;
      com += ch.mass * ch.com;
      lo = lo.cwiseMin(ch.lo);
      hi = hi.cwiseMax(ch.hi);
      hmax = std::max(hmax, ch.hmax);
    }
    com /= M;
    double bmax = 0;
    for (int k = 0; k < nd.nchild; ++k) {
      const Node& ch = nodes_[nd.child + k];
      const Vec3 d = ch.com - com;
      const double m = ch.mass, dd = d.squaredNorm();
      q[0] += ch.q[0] + m * (3 * d.x() * d.x() - dd);
      q[1] += ch.q[1] + m * (3 * d.y() * d.y() - dd);
      q[2] += ch.q[2] + m * (3 * d.z() * d.z() - dd);
      q[3] += ch.q[3] + m * 3 * d.x() * d.y();
      q[4] += ch.q[4] + m * 3 * d.x() * d.z();
      q[5] += ch.q[5] + m * 3 * d.y() * d.z();
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

}  // namespace ssdem
