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
  for (const StateField& f : info.state_fields)
    if (f.work > 0.0 && f.ncomp != 1)  // work_weights reads one value per particle
      throw std::invalid_argument("material style '" + info.name + "': cost field '" + f.name + "' must have one component");
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
  // A = W dt / 2 with W = (L - L^T)/2; axial vector a: A x = a x x, so A = [[0,-a2,a1],[a2,0,-a0],[-a1,a0,0]].
  const double a0 = 0.25 * dt * (L[7] - L[5]);  // A(2,1) = (L21 - L12) dt / 4
  const double a1 = 0.25 * dt * (L[2] - L[6]);  // A(0,2)
  const double a2 = 0.25 * dt * (L[3] - L[1]);  // A(1,0)
  const double t2 = a0 * a0 + a1 * a1 + a2 * a2;
  if (t2 == 0.0) return;
  // Cayley transform: R = (I - A)^{-1} (I + A) = I + 2/(1 + |a|^2) (A + A^2), A^2 = a a^T - |a|^2 I
  const double c = 2.0 / (1.0 + t2);
  double R[9] = {1 + c * (a0 * a0 - t2), c * (-a2 + a0 * a1), c * (a1 + a0 * a2),
                 c * (a2 + a1 * a0), 1 + c * (a1 * a1 - t2), c * (-a0 + a1 * a2),
                 c * (-a1 + a2 * a0), c * (a0 + a2 * a1), 1 + c * (a2 * a2 - t2)};
  const double S[9] = {v[0], v[5], v[4], v[5], v[1], v[3], v[4], v[3], v[2]};
  double T[9];  // T = R S
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) T[3 * i + j] = R[3 * i] * S[j] + R[3 * i + 1] * S[3 + j] + R[3 * i + 2] * S[6 + j];
  auto rs = [&](int i, int j) { return T[3 * i] * R[3 * j] + T[3 * i + 1] * R[3 * j + 1] + T[3 * i + 2] * R[3 * j + 2]; };
  v[0] = rs(0, 0);
  v[1] = rs(1, 1);
  v[2] = rs(2, 2);
  v[3] = rs(1, 2);
  v[4] = rs(0, 2);
  v[5] = rs(0, 1);
}

}  // namespace mpmfrag
