/// @file projection.cpp
/// Implementation of handoff/projection.hpp (the header states the contract, and for physics the equations and sources).
#include "handoff/projection.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <sstream>

#include "common/huge_pages.hpp"
#include "common/status.hpp"
#include "kernel_types.hpp"

namespace handoff {

namespace {

using detail::CoarseGrid;
using detail::Lattice;

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
  out.resize(ns);  // spins stay zero: the paper's hand-off gives spheres no spin
  std::fill(out.radius.begin(), out.radius.end(), 0.5 * cg.edge);
  for (const auto* f : carry) out.fields.push_back({f->name, f->unit, 1, std::vector<double>(ns), "mass-weighted mean over the sphere's particles"});
  r.map.offset.resize(ns + 1);
  r.map.particle_id.resize(n);

  common::huge_buffer<double> node(4 * mpmfrag::node_count(g));  // m, px, py, pz
#pragma omp parallel for schedule(static)  // zeroed in parallel: first-touch faults shared
  for (std::int64_t i = 0; i < static_cast<std::int64_t>(node.size()); ++i) node[i] = 0.0;
  const detail::KernelArgs args{s, L, cg, k, start, order, carry, cells, node, r};
  if (opt.vector_kernels && detail::run_kernels_avx2(opt.shape, args)) {
    r.kernels = "avx2";
  } else {
    detail::run_kernels_portable(opt.shape, args);
    r.kernels = "portable";
  }
  r.map.offset[ns] = n;
  r.cell = std::move(cells);
  return r;
}

bool vector_kernels_available() { return detail::avx2_kernels_available(); }

}  // namespace handoff
