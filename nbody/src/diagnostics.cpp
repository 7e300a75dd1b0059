/// @file diagnostics.cpp
/// Exact sums of the series row's quantities (diagnostics.hpp).
#include "ssdem/diagnostics.hpp"

#include <Eigen/Geometry>

namespace ssdem {

void DiagnosticSums::add_sphere(const Spheres& sp, std::size_t i, bool rotation, const double* pot, const Vec3& g) {
  const double m = sp.m[i];
  kinetic += 0.5 * m * sp.v[i].squaredNorm();
  if (rotation) rotational += 0.5 * sp.inertia(i) * sp.w[i].squaredNorm();
  if (pot) potential_self += 0.5 * m * *pot;
  potential_uniform += -(m * g.dot(sp.x[i]));
  dissipated += sp.dissipated[i];
  const Vec3 p = m * sp.v[i];
  const Vec3 l = m * sp.x[i].cross(sp.v[i]) + sp.inertia(i) * sp.w[i];
  for (int k = 0; k < 3; ++k) {
    momentum[k] += p[k];
    angular_momentum[k] += l[k];
  }
}

void DiagnosticSums::store(Diagnostics& d) const {
  d.kinetic = kinetic.value();
  d.rotational = rotational.value();
  d.potential_self = potential_self.value();
  d.potential_uniform = potential_uniform.value();
  d.dissipated = dissipated.value();
  d.elastic = elastic.value();
  for (int k = 0; k < 3; ++k) {
    d.momentum[k] = momentum[k].value();
    d.angular_momentum[k] = angular_momentum[k].value();
  }
}

std::array<common::ExactSum*, DiagnosticSums::kCount> DiagnosticSums::all() {
  return {&kinetic,     &rotational,  &potential_self, &potential_uniform,   &dissipated,          &elastic,
          &momentum[0], &momentum[1], &momentum[2],    &angular_momentum[0], &angular_momentum[1], &angular_momentum[2]};
}

}  // namespace ssdem
