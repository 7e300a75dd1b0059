/// @file gravity_walk.cpp
/// Group tree walk of TreeGravity (gravity.hpp): one walk per sink group builds three
/// interaction lists shared by the group's spheres — multipole cells, far particles (Newtonian
/// pairs) and near particles (possibly overlapping pairs, spline kernel) — gathered into
/// structure-of-arrays buffers and summed by the vectorised kernels of gravity_kernels.cpp.
/// A leaf that the walk finds near the group is split particle by particle: a particle whose
/// distance to the group's box is at least its radius plus the group's largest radius cannot
/// overlap any sink (r >= h_i + h_j, where the spline is exactly Newtonian) and joins the far
/// list, unless it lies within 1e-3 of the group's extent of the box (float precision: a leaf
/// that close is near too).
/// In a dense pile the near leaves' boxes reach two sphere diameters beyond the group while
/// the overlapping pairs lie within one, so most of them are far (measured in nbody/README.md).
#include <algorithm>
#include <cmath>

#include "gravity_kernels.hpp"
#include "ssdem/gravity.hpp"

namespace ssdem {
namespace {
// Squared distance between two axis-aligned boxes (0 if they overlap; a point is a box lo = hi).
double box_distance2(const Vec3& alo, const Vec3& ahi, const Vec3& blo, const Vec3& bhi) {
  return (alo - bhi).cwiseMax(blo - ahi).cwiseMax(Vec3::Zero()).squaredNorm();
}
// Per-thread gather buffers.
struct Lists {
  std::vector<std::uint32_t> stack, cells, far, near;  // far/near: leaf node indices
  std::vector<std::uint32_t> fpart, npart;           // far/near: particle indices (tree order)
  std::vector<float> cbuf, fbuf, sbuf, nflt;
  std::vector<double> nbuf, sdbl, acc;
  std::vector<std::int32_t> ntid, stid;
};
}  // namespace

void TreeGravity::compute(const Spheres& sp, std::vector<Vec3>& acc, std::vector<double>* pot) {
  const std::size_t n = sp.size();
  acc.assign(n, Vec3::Zero());
  if (pot) pot->assign(n, 0.0);
  if (n == 0) return;
  build(sp);
  tree::WalkTally tally;
  tree::walk(d_, p_, d_.groups, acc, pot, tally);
  d_.stats.cell_interactions = tally.cells / static_cast<double>(n);
  d_.stats.particle_interactions = tally.parts / static_cast<double>(n);
  d_.stats.near_interactions = tally.near / static_cast<double>(n);
}

namespace tree {

void walk(const Data& d, const GravityParams& p, const std::vector<std::uint32_t>& groups,
          std::vector<Vec3>& acc, std::vector<double>* pot, WalkTally& tally) {
  if (d.nodes.empty() || groups.empty()) return;
  const std::vector<Node>& nodes = d.nodes;
  const std::vector<double>&px = d.px, &py = d.py, &pz = d.pz, &pm = d.pm, &ph = d.ph;
  // Kernel units (single precision must neither overflow nor underflow for any SI scene):
  // lengths in units of the root cell's half-size L, masses in units of the total mass M,
  // coordinates relative to each group's centre.
  const double L = d.root_half, M = nodes[0].mass;
  const double il = 1.0 / L, im = 1.0 / M, il2 = il * il;
  const double facc = p.G * M / (L * L), fpot = p.G * M / L;
  const double itheta = 1.0 / p.theta;
  const std::size_t nl = groups.size();
  std::size_t nsinks = 0;
  for (std::uint32_t gi : groups) nsinks += nodes[gi].count;
  double tot_cells = 0, tot_parts = 0, tot_near = 0;
#pragma omp parallel reduction(+ : tot_cells, tot_parts, tot_near) if (nsinks >= 1024)
  {
    Lists w;
    w.stack.reserve(256);
#pragma omp for schedule(dynamic, 4)
    for (std::size_t gl = 0; gl < nl; ++gl) {
      const std::uint32_t gi = groups[gl];
      const Node& g = nodes[gi];
      // The far kernel takes coordinates relative to the group's centre in float, good to ~1e-7
      // of the group's extent: a source closer to the group's box than 1e-3 of that extent keeps
      // the near list's double differences (so every separation is good to ~1e-4 of itself; a
      // close pair in a wide, sparse group, which before 2026-12-06 could lose percents or, at
      // 1e7 radii of extent, round to r = 0). In a pile the extent is ~16 radii: never binds.
      const double dmin = 1e-3 * (g.hi - g.lo).norm();
      w.cells.clear();
      w.far.clear();
      w.near.clear();
      w.stack.assign(1, 0);
      while (!w.stack.empty()) {
        const std::uint32_t ci = w.stack.back();
        w.stack.pop_back();
        const Node& c = nodes[ci];
        if (ci == gi) {
          w.near.push_back(ci);
          continue;
        }
        if (tree_accepts(c, g.lo, g.hi, g.hmax, itheta)) {
          w.cells.push_back(ci);
        } else if (c.child < 0) {
          const double reach = std::max(c.hmax + g.hmax, dmin);
          (box_distance2(c.lo, c.hi, g.lo, g.hi) < reach * reach ? w.near : w.far).push_back(ci);
        } else {
          for (int k = c.nchild - 1; k >= 0; --k) w.stack.push_back(c.child + k);
        }
      }
      // gather the lists (structure of arrays)
      const Vec3 c0 = 0.5 * (g.lo + g.hi);
      detail::CellList cl;
      cl.n = w.cells.size();
      w.cbuf.resize(10 * cl.n);
      {
        float* b = w.cbuf.data();
        const std::size_t m = cl.n;
        cl.x = b, cl.y = b + m, cl.z = b + 2 * m, cl.m = b + 3 * m;
        cl.q0 = b + 4 * m, cl.q1 = b + 5 * m, cl.q2 = b + 6 * m;
        cl.q3 = b + 7 * m, cl.q4 = b + 8 * m, cl.q5 = b + 9 * m;
        for (std::size_t k = 0; k < m; ++k) {
          const Node& nd = nodes[w.cells[k]];
          b[k] = static_cast<float>((nd.com.x() - c0.x()) * il);
          b[m + k] = static_cast<float>((nd.com.y() - c0.y()) * il);
          b[2 * m + k] = static_cast<float>((nd.com.z() - c0.z()) * il);
          b[3 * m + k] = static_cast<float>(nd.mass * im);
          for (int q = 0; q < 6; ++q) b[(4 + q) * m + k] = static_cast<float>(nd.q[q] * im * il2);
        }
      }
      // particles: far leaves whole; near leaves (other than the group) split per particle: far
      // only if it cannot overlap a sink (distance to the box >= its radius plus the group's
      // largest) and lies at least dmin from the box
      w.fpart.clear();
      w.npart.clear();
      for (std::uint32_t li : w.far)
        for (std::uint32_t t = nodes[li].start; t < nodes[li].start + nodes[li].count; ++t) w.fpart.push_back(t);
      for (std::uint32_t li : w.near) {
        const std::uint32_t t0 = nodes[li].start, t1 = t0 + nodes[li].count;
        if (li == gi) {
          for (std::uint32_t t = t0; t < t1; ++t) w.npart.push_back(t);
          continue;
        }
        for (std::uint32_t t = t0; t < t1; ++t) {
          const Vec3 x(px[t], py[t], pz[t]);
          const double reach = std::max(ph[t] + g.hmax, dmin);
          (box_distance2(x, x, g.lo, g.hi) < reach * reach ? w.npart : w.fpart).push_back(t);
        }
      }
      const std::size_t nf = w.fpart.size(), nn = w.npart.size();
      detail::PartList fl;
      fl.n = nf;
      w.fbuf.resize(4 * nf);
      {
        float* b = w.fbuf.data();
        fl.x = b, fl.y = b + nf, fl.z = b + 2 * nf, fl.m = b + 3 * nf;
        for (std::size_t k = 0; k < nf; ++k) {
          const std::uint32_t t = w.fpart[k];
          b[k] = static_cast<float>((px[t] - c0.x()) * il);
          b[nf + k] = static_cast<float>((py[t] - c0.y()) * il);
          b[2 * nf + k] = static_cast<float>((pz[t] - c0.z()) * il);
          b[3 * nf + k] = static_cast<float>(pm[t] * im);
        }
      }
      // near list in units of the group's largest radius (gravity_kernels.hpp)
      const double iln = 1.0 / g.hmax;
      detail::NearList nlst;
      nlst.n = nn;
      nlst.acc_scale = (L * iln) * (L * iln);
      nlst.pot_scale = L * iln;
      w.nbuf.resize(3 * nn);
      w.nflt.resize(2 * nn);
      w.ntid.resize(nn);
      {
        double* b = w.nbuf.data();
        float* f = w.nflt.data();
        nlst.x = b, nlst.y = b + nn, nlst.z = b + 2 * nn, nlst.m = f, nlst.h = f + nn;
        nlst.tid = w.ntid.data();
        for (std::size_t k = 0; k < nn; ++k) {
          const std::uint32_t t = w.npart[k];
          b[k] = (px[t] - c0.x()) * iln;
          b[nn + k] = (py[t] - c0.y()) * iln;
          b[2 * nn + k] = (pz[t] - c0.z()) * iln;
          f[k] = static_cast<float>(pm[t] * im);
          f[nn + k] = static_cast<float>(ph[t] * iln);
          w.ntid[k] = static_cast<std::int32_t>(t);
        }
      }
      // sinks
      const std::size_t ns = g.count;
      w.sbuf.resize(4 * ns);
      w.sdbl.resize(3 * ns);
      w.stid.resize(ns);
      w.acc.assign(4 * ns, 0.0);
      detail::GroupSinks s;
      s.n = ns;
      {
        float* b = w.sbuf.data();
        double* d = w.sdbl.data();
        for (std::size_t k = 0; k < ns; ++k) {
          const std::uint32_t t = g.start + static_cast<std::uint32_t>(k);
          b[k] = static_cast<float>((px[t] - c0.x()) * il);
          b[ns + k] = static_cast<float>((py[t] - c0.y()) * il);
          b[2 * ns + k] = static_cast<float>((pz[t] - c0.z()) * il);
          b[3 * ns + k] = static_cast<float>(ph[t] * iln);
          d[k] = (px[t] - c0.x()) * iln;
          d[ns + k] = (py[t] - c0.y()) * iln;
          d[2 * ns + k] = (pz[t] - c0.z()) * iln;
          w.stid[k] = static_cast<std::int32_t>(t);
        }
        s.x = b, s.y = b + ns, s.z = b + 2 * ns, s.h = b + 3 * ns, s.tid = w.stid.data();
        s.xd = d, s.yd = d + ns, s.zd = d + 2 * ns;
        double* a = w.acc.data();
        s.ax = a, s.ay = a + ns, s.az = a + 2 * ns;
        s.pot = pot ? a + 3 * ns : nullptr;
      }
      detail::cell_kernel(s, cl);
      detail::far_kernel(s, fl);
      detail::near_kernel(s, nlst);
      tot_cells += static_cast<double>(cl.n) * static_cast<double>(ns);
      tot_parts += static_cast<double>(fl.n + nlst.n) * static_cast<double>(ns);
      tot_near += static_cast<double>(nlst.n) * static_cast<double>(ns);
      for (std::size_t k = 0; k < ns; ++k) {
        const std::uint32_t i = d.perm[g.start + k];
        acc[i] = Vec3(facc * s.ax[k], facc * s.ay[k], facc * s.az[k]);
        if (pot) (*pot)[i] = fpot * s.pot[k];
      }
    }
  }
  tally.cells += tot_cells;
  tally.parts += tot_parts;
  tally.near += tot_near;
}

}  // namespace tree
}  // namespace ssdem
