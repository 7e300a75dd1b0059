/// @file outflow.cpp
/// Hand-off of the particles that left the MPM grid (equations in outflow.hpp).
#include "handoff/outflow.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>

#include "common/status.hpp"

namespace handoff {

std::size_t append_outflow(const common::ParticleSnapshot& out, const common::GridInfo& grid, double t,
                           ProjectionResult& r, const std::string& file) {
  const std::size_t n = out.count();
  if (n == 0) return 0;
  for (int d = 0; d < 3; ++d) {
    const double h = grid.cell_size[d];
    if (out.grid.shape[d] != grid.shape[d] || std::fabs(out.grid.origin[d] - grid.origin[d]) > 1e-9 * h ||
        std::fabs(out.grid.cell_size[d] - h) > 1e-12 * h)
      throw common::InputError(file, "/grid", "the outflow file was written on a different grid than the snapshot");
  }
  common::SphereSet& sph = r.spheres;
  std::vector<const common::Field*> carry;
  for (const common::Field& f : sph.fields) {
    const common::Field* g = out.field(f.name);
    if (!g || g->ncomp != 1)
      throw common::InputError(file, "/particles/" + f.name, "scalar field carried onto the spheres is missing");
    carry.push_back(g);
  }
  const std::size_t n_grid = r.cell.size();
  const double edge = r.sphere_cell;
  const Eigen::Vector3i sh = r.cell_shape;
  // Bin each particle: into an existing projection sphere (by its cell key) or a new lattice cell.
  std::vector<std::vector<std::size_t>> merged(n_grid);
  std::map<std::array<std::int64_t, 3>, std::vector<std::size_t>> fresh;
  for (std::size_t p = 0; p < n; ++p) {
    std::array<std::int64_t, 3> c;
    bool inside = true;
    for (int d = 0; d < 3; ++d) {
      const double x = out.position[3 * p + d] + out.velocity[3 * p + d] * (t - out.time);
      c[d] = static_cast<std::int64_t>(std::floor((x - grid.origin[d]) / edge));
      inside = inside && c[d] >= 0 && c[d] < sh[d];
    }
    if (inside) {
      const std::int64_t key = c[0] + std::int64_t(sh[0]) * (c[1] + std::int64_t(sh[1]) * c[2]);
      const auto it = std::lower_bound(r.cell.begin(), r.cell.end(), key);
      if (it != r.cell.end() && *it == key) {
        merged[static_cast<std::size_t>(it - r.cell.begin())].push_back(p);
        continue;
      }
    }
    fresh[c].push_back(p);
  }
  // Merge into projection spheres (mass-weighted velocity and fields; position stays the centre).
  for (std::size_t s = 0; s < n_grid; ++s) {
    if (merged[s].empty()) continue;
    double M = sph.mass[s], P[3];
    for (int d = 0; d < 3; ++d) P[d] = M * sph.velocity[3 * s + d];
    std::vector<double> F(carry.size());
    for (std::size_t f = 0; f < carry.size(); ++f) F[f] = M * sph.fields[f].values[s];
    for (std::size_t p : merged[s]) {
      const double m = out.mass[p];
      M += m;
      for (int d = 0; d < 3; ++d) P[d] += m * out.velocity[3 * p + d];
      for (std::size_t f = 0; f < carry.size(); ++f) F[f] += m * carry[f]->values[p];
    }
    sph.mass[s] = M;
    for (int d = 0; d < 3; ++d) sph.velocity[3 * s + d] = P[d] / M;
    for (std::size_t f = 0; f < carry.size(); ++f) sph.fields[f].values[s] = F[f] / M;
  }
  // New spheres at the centres of the outside cells.
  const double radius = 0.5 * edge;
  std::uint64_t next_id = 0;
  for (std::uint64_t id : sph.id) next_id = std::max(next_id, id + 1);
  for (const auto& [c, members] : fresh) {
    double M = 0.0, P[3] = {0, 0, 0};
    std::vector<double> F(carry.size(), 0.0);
    for (std::size_t p : members) {
      const double m = out.mass[p];
      M += m;
      for (int d = 0; d < 3; ++d) P[d] += m * out.velocity[3 * p + d];
      for (std::size_t f = 0; f < carry.size(); ++f) F[f] += m * carry[f]->values[p];
    }
    sph.id.push_back(next_id++);
    sph.mass.push_back(M);
    sph.radius.push_back(radius);
    for (int d = 0; d < 3; ++d) {
      sph.position.push_back(grid.origin[d] + (static_cast<double>(c[d]) + 0.5) * edge);
      sph.velocity.push_back(P[d] / M);
      sph.spin.push_back(0.0);
    }
    for (std::size_t f = 0; f < carry.size(); ++f) sph.fields[f].values.push_back(F[f] / M);
  }
  // Rebuild the sphere -> particle map with the outflow ids.
  SphereParticleMap map;
  map.offset.reserve(sph.count() + 1);
  map.particle_id.reserve(r.map.particle_id.size() + n);
  for (std::size_t s = 0; s < n_grid; ++s) {
    map.offset.push_back(map.particle_id.size());
    map.particle_id.insert(map.particle_id.end(), r.map.particle_id.begin() + r.map.offset[s],
                           r.map.particle_id.begin() + r.map.offset[s + 1]);
    for (std::size_t p : merged[s]) map.particle_id.push_back(out.id[p]);
  }
  for (const auto& [c, members] : fresh) {
    map.offset.push_back(map.particle_id.size());
    for (std::size_t p : members) map.particle_id.push_back(out.id[p]);
  }
  map.offset.push_back(map.particle_id.size());
  r.map = std::move(map);
  return fresh.size();
}

}  // namespace handoff
