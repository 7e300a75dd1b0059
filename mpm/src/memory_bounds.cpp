/// @file memory_bounds.cpp
/// Memory estimate and check of an mpm-frag scene (memory_bounds.hpp).
#include "mpm/memory_bounds.hpp"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <numbers>
#include <string>

#include "common/status.hpp"
#include "mpm/particles.hpp"

namespace mpmfrag {
namespace {

double body_volume(const common::Scene& b, double domain_volume) {
  const std::string shape = b.string("shape");
  if (shape == "sphere") return 4.0 / 3.0 * std::numbers::pi * std::pow(b.real("radius"), 3);
  if (shape == "box") return (b.vec3("max") - b.vec3("min")).cwiseMax(0.0).prod();
  if (shape == "cylinder") return std::numbers::pi * std::pow(b.real("radius"), 2) * b.real("length");
  return domain_volume;  // a shape added later: bounded by the domain
}

std::string gigabytes(double bytes) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g GB", bytes / 1e9);
  return buf;
}

}  // namespace

namespace {
double array_bytes_per_particle() {
  double b = 0;
  ParticleSet::for_each_array([&](const auto& a) {
    using T = typename std::decay_t<decltype(a)>::element_type;
    b += static_cast<double>(sizeof(T) * a.info.width);
  });
  return b;
}
}  // namespace

double process_bytes(double nodes, const std::vector<MaterialSlot>& mats) {
  double b = 88.0 * nodes;
  const double arrays = array_bytes_per_particle();
  for (const MaterialSlot& m : mats) {
    double state = 0;
    if (m.style)
      for (const StateField& f : m.style->state_fields) state += 8.0 * f.ncomp;
    b += static_cast<double>(m.end - m.begin) * (2 * (arrays + state) + 96);
  }
  return b;
}

MemoryEstimate estimate_memory(const common::Scene& sc, const MaterialRegistry& reg) {
  MemoryEstimate e;
  const Eigen::Vector3d lo = sc.vec3("grid.domain_min"), hi = sc.vec3("grid.domain_max");
  const double h = sc.real("grid.cell_size");
  const double ghost = static_cast<double>(sc.integer("grid.ghost_layers"));
  e.grid_nodes = 1;
  for (int d = 0; d < 3; ++d) e.grid_nodes *= std::ceil(std::max(0.0, hi[d] - lo[d]) / h) + 1 + 2 * ghost;
  e.grid_bytes = 88.0 * e.grid_nodes;
  const double array_bytes = array_bytes_per_particle();
  const double domain_volume = (hi - lo).cwiseMax(0.0).prod();
  for (std::size_t i = 0; i < sc.count("body"); ++i) {
    const common::Scene b = sc.element("body", i);
    const double ppc = static_cast<double>(b.integer("ppc"));
    const double n = body_volume(b, domain_volume) * std::pow(ppc / h, 3);
    double state = 0;
    for (std::size_t m = 0; m < sc.count("material"); ++m) {
      const common::Scene mat = sc.element("material", m);
      if (mat.string("name") != b.string("material")) continue;
      if (const StyleInfo* s = reg.find(mat.string("model")))
        for (const StateField& f : s->state_fields) state += 8.0 * f.ncomp;
    }
    e.particles += n;
    e.particle_bytes += n * (2 * (array_bytes + state) + 96);
  }
  return e;
}

double process_memory_limit() {
  rlimit rl{};
  if (getrlimit(RLIMIT_AS, &rl) == 0 && rl.rlim_cur != RLIM_INFINITY) return static_cast<double>(rl.rlim_cur);
  return std::numeric_limits<double>::infinity();
}

double available_memory() { return std::min(node_memory(), process_memory_limit()); }

double node_memory() {
  double avail = static_cast<double>(sysconf(_SC_PHYS_PAGES)) * static_cast<double>(sysconf(_SC_PAGE_SIZE));
  std::ifstream cg("/sys/fs/cgroup/memory.max");
  std::string v;
  if (cg >> v && v != "max") {
    try {
      avail = std::min(avail, std::stod(v));
    } catch (...) {
    }
  }
  return avail;
}

void check_memory(const common::Scene& sc, double available, const MaterialRegistry& reg, int ranks, int ranks_here) {
  const MemoryEstimate e = estimate_memory(sc, reg);
  if (e.particles >= 4294967295.0)
    throw common::InputError(sc.source(), "grid.cell_size",
                             "the bodies would hold about " + std::to_string(static_cast<long long>(e.particles)) +
                                 " particles at this cell size and their ppc (at most 2^32 - 1)");
  const double share = static_cast<double>(std::max(ranks_here, 1)) / static_cast<double>(std::max(ranks, 1));
  if (e.total() * share > available) {
    char nodes[32];
    std::snprintf(nodes, sizeof nodes, "%.3g", e.grid_nodes);
    char parts[32];
    std::snprintf(parts, sizeof parts, "%.3g", e.particles);
    throw common::InputError(sc.source(), "grid.cell_size",
                             "the grid over grid.domain_min .. grid.domain_max at this cell size has " +
                                 std::string(nodes) + " nodes (" + gigabytes(e.grid_bytes) + ") and the bodies about " +
                                 parts + " particles (" + gigabytes(e.particle_bytes) + "): " + gigabytes(e.total()) +
                                 " in all" +
                                 (ranks > 1 ? ", " + gigabytes(e.total() * share) + " for the " + std::to_string(ranks_here) +
                                                  " of " + std::to_string(ranks) + " MPI ranks on this node"
                                            : std::string()) +
                                 ", more than the " + gigabytes(available) + " of memory available");
  }
}

}  // namespace mpmfrag
