/// @file material_registry.cpp
/// The explicit registry of material styles (no static self-registration) and shared kinematic
/// helpers. Hughes–Winget incremental rotation: Hughes & Winget 1980, IJNME 15:1862, eq. (31):
/// R = (I - W dt/2)^{-1} (I + W dt/2), W = (L - L^T)/2; sigma_rot = R sigma R^T.
#include <Eigen/Dense>
#include <stdexcept>

#include "mpm/material.hpp"
#include "mpm/materials/builtin.hpp"
#include "mpm/tonge_ramesh/style.hpp"

namespace mpmfrag {

void MaterialRegistry::add(StyleInfo info) {
  if (styles_.count(info.name)) throw std::invalid_argument("material style '" + info.name + "' registered twice");
  std::string key = info.name;
  styles_.emplace(std::move(key), std::move(info));
}

const StyleInfo* MaterialRegistry::find(const std::string& name) const {
  auto it = styles_.find(name);
  return it == styles_.end() ? nullptr : &it->second;
}

std::vector<std::string> MaterialRegistry::names() const {
  std::vector<std::string> out;
  for (const auto& kv : styles_) out.push_back(kv.first);
  return out;
}

std::map<std::string, common::Schema> MaterialRegistry::schemas() const {
  std::map<std::string, common::Schema> out;
  for (const auto& kv : styles_) out.emplace(kv.first, kv.second.schema);
  return out;
}

void register_builtin_materials(MaterialRegistry& reg) {
  register_elastic(reg);
  register_neo_hookean(reg);
  register_tillotson(reg);
  register_tonge_ramesh(reg);
  // Plug-in styles: one line each, e.g. register_tonge_ramesh(reg);
}

const MaterialRegistry& builtin_materials() {
  static const MaterialRegistry reg = [] {
    MaterialRegistry r;
    register_builtin_materials(r);
    return r;
  }();
  return reg;
}

void rotate_stress_hughes_winget(double* v, const double* L, double dt) {
  using M3 = Eigen::Matrix3d;
  const Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> Lm(L);
  const M3 W = 0.5 * (Lm - Lm.transpose()) * dt;
  if (W.cwiseAbs().maxCoeff() == 0.0) return;
  const M3 I = M3::Identity();
  const M3 R = (I - 0.5 * W).inverse() * (I + 0.5 * W);
  M3 s;
  s << v[0], v[5], v[4], v[5], v[1], v[3], v[4], v[3], v[2];
  const M3 r = R * s * R.transpose();
  v[0] = r(0, 0);
  v[1] = r(1, 1);
  v[2] = r(2, 2);
  v[3] = 0.5 * (r(1, 2) + r(2, 1));
  v[4] = 0.5 * (r(0, 2) + r(2, 0));
  v[5] = 0.5 * (r(0, 1) + r(1, 0));
}

}  // namespace mpmfrag
