/// @file gravity_cadence.cpp
/// Error-controlled gravity cadence (gravity_cadence.hpp, simulation.hpp).
#include "ssdem/gravity_cadence.hpp"

#include <algorithm>
#include <cmath>

#include "omp_team.hpp"

namespace ssdem {

int next_gravity_block(int k, double g2, double d2, double cmax, const SimConfig& cfg, CadenceStats& st) {
  const double c = g2 > 0 ? std::sqrt(d2 / g2) : 0.0;
  const double r = std::max(c / cfg.gravity_tolerance, cmax / kCadenceMaxChange);
  const double grow = r > 0 ? static_cast<double>(k) / r : 2.0 * k;
  st.max_change_one = std::max(st.max_change_one, cmax);
  const int next = static_cast<int>(
      std::clamp(std::floor(grow), 1.0, static_cast<double>(std::min(2 * k, cfg.gravity_max_every))));
  ++st.blocks;
  st.steps += k;
  st.min_block = st.blocks == 1 ? k : std::min<std::int64_t>(st.min_block, k);
  st.max_block = std::max<std::int64_t>(st.max_block, k);
  st.max_change = std::max(st.max_change, c);
  st.sum_change += c;
  return next;
}

common::ExactSum cadence_g2(const std::vector<Vec3>& g, const std::vector<std::uint32_t>* idx) {
  const std::size_t n = idx ? idx->size() : g.size();
  common::ExactSum total;
  in_team(use_team(n), [&] {
    common::ExactSum part;  // per thread; merging is exact, so the order of the merges is free
#pragma omp for schedule(static) nowait
    for (std::size_t k = 0; k < n; ++k) part += g[idx ? (*idx)[k] : k].squaredNorm();
#pragma omp critical(cadence_sum)
    total.merge(part);
  });
  return total;
}

void cadence_change(const std::vector<Vec3>& g, const std::vector<Vec3>& g_old, double floor,
                    const std::vector<std::uint32_t>* idx, common::ExactSum& d2, double& cmax) {
  const std::size_t n = idx ? idx->size() : g.size();
  double mx = 0.0;
  in_team(use_team(n), [&] {
    common::ExactSum part;
    double lmx = 0.0;
#pragma omp for schedule(static) nowait
    for (std::size_t k = 0; k < n; ++k) {
      const std::size_t i = idx ? (*idx)[k] : k;
      const double d = (g[i] - g_old[i]).norm();
      part += d * d;
      lmx = std::max(lmx, d / std::max({g[i].norm(), floor, 1e-300}));
    }
#pragma omp critical(cadence_sum)
    {
      d2.merge(part);
      mx = std::max(mx, lmx);  // (a maximum: the order of the merges is free)
    }
  });
  cmax = std::max(cmax, mx);
}

}  // namespace ssdem
