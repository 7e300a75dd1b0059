/// @file gravity.cpp
/// Octree gravity with quadrupoles and group walk; equations and criteria in gravity.hpp.
#include "ssdem/gravity.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "common/status.hpp"

namespace ssdem {

namespace {
// Position of tree slot t in the gathered particle list (its group's range is in `ranges`).
std::size_t self_index(const std::vector<std::uint32_t>& ranges, std::uint32_t t) {
  std::size_t q = 0;
  for (std::size_t r = 0; r < ranges.size(); r += 2) {
    if (t >= ranges[r] && t < ranges[r] + ranges[r + 1]) return q + (t - ranges[r]);
    q += ranges[r + 1];
  }
  return static_cast<std::size_t>(-1);
}
}  // namespace

void direct_gravity(const Spheres& sp, double G, std::vector<Vec3>& acc, std::vector<double>* pot) {
  const std::size_t n = sp.size();
  acc.assign(n, Vec3::Zero());
  if (pot) pot->assign(n, 0.0);
#pragma omp parallel for schedule(dynamic, 64) if (n >= 256)
  for (std::size_t i = 0; i < n; ++i) {
    Vec3 a = Vec3::Zero();
    double ph = 0.0;
    for (std::size_t j = 0; j < n; ++j) {
      if (j == i) continue;
      const Vec3 r = sp.x[j] - sp.x[i];
      double pf;
      const double f = spline_force_factor(r.norm(), sp.s[i] + sp.s[j], pf);
      a += (G * sp.m[j] * f) * r;
      ph -= G * sp.m[j] * pf;
    }
    acc[i] = a;
    if (pot) (*pot)[i] = ph;
  }
}

void TreeGravity::build(const Spheres& sp) {
  const std::size_t n = sp.size();
  nodes_.clear();
  leaves_.clear();
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
  // Fill tree-order arrays lazily: build_node permutes perm_, data copied after.
  sp_ = &sp;
  nodes_.reserve(2 * n / std::max(1, p_.bucket) + 16);
  nodes_.emplace_back();
  build_node(0, 0, static_cast<std::uint32_t>(n), c, half, 0);
  sp_ = nullptr;
  stats_.nodes = nodes_.size();
  stats_.leaves = leaves_.size();
}

std::uint32_t TreeGravity::build_node(std::uint32_t self, std::uint32_t start, std::uint32_t count,
                                      const Vec3& c, double half, int depth) {
  const Spheres& sp = *sp_;
  stats_.depth = std::max<std::size_t>(stats_.depth, static_cast<std::size_t>(depth));
  nodes_[self].start = start;
  nodes_[self].count = count;
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
      build_node(first + k, start + cnt[o], cnt[o + 1] - cnt[o], cc, hh, depth + 1);
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

void TreeGravity::compute(const Spheres& sp, std::vector<Vec3>& acc, std::vector<double>* pot) {
  const std::size_t n = sp.size();
  acc.assign(n, Vec3::Zero());
  if (pot) pot->assign(n, 0.0);
  if (n == 0) return;
  build(sp);
  const double G = p_.G;
  const double itheta = 1.0 / p_.theta;
  const std::size_t nl = leaves_.size();
  double tot_cells = 0, tot_parts = 0;
#pragma omp parallel reduction(+ : tot_cells, tot_parts) if (n >= 1024)
  {
    std::vector<std::uint32_t> stack, cells;
    std::vector<std::uint32_t> ranges;  // start, count pairs
    std::vector<double> cbuf, pbuf;
    stack.reserve(256);
#pragma omp for schedule(dynamic, 4)
    for (std::size_t L = 0; L < nl; ++L) {
      const Node& g = nodes_[leaves_[L]];
      cells.clear();
      ranges.clear();
      stack.clear();
      stack.push_back(0);
      while (!stack.empty()) {
        const std::uint32_t ci = stack.back();
        stack.pop_back();
        const Node& c = nodes_[ci];
        if (ci == leaves_[L]) {
          ranges.push_back(c.start);
          ranges.push_back(c.count);
          continue;
        }
        const Vec3 dd = (g.lo - c.com).cwiseMax(c.com - g.hi).cwiseMax(Vec3::Zero());
        const double rmin = dd.norm();
        if (rmin > c.bmax * itheta && rmin > c.bmax + c.hmax + g.hmax) {
          cells.push_back(ci);
        } else if (c.child < 0) {
          ranges.push_back(c.start);
          ranges.push_back(c.count);
        } else {
          for (int k = c.nchild - 1; k >= 0; --k) stack.push_back(c.child + k);
        }
      }
      // Gather the interaction lists into contiguous arrays (vectorisable inner loops).
      const std::size_t nc = cells.size();
      cbuf.resize(10 * nc);
      double* cx = cbuf.data();
      double* cy = cx + nc;
      double* cz = cy + nc;
      double* cm = cz + nc;
      double* q0 = cm + nc;
      double* q1 = q0 + nc;
      double* q2 = q1 + nc;
      double* q3 = q2 + nc;
      double* q4 = q3 + nc;
      double* q5 = q4 + nc;
      for (std::size_t c = 0; c < nc; ++c) {
        const Node& nd = nodes_[cells[c]];
        cx[c] = nd.com.x();
        cy[c] = nd.com.y();
        cz[c] = nd.com.z();
        cm[c] = nd.mass;
        q0[c] = nd.q[0];
        q1[c] = nd.q[1];
        q2[c] = nd.q[2];
        q3[c] = nd.q[3];
        q4[c] = nd.q[4];
        q5[c] = nd.q[5];
      }
      std::size_t npart = 0;
      for (std::size_t r = 0; r < ranges.size(); r += 2) npart += ranges[r + 1];
      pbuf.resize(5 * npart);
      double* ux = pbuf.data();
      double* uy = ux + npart;
      double* uz = uy + npart;
      double* um = uz + npart;
      double* uh = um + npart;
      {
        std::size_t q = 0;
        for (std::size_t r = 0; r < ranges.size(); r += 2)
          for (std::uint32_t u = ranges[r]; u < ranges[r] + ranges[r + 1]; ++u, ++q) {
            ux[q] = px_[u];
            uy[q] = py_[u];
            uz[q] = pz_[u];
            um[q] = pm_[u];
            uh[q] = ph_[u];
          }
      }
      const std::size_t self_q = self_index(ranges, g.start);
      tot_cells += static_cast<double>(nc) * g.count;
      tot_parts += static_cast<double>(npart) * g.count;
      for (std::uint32_t t = g.start; t < g.start + g.count; ++t) {
        const double xi = px_[t], yi = py_[t], zi = pz_[t], hi = ph_[t];
        double ax = 0, ay = 0, az = 0, ph = 0;
        for (std::size_t c = 0; c < nc; ++c) {
          const double rx = xi - cx[c], ry = yi - cy[c], rz = zi - cz[c];
          const double r2 = rx * rx + ry * ry + rz * rz;
          const double ir = 1.0 / std::sqrt(r2), ir2 = ir * ir;
          const double ir3 = ir * ir2, ir5 = ir3 * ir2, ir7 = ir5 * ir2;
          const double qx = q0[c] * rx + q3[c] * ry + q4[c] * rz;
          const double qy = q3[c] * rx + q1[c] * ry + q5[c] * rz;
          const double qz = q4[c] * rx + q5[c] * ry + q2[c] * rz;
          const double rqr = rx * qx + ry * qy + rz * qz;
          const double mono = -cm[c] * ir3 - 2.5 * rqr * ir7;
          ax += mono * rx + qx * ir5;
          ay += mono * ry + qy * ir5;
          az += mono * rz + qz * ir5;
          ph -= cm[c] * ir + 0.5 * rqr * ir5;
        }
        // Newtonian for all pairs (self and softened pairs masked), then a scalar fix-up pass
        // for the few pairs closer than h (overlapping spheres).
        double bx = 0, by = 0, bz = 0, bp = 0;
        for (std::size_t q = 0; q < npart; ++q) {
          const double rx = ux[q] - xi, ry = uy[q] - yi, rz = uz[q] - zi;
          const double r2 = rx * rx + ry * ry + rz * rz;
          const double h = hi + uh[q];
          const bool far = r2 >= h * h;
          const double ir = far ? 1.0 / std::sqrt(r2) : 0.0;
          const double mf = um[q] * ir * ir * ir;
          bx += mf * rx;
          by += mf * ry;
          bz += mf * rz;
          bp -= um[q] * ir;
        }
        const std::size_t self = self_q + (t - g.start);
        for (std::size_t q = 0; q < npart; ++q) {
          const double rx = ux[q] - xi, ry = uy[q] - yi, rz = uz[q] - zi;
          const double r2 = rx * rx + ry * ry + rz * rz;
          const double h = hi + uh[q];
          if (r2 >= h * h || q == self) continue;
          double pf;
          const double f = spline_force_factor(std::sqrt(r2), h, pf);
          bx += um[q] * f * rx;
          by += um[q] * f * ry;
          bz += um[q] * f * rz;
          bp -= um[q] * pf;
        }
        const std::uint32_t i = perm_[t];
        acc[i] = Vec3(G * (ax + bx), G * (ay + by), G * (az + bz));
        if (pot) (*pot)[i] = G * (ph + bp);
      }
    }
  }
  stats_.cell_interactions = tot_cells / static_cast<double>(n);
  stats_.particle_interactions = tot_parts / static_cast<double>(n);
}

double TreeGravity::bytes_per_sphere(std::size_t n) const {
  if (n == 0) return 0.0;
  return (static_cast<double>(nodes_.size()) * sizeof(Node) +
          static_cast<double>(n) * (4 + 4 + 5 * 8) + 4.0 * leaves_.size()) /
         static_cast<double>(n);
}

}  // namespace ssdem
