/// @file gravity_cadence.cpp
/// Error-controlled gravity cadence (gravity_cadence.hpp, simulation.hpp).
#include "ssdem/gravity_cadence.hpp"

#include <algorithm>
#include <cmath>

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

}  // namespace ssdem
