#include "handoff/projection.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <sstream>

#include "common/huge_pages.hpp"
#include "common/status.hpp"

namespace handoff {

namespace {

struct CoarseGrid {
  Eigen::Vector3i shape;  // sphere cells per axis
  double edge;            // sphere cell edge
  Eigen::Vector3d origin;
  std::int64_t cells() const { return std::int64_t(shape[0]) * shape[1] * shape[2]; }
  std::int64_t key(const Eigen::Vector3i& c) const { return c[0] + std::int64_t(shape[0]) * (c[1] + std::int64_t(shape[1]) * c[2]); }
};

/// The weights of one particle's stencil (mpm-frag's axis weights without the gradients),
/// kept between P2G and G2P so that each particle's stencil is evaluated once.
struct WeightStencil {
  std::int32_t first[3];
  std::int32_t n;  // nodes per axis (same on every axis)
  double w[3][3];  // w[axis][node]
};

inline WeightStencil weight_stencil(const mpmfrag::ParticleStencil& st) {
  WeightStencil ws;
  ws.n = st.axis[0].n;
  for (int d = 0; d < 3; ++d) {
    ws.first[d] = st.axis[d].first;
    for (int k = 0; k < 3; ++k) ws.w[d][k] = st.axis[d].w[k];
  }
  return ws;
}

/// Call f(node_linear_index, weight) for every stencil node with non-zero weight.
template <class F>
inline void for_each_weight(const WeightStencil& st, const common::GridInfo& g, F&& f) {
  const std::size_t sy = static_cast<std::size_t>(g.shape[0]), sz = sy * static_cast<std::size_t>(g.shape[1]);
  for (int c = 0; c < st.n; ++c) {
    if (st.w[2][c] == 0.0) continue;
    const std::size_t zbase = (st.first[2] + c) * sz;
    for (int b = 0; b < st.n; ++b) {
      const double wyz = st.w[1][b] * st.w[2][c];
      if (wyz == 0.0) continue;
      const std::size_t base = zbase + (st.first[1] + b) * sy + st.first[0];
      for (int a = 0; a < st.n; ++a)
        if (st.w[0][a] != 0.0) f(base + a, st.w[0][a] * wyz);
    }
  }
}

std::string where_particle(const common::ParticleSnapshot& s, std::size_t p) {
  std::ostringstream o;
  o.precision(9);
  o << "particle id " << s.id[p] << " at (" << s.position[3 * p] << ", " << s.position[3 * p + 1] << ", "
    << s.position[3 * p + 2] << ")";
  return o.str();
}

}  // namespace

ProjectionResult project_to_spheres(const common::ParticleSnapshot& s, const ProjectionOptions& opt,
                                    const std::string& file) {
  const std::size_t n = s.count();
  if (n == 0) throw common::InputError(file, "/particles", "no particles to hand off");
  const common::GridInfo& g = s.grid;
  const double h = g.cell_size[0];
  if (std::fabs(g.cell_size[1] - h) > 1e-12 * h || std::fabs(g.cell_size[2] - h) > 1e-12 * h)
    throw common::InputError(file, "/grid/cell_size", "spheres need cubic cells (equal cell_size entries)");
  if (opt.coarsen < 1) throw common::InputError(file, "coarsen", "must be >= 1");
  const int k = opt.coarsen;

  CoarseGrid cg;
  cg.edge = k * h;
  cg.origin = g.origin;
  for (int d = 0; d < 3; ++d) cg.shape[d] = (g.shape[d] - 1 + k - 1) / k;

  // Carried fields (scalar only).
  std::vector<const common::Field*> carry;
  for (const auto& name : opt.carry_fields) {
    const common::Field* f = s.field(name);
    if (!f) throw common::InputError(file, "/particles/" + name, "field to carry onto spheres is missing");
    if (f->ncomp != 1) throw common::InputError(file, "/particles/" + name, "only scalar fields can be carried");
    carry.push_back(f);
  }

  // 1. Validate and bin particles by sphere cell (parallel keys; the first offending particle in
  //    index order is reported, whatever the thread count).
  // Work arrays on transparent huge pages (common/huge_pages.hpp): first-touch faults dominate a
  // one-shot call otherwise.
  common::huge_vector<std::int64_t> key(n);
  if (n >= std::size_t(1) << 32) throw common::InputError(file, "/particles", "more than 2^32 particles in one hand-off");
  std::size_t first_big = n, first_out = n;
#pragma omp parallel for schedule(static) reduction(min : first_big, first_out)
  for (std::size_t p = 0; p < n; ++p) {
    bool big = false, inside = true;
    std::int64_t c[3];
    for (int d = 0; d < 3; ++d) {
      big = big || 0.5 * s.size[3 * p + d] > 0.5 * h * (1 + 1e-12);
      // Stencil bounds without computing weights: uGIMP uses nodes {i-1, i, i+1} or {i, i+1, i+2}
      // (shape_functions.hpp), linear {i, i+1}.
      const double xi = (s.position[3 * p + d] - g.origin[d]) / h;
      const double fl = std::floor(xi);
      const int i = static_cast<int>(fl);
      const int first = opt.shape == mpmfrag::ShapeKind::linear ? i : (xi - fl <= 0.5 ? i - 1 : i);
      const int count = opt.shape == mpmfrag::ShapeKind::linear ? 2 : 3;
      inside = inside && std::isfinite(xi) && first >= 0 && first + count <= g.shape[d];
      c[d] = inside ? std::clamp(i, 0, g.shape[d] - 2) / k : 0;
    }
    if (big) first_big = std::min(first_big, p);
    if (!inside) first_out = std::min(first_out, p);
    key[p] = c[0] + std::int64_t(cg.shape[0]) * (c[1] + std::int64_t(cg.shape[1]) * c[2]);
  }
  if (first_big < n && first_big <= first_out)
    throw common::InputError(file, "/particles/size", where_particle(s, first_big) + ": particle size exceeds the cell size " + std::to_string(h) + " m");
  if (first_out < n)
    throw common::InputError(file, "/particles/position", where_particle(s, first_out) + " lies outside the grid (its shape-function support leaves it)");
  std::vector<std::size_t> start(static_cast<std::size_t>(cg.cells()) + 1, 0);
  for (std::size_t p = 0; p < n; ++p) ++start[key[p] + 1];
  for (std::size_t c = 0; c + 1 < start.size(); ++c) start[c + 1] += start[c];
  common::huge_vector<std::uint32_t> order(n);  // 32-bit: half the memory traffic of size_t
  {
    std::vector<std::size_t> fill(start.begin(), start.end() - 1);
    for (std::size_t p = 0; p < n; ++p) order[fill[key[p]]++] = static_cast<std::uint32_t>(p);
  }

  // 2. P2G, parallel over slabs of sphere-cell z layers, two colours so that no two threads
  //    touch the same node; sums run in sorted order, so results do not depend on threads.
  const std::size_t nn = mpmfrag::node_count(g);
  common::huge_vector<double> node(4 * nn, 0.0);  // m, px, py, pz
  // Weights are recomputed in the G2P pass rather than cached: a cached stencil is ~90 bytes per
  // particle of fresh memory, which cost more than the few flops of the weights when measured with
  // 4 KiB pages (not re-measured since the work arrays moved to huge pages).
  auto weights = [&](std::size_t p) {
    const Eigen::Vector3d x(s.position[3 * p], s.position[3 * p + 1], s.position[3 * p + 2]);
    const Eigen::Vector3d lp(0.5 * s.size[3 * p], 0.5 * s.size[3 * p + 1], 0.5 * s.size[3 * p + 2]);
    return weight_stencil(mpmfrag::compute_stencil(opt.shape, g, x, lp));
  };
  const int layers_per_slab = (3 + k - 1) / k;
  const std::int64_t layer_cells = std::int64_t(cg.shape[0]) * cg.shape[1];
  const int nslab = (cg.shape[2] + layers_per_slab - 1) / layers_per_slab;
  auto slab_range = [&](int sl) {
    const std::int64_t z0 = std::int64_t(sl) * layers_per_slab;
    const std::int64_t z1 = std::min<std::int64_t>(z0 + layers_per_slab, cg.shape[2]);
    return std::pair<std::size_t, std::size_t>(start[z0 * layer_cells], start[z1 * layer_cells]);
  };
  for (int colour = 0; colour < 2; ++colour) {
#pragma omp parallel for schedule(dynamic, 1)
    for (int sl = colour; sl < nslab; sl += 2) {
      const auto [b, e] = slab_range(sl);
      for (std::size_t q = b; q < e; ++q) {
        const std::size_t p = order[q];
        const double m = s.mass[p];
        const double* v = &s.velocity[3 * p];
        for_each_weight(weights(p), g, [&](std::size_t ni, double w) {
          double* nd = &node[4 * ni];
          const double mw = m * w;
          nd[0] += mw;
          nd[1] += mw * v[0];
          nd[2] += mw * v[1];
          nd[3] += mw * v[2];
        });
      }
    }
  }
  // Nodal velocities in place.
#pragma omp parallel for schedule(static)
  for (std::int64_t i = 0; i < static_cast<std::int64_t>(nn); ++i) {
    double* nd = &node[4 * i];
    if (nd[0] > 0.0) {
      nd[1] /= nd[0];
      nd[2] /= nd[0];
      nd[3] /= nd[0];
    }
  }

  // 3. One sphere per occupied cell: G2P at the cell's particles, mass-weighted average.
  ProjectionResult r;
  r.cell_shape = cg.shape;
  r.sphere_cell = cg.edge;
  std::vector<std::int64_t> cells;
  for (std::int64_t c = 0; c < cg.cells(); ++c)
    if (start[c + 1] > start[c]) cells.push_back(c);
  const std::size_t ns = cells.size();
  common::SphereSet& out = r.spheres;
  out.time = s.time;
  out.step = s.step;
  out.id.resize(ns);
  out.position.resize(3 * ns);
  out.velocity.resize(3 * ns);
  out.spin.assign(3 * ns, 0.0);
  out.mass.resize(ns);
  out.radius.assign(ns, 0.5 * cg.edge);
  for (const auto* f : carry) out.fields.push_back({f->name, f->unit, 1, std::vector<double>(ns), "mass-weighted mean over the sphere's particles"});
  r.cell = cells;
  r.map.offset.resize(ns + 1);
  r.map.particle_id.resize(n);

  // Occupied MPM cells are counted per sphere cell (its k^3 fine cells, marked in a per-thread
  // table that is cleared through the list of marks).
  std::size_t occupied = 0;
#pragma omp parallel reduction(+ : occupied)
  {
  std::vector<double> fsum(carry.size());
  std::vector<unsigned char> mark(static_cast<std::size_t>(k) * k * k, 0);
  std::vector<std::size_t> marked;
#pragma omp for schedule(dynamic, 64)
  for (std::int64_t si = 0; si < static_cast<std::int64_t>(ns); ++si) {
    const std::int64_t c = cells[si];
    const std::int64_t cx = c % cg.shape[0], cy = (c / cg.shape[0]) % cg.shape[1], cz = c / (std::int64_t(cg.shape[0]) * cg.shape[1]);
    const std::int64_t idx[3] = {cx, cy, cz};
    double M = 0.0, P[3] = {0, 0, 0};
    std::fill(fsum.begin(), fsum.end(), 0.0);
    for (std::size_t q = start[c]; q < start[c + 1]; ++q) {
      const std::size_t p = order[q];
      std::size_t local = 0;
      for (int d = 2; d >= 0; --d) {
        const int fi = std::clamp(static_cast<int>(std::floor((s.position[3 * p + d] - g.origin[d]) / h)), 0, g.shape[d] - 2);
        local = local * k + static_cast<std::size_t>(fi - idx[d] * k);
      }
      if (!mark[local]) {
        mark[local] = 1;
        marked.push_back(local);
      }
      double vt[3] = {0, 0, 0};
      for_each_weight(weights(p), g, [&](std::size_t ni, double w) {
        const double* nd = &node[4 * ni];
        vt[0] += w * nd[1];
        vt[1] += w * nd[2];
        vt[2] += w * nd[3];
      });
      const double m = s.mass[p];
      M += m;
      for (int d = 0; d < 3; ++d) P[d] += m * vt[d];
      for (std::size_t f = 0; f < carry.size(); ++f) fsum[f] += m * carry[f]->values[p];
      r.map.particle_id[q] = s.id[p];
    }
    occupied += marked.size();
    for (std::size_t i : marked) mark[i] = 0;
    marked.clear();
    out.id[si] = static_cast<std::uint64_t>(si);
    out.mass[si] = M;
    for (int d = 0; d < 3; ++d) {
      out.position[3 * si + d] = cg.origin[d] + (idx[d] + 0.5) * cg.edge;
      out.velocity[3 * si + d] = P[d] / M;
    }
    for (std::size_t f = 0; f < carry.size(); ++f) out.fields[f].values[si] = fsum[f] / M;
    r.map.offset[si] = start[c];
  }
  }
  r.map.offset[ns] = n;
  r.occupied_mpm_cells = occupied;
  return r;
}

}  // namespace handoff
