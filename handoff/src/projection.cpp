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
};

/// One particle's stencil for the projection: the first node's linear index and the per-axis
/// weights (mpmfrag::axis_weights_only, the solver's S(d) evaluated without branches).
template <mpmfrag::ShapeKind K>
struct Stencil {
  static constexpr int N = K == mpmfrag::ShapeKind::ugimp ? 3 : 2;  // nodes per axis
  std::size_t base;
  double w[3][N];  // w[axis][node]
};

/// Grid constants of the kernels.
struct Lattice {
  Eigen::Vector3d origin;
  double inv_h;
  std::size_t sy, sz;  // node strides in y and z
  std::size_t size_stride = 3;  // 0 when every particle has the first one's size: the kernels then
                                // read one cached triple instead of streaming 24 B per particle
};

/// The particle half-widths in cell units, l = size / (2 h), and 1/(4 l), kept from the previous
/// particle: particles of one body share their size, so the three divisions are rarely repeated.
struct HalfWidths {
  double size[3] = {-1.0, -1.0, -1.0};
  double l[3] = {1.0, 1.0, 1.0}, inv4l[3] = {0.25, 0.25, 0.25};
  [[gnu::always_inline]] void update(const double* sz, double inv_h) {
    if (sz[0] == size[0] && sz[1] == size[1] && sz[2] == size[2]) return;
    for (int d = 0; d < 3; ++d) {
      size[d] = sz[d];
      l[d] = 0.5 * sz[d] * inv_h;
      inv4l[d] = 0.25 / l[d];
    }
  }
};

template <mpmfrag::ShapeKind K>
[[gnu::always_inline]] inline Stencil<K> stencil_of(const double* x, const double* size, const Lattice& g, HalfWidths& hw) {
  Stencil<K> st;
  hw.update(size, g.inv_h);
  std::size_t base = 0;
  const std::size_t stride[3] = {1, g.sy, g.sz};
  for (int d = 0; d < 3; ++d) {
    const mpmfrag::AxisWeightsOnly a = mpmfrag::axis_weights_only<K>(x[d], g.origin[d], g.inv_h, hw.l[d], hw.inv4l[d]);
    base += static_cast<std::size_t>(a.first) * stride[d];
    for (int k = 0; k < Stencil<K>::N; ++k) st.w[d][k] = a.w[k];
  }
  st.base = base;
  return st;
}

/// P2G of one particle: node (m, px, py, pz) += S_ip m_p (1, v_p). Zero weights are added too
/// (every stencil node lies inside the grid): no branches in the 27-node loop.
template <mpmfrag::ShapeKind K>
[[gnu::always_inline]] inline void scatter(const Stencil<K>& st, const Lattice& g, double m, const double* v, double* node) {
  constexpr int N = Stencil<K>::N;
  const double v0 = v[0], v1 = v[1], v2 = v[2];
  for (int c = 0; c < N; ++c)
    for (int b = 0; b < N; ++b) {
      const double myz = m * st.w[1][b] * st.w[2][c];
      double* row = node + 4 * (st.base + b * g.sy + c * g.sz);
      for (int a = 0; a < N; ++a) {
        const double mw = st.w[0][a] * myz;
        row[4 * a] += mw;
        row[4 * a + 1] += mw * v0;
        row[4 * a + 2] += mw * v1;
        row[4 * a + 3] += mw * v2;
      }
    }
}

/// G2P of one particle: sum_i S_ip v_i (node layout m, vx, vy, vz).
template <mpmfrag::ShapeKind K>
[[gnu::always_inline]] inline void gather(const Stencil<K>& st, const Lattice& g, const double* node, double* vt) {
  constexpr int N = Stencil<K>::N;
  double s0 = 0.0, s1 = 0.0, s2 = 0.0;
  for (int c = 0; c < N; ++c)
    for (int b = 0; b < N; ++b) {
      const double wyz = st.w[1][b] * st.w[2][c];
      const double* row = node + 4 * (st.base + b * g.sy + c * g.sz);
      for (int a = 0; a < N; ++a) {
        const double w = st.w[0][a] * wyz;
        s0 += w * row[4 * a + 1];
        s1 += w * row[4 * a + 2];
        s2 += w * row[4 * a + 3];
      }
    }
  vt[0] = s0;
  vt[1] = s1;
  vt[2] = s2;
}

std::string where_particle(const common::ParticleSnapshot& s, std::size_t p) {
  std::ostringstream o;
  o.precision(9);
  o << "particle id " << s.id[p] << " at (" << s.position[3 * p] << ", " << s.position[3 * p + 1] << ", "
    << s.position[3 * p + 2] << ")";
  return o.str();
}

/// Steps 2 and 3 of project_to_spheres for one shape kind (the kernels are compiled per kind).
template <mpmfrag::ShapeKind K>
void project_kernels(const common::ParticleSnapshot& s, const Lattice& L, const CoarseGrid& cg, int k,
                     const std::vector<std::size_t>& start, const common::huge_buffer<std::uint32_t>& order,
                     const std::vector<const common::Field*>& carry, const std::vector<std::int64_t>& cells,
                     common::huge_buffer<double>& node, ProjectionResult& r) {
  const std::size_t nn = node.size() / 4;
  const std::size_t n = s.count();
  // Software prefetch of the particle data kAhead particles ahead in the sorted order: the cell
  // order reads each particle array as several interleaved streams, too many for the hardware
  // prefetcher once the input is not in the hand-off's order.
  constexpr std::size_t kAhead = 32;
  // 2. P2G, parallel over slabs of sphere-cell z layers, two colours so that no two threads
  //    touch the same node; sums run in sorted order, so results do not depend on threads.
  //    (A uGIMP stencil spans 3 node layers: a slab of ceil(3/k) sphere layers covers them.)
  const int layers_per_slab = (3 + k - 1) / k;
  const std::int64_t layer_cells = std::int64_t(cg.shape[0]) * cg.shape[1];
  const int nslab = (cg.shape[2] + layers_per_slab - 1) / layers_per_slab;
  for (int colour = 0; colour < 2; ++colour) {
#pragma omp parallel for schedule(dynamic, 1)
    for (int sl = colour; sl < nslab; sl += 2) {
      const std::int64_t z0 = std::int64_t(sl) * layers_per_slab;
      const std::int64_t z1 = std::min<std::int64_t>(z0 + layers_per_slab, cg.shape[2]);
      HalfWidths hw;
      const std::size_t qe = start[z1 * layer_cells];
      for (std::size_t q = start[z0 * layer_cells]; q < qe; ++q) {
        if (q + kAhead < qe) {
          const std::size_t pa = order[q + kAhead];
          __builtin_prefetch(&s.position[3 * pa]);
          __builtin_prefetch(&s.velocity[3 * pa]);
          __builtin_prefetch(&s.size[L.size_stride * pa]);
          __builtin_prefetch(&s.mass[pa]);
        }
        const std::size_t p = order[q];
        scatter<K>(stencil_of<K>(&s.position[3 * p], &s.size[L.size_stride * p], L, hw), L, s.mass[p], &s.velocity[3 * p], node.data());
      }
    }
  }
  // Nodal velocities in place.
#pragma omp parallel for schedule(static)
  for (std::int64_t i = 0; i < static_cast<std::int64_t>(nn); ++i) {
    double* nd = &node[4 * i];
    if (nd[0] > 0.0) {
      const double inv = 1.0 / nd[0];
      nd[1] *= inv;
      nd[2] *= inv;
      nd[3] *= inv;
    }
  }

  // 3. One sphere per occupied cell: G2P at the cell's particles, mass-weighted average.
  common::SphereSet& out = r.spheres;
  const std::size_t ns = cells.size();
  // With k > 1, occupied MPM cells are counted per sphere cell (its k^3 fine cells, marked in a
  // per-thread table that is cleared through the list of marks); with k = 1 they are the spheres.
  std::size_t occupied = 0;
#pragma omp parallel reduction(+ : occupied)
  {
  std::vector<double> fsum(carry.size());
  std::vector<unsigned char> mark(k > 1 ? static_cast<std::size_t>(k) * k * k : 0, 0);
  std::vector<std::size_t> marked;
  HalfWidths hw;
#pragma omp for schedule(dynamic, 64)
  for (std::int64_t si = 0; si < static_cast<std::int64_t>(ns); ++si) {
    const std::int64_t c = cells[si];
    const std::int64_t cx = c % cg.shape[0], cy = (c / cg.shape[0]) % cg.shape[1], cz = c / (std::int64_t(cg.shape[0]) * cg.shape[1]);
    const std::int64_t idx[3] = {cx, cy, cz};
    double M = 0.0, P[3] = {0, 0, 0};
    std::fill(fsum.begin(), fsum.end(), 0.0);
    for (std::size_t q = start[c]; q < start[c + 1]; ++q) {
      if (q + kAhead < n) {
        const std::size_t pa = order[q + kAhead];
        __builtin_prefetch(&s.position[3 * pa]);
        __builtin_prefetch(&s.size[L.size_stride * pa]);
        __builtin_prefetch(&s.mass[pa]);
        __builtin_prefetch(&s.id[pa]);
        for (const common::Field* f : carry) __builtin_prefetch(&f->values[pa]);
      }
      const std::size_t p = order[q];
      const double* x = &s.position[3 * p];
      if (k > 1) {
        std::size_t local = 0;
        for (int d = 2; d >= 0; --d) {
          const int fi = std::clamp(common::floor_to_int((x[d] - L.origin[d]) * L.inv_h), 0, s.grid.shape[d] - 2);
          local = local * k + static_cast<std::size_t>(fi - idx[d] * k);
        }
        if (!mark[local]) {
          mark[local] = 1;
          marked.push_back(local);
        }
      }
      double vt[3];
      gather<K>(stencil_of<K>(x, &s.size[L.size_stride * p], L, hw), L, node.data(), vt);
      const double m = s.mass[p];
      M += m;
      for (int d = 0; d < 3; ++d) P[d] += m * vt[d];
      for (std::size_t f = 0; f < carry.size(); ++f) fsum[f] += m * carry[f]->values[p];
      r.map.particle_id[q] = s.id[p];
    }
    occupied += k > 1 ? marked.size() : 1;
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
  r.occupied_mpm_cells = occupied;
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
  if (cg.cells() >= (std::int64_t(1) << 32))
    throw common::InputError(file, "/grid/shape", "more than 2^32 sphere cells (use a larger coarsen)");
  if (n >= std::size_t(1) << 32) throw common::InputError(file, "/particles", "more than 2^32 particles in one hand-off");
  Lattice L{g.origin, 1.0 / h, static_cast<std::size_t>(g.shape[0]),
                  static_cast<std::size_t>(g.shape[0]) * static_cast<std::size_t>(g.shape[1])};

  // Carried fields (scalar only).
  std::vector<const common::Field*> carry;
  for (const auto& name : opt.carry_fields) {
    const common::Field* f = s.field(name);
    if (!f) throw common::InputError(file, "/particles/" + name, "field to carry onto spheres is missing");
    if (f->ncomp != 1) throw common::InputError(file, "/particles/" + name, "only scalar fields can be carried");
    carry.push_back(f);
  }

  // 1. Validate and bin particles by sphere cell (parallel keys; the first offending particle in
  //    index order is reported, whatever the thread count). The node choice is computed exactly as
  //    in mpmfrag::axis_weights_only (same xi), so a stencil that passes here is the one used below.
  //    Work arrays on transparent huge pages (common/huge_pages.hpp): first-touch faults dominate a
  //    one-shot call otherwise.
  common::huge_buffer<std::uint32_t> key(n);
  std::size_t first_big = n, first_out = n;
  bool uniform_size = true;
  const bool linear = opt.shape == mpmfrag::ShapeKind::linear;
#pragma omp parallel for schedule(static) reduction(min : first_big, first_out) reduction(&& : uniform_size)
  for (std::size_t p = 0; p < n; ++p) {
    bool big = false, inside = true;
    std::uint32_t c[3];
    for (int d = 0; d < 3; ++d) {
      big = big || !(s.size[3 * p + d] > 0.0 && s.size[3 * p + d] <= h * (1 + 1e-12));
      uniform_size = uniform_size && s.size[3 * p + d] == s.size[d];
      // Stencil bounds without the weights: uGIMP uses nodes {i-1, i, i+1} or {i, i+1, i+2}, linear {i, i+1}.
      const double xi = (s.position[3 * p + d] - g.origin[d]) * L.inv_h;
      const bool finite = std::fabs(xi) < 1e9;  // false for NaN and Inf
      const int i = finite ? common::floor_to_int(xi) : -2;
      const int first = linear ? i : (xi - i <= 0.5 ? i - 1 : i);
      inside = inside && finite && first >= 0 && first + (linear ? 2 : 3) <= g.shape[d];
      c[d] = inside ? static_cast<std::uint32_t>(std::clamp(i, 0, g.shape[d] - 2) / k) : 0u;
    }
    if (big) first_big = std::min(first_big, p);
    if (!inside) first_out = std::min(first_out, p);
    key[p] = c[0] + static_cast<std::uint32_t>(cg.shape[0]) * (c[1] + static_cast<std::uint32_t>(cg.shape[1]) * c[2]);
  }
  if (first_big < n && first_big <= first_out)
    throw common::InputError(file, "/particles/size", where_particle(s, first_big) + ": particle size must lie in (0, cell size " + std::to_string(h) + " m]");
  if (first_out < n)
    throw common::InputError(file, "/particles/position", where_particle(s, first_out) + " lies outside the grid (its shape-function support leaves it)");
  if (uniform_size) L.size_stride = 0;
  // Counting sort by cell (stable: index order within a cell).
  std::vector<std::size_t> start(static_cast<std::size_t>(cg.cells()) + 1, 0);
  for (std::size_t p = 0; p < n; ++p) ++start[key[p] + 1];
  for (std::size_t c = 0; c + 1 < start.size(); ++c) start[c + 1] += start[c];
  common::huge_buffer<std::uint32_t> order(n);  // 32-bit: half the memory traffic of size_t
  {
    std::vector<std::size_t> fill(start.begin(), start.end() - 1);
    for (std::size_t p = 0; p < n; ++p) order[fill[key[p]]++] = static_cast<std::uint32_t>(p);
  }

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
  r.map.offset.resize(ns + 1);
  r.map.particle_id.resize(n);

  common::huge_buffer<double> node(4 * mpmfrag::node_count(g));  // m, px, py, pz
#pragma omp parallel for schedule(static)  // zeroed in parallel: first-touch faults shared
  for (std::int64_t i = 0; i < static_cast<std::int64_t>(node.size()); ++i) node[i] = 0.0;
  if (linear)
    project_kernels<mpmfrag::ShapeKind::linear>(s, L, cg, k, start, order, carry, cells, node, r);
  else
    project_kernels<mpmfrag::ShapeKind::ugimp>(s, L, cg, k, start, order, carry, cells, node, r);
  r.map.offset[ns] = n;
  r.cell = std::move(cells);
  return r;
}

}  // namespace handoff
