/// @file shape_functions.cpp
/// Non-inline parts of the uGIMP / linear interpolation API (see shape_functions.hpp for the
/// governing equations: Bardenhagen & Kober 2004; Sulsky et al. 1994).
#include "mpm/shape_functions.hpp"

#include <stdexcept>

namespace mpmfrag {

ShapeKind parse_shape_kind(const std::string& name) {
  if (const auto k = common::choice_value(kShapeKinds, name)) return *k;
  if (name == "gimp") return ShapeKind::ugimp;
  throw std::invalid_argument("unknown shape function '" + name + "' (ugimp, linear)");
}

const char* shape_kind_name(ShapeKind k) { return common::choice_name(kShapeKinds, k).data(); }

std::vector<StencilNode> stencil_nodes(ShapeKind kind, const common::GridInfo& grid,
                                       const Eigen::Vector3d& x, const Eigen::Vector3d& lp) {
  std::vector<StencilNode> out;
  out.reserve(27);
  const ParticleStencil s = compute_stencil(kind, grid, x, lp);
  for_each_node(s, [&](int i, int j, int k, double w, const Eigen::Vector3d& g) {
    if (w != 0.0 || g.squaredNorm() != 0.0) out.push_back({Eigen::Vector3i(i, j, k), w, g});
  });
  return out;
}

}  // namespace mpmfrag
