/// @file gravity.cpp
/// Direct-summation gravity (reference) and the tree's memory accounting; equations in gravity.hpp.
#include "ssdem/gravity.hpp"

#include <cmath>

namespace ssdem {

void direct_gravity(const Spheres& sp, double G, std::vector<Vec3>& acc, std::vector<double>* pot) {
  const std::size_t n = sp.size();
  acc.assign(n, Vec3::Zero());
  if (pot) pot->assign(n, 0.0);
#pragma omp parallel for schedule(dynamic, 64) if (n >= 256)
  for (std::size_t i = 0; i < n; ++i) {
    Vec3 a = Vec3::Zero();
    double ph = 0.0;
    for (std::size_t j = 0; j < n; ++j) {
      if (j == i) continue;
      const Vec3 r = sp.x[j] - sp.x[i];
      double pf;
      const double f = spline_force_factor(r.norm(), sp.s[i] + sp.s[j], pf);
      a += (G * sp.m[j] * f) * r;
      ph -= G * sp.m[j] * pf;
    }
    acc[i] = a;
    if (pot) (*pot)[i] = ph;
  }
}

double TreeGravity::bytes_per_sphere(std::size_t n) const {
  if (n == 0) return 0.0;
  return (static_cast<double>(d_.nodes.size()) * sizeof(tree::Node) +
          static_cast<double>(n) * (4 + 4 + 5 * 8) + 4.0 * d_.leaves.size()) /
         static_cast<double>(n);
}

}  // namespace ssdem
