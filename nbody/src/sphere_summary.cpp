/// @file sphere_summary.cpp
/// SphereSummary of a whole set (sphere_summary.hpp).
#include "ssdem/sphere_summary.hpp"

#include <algorithm>
#include <vector>

#include "common/exact_sum.hpp"

namespace ssdem {

SphereSummary summarise(const Spheres& sp) {
  SphereSummary s;
  s.n = sp.size();
  common::ExactSum M, mx[3];
  for (std::size_t i = 0; i < s.n; ++i) {
    const double m = sp.m[i];
    offer_smallest(m, s.m1, s.m2);
    s.mmax = std::max(s.mmax, m);
    s.smin = std::min(s.smin, sp.s[i]);
    s.smax = std::max(s.smax, sp.s[i]);
    s.vmax = std::max(s.vmax, sp.v[i].norm());
    M += m;
    for (int c = 0; c < 3; ++c) mx[c] += m * sp.x[i][c];
  }
  s.M = M.value();
  for (int c = 0; c < 3; ++c) s.com[c] = mx[c].value() / s.M;
  for (std::size_t i = 0; i < s.n; ++i) s.R = std::max(s.R, (sp.x[i] - s.com).norm() + sp.s[i]);
  if (s.n > 0) {
    std::vector<double> m = sp.m;
    std::nth_element(m.begin(), m.begin() + static_cast<std::ptrdiff_t>(s.n / 2), m.end());
    s.m_median = m[s.n / 2];
  }
  return s;
}

}  // namespace ssdem
