/// @file element_driver.cpp
/// Homogeneous uniaxial-stress driver for one Tonge–Ramesh point (see element_driver.hpp).
#include "mpm/tonge_ramesh/element_driver.hpp"

#include <algorithm>
#include <cmath>

#include "mpm/tonge_ramesh/flaws.hpp"
#include "mpm/tonge_ramesh/moduli.hpp"

namespace mpmfrag::tonge_ramesh {

ElementResult run_uniaxial_stress(const Params& p, double V, std::uint64_t id, double rate,
                                  double dstrain, double max_strain, double drop,
                                  int record_every) {
  const Derived d(p);
  const int n = p.total_bins();
  std::vector<double> omega(n), s(n), l(n, 0.0), ltry(n);
  sample_flaws(p, V, id, 0, omega.data(), s.data());
  PointState st = initial_state(p, n, omega.data(), s.data());
  Eigen::Matrix3d sig = Eigen::Matrix3d::Zero();
  const double dt = dstrain / std::abs(rate);
  double J = 1.0, strain = 0.0, x = -d.nu0 * rate;
  ElementResult res;
  bool past_peak = false;
  for (long step = 0; std::abs(strain) < max_strain; ++step) {
    // Secant iteration on the lateral rate x so that sigma_22 = 0 after the update.
    auto trial = [&](double xr, PointState& so, Eigen::Matrix3d& sg) {
      StepInput in;
      in.L.diagonal() << rate, xr, xr;
      in.dt = dt;
      in.Jn = J;
      in.Jnp1 = J * std::exp((rate + 2.0 * xr) * dt);
      so = st;
      sg = sig;
      std::copy(l.begin(), l.end(), ltry.begin());
      const auto status = update_point(p, d, in, sg, so, n, omega.data(), s.data(), ltry.data());
      return status == UpdateStatus::ok ? sg(1, 1) : NAN;
    };
    PointState s1;
    Eigen::Matrix3d g1;
    double r1 = trial(x, s1, g1);
    const double Kd = damaged_bulk(d, st.D), Gd = damaged_shear(p, d, st.D);
    double slope = (2.0 * Kd + 2.0 * Gd / 3.0) * dt;  // d sigma_22 / d x, elastic estimate
    double x1 = x;
    for (int it = 0; it < 12 && std::isfinite(r1) && std::abs(r1) > 1e-7 * std::max(std::abs(g1(0, 0)), 1e3); ++it) {
      const double x2 = x1 - r1 / slope;
      PointState s2;
      Eigen::Matrix3d g2;
      const double r2 = trial(x2, s2, g2);
      if (!std::isfinite(r2)) break;
      if (x2 != x1 && r2 != r1) slope = (r2 - r1) / (x2 - x1);
      if (!(slope > 0.0)) slope = (2.0 * Kd + 2.0 * Gd / 3.0) * dt;
      x1 = x2;
      r1 = r2;
      s1 = s2;
      g1 = g2;
    }
    if (!std::isfinite(r1)) {
      res.ok = false;
      break;
    }
    // Accept: redo the accepted trial into the real state (ltry holds the last trial's lengths).
    (void)trial(x1, s1, g1);
    std::copy(ltry.begin(), ltry.end(), l.begin());
    st = s1;
    sig = g1;
    x = x1;
    J *= std::exp((rate + 2.0 * x) * dt);
    strain += rate * dt;
    res.steps = step + 1;
    const double a = std::abs(sig(0, 0));
    if (a > res.peak_stress && !past_peak) {  // loading branch: check the lateral condition
      res.max_lateral_residual =
          std::max(res.max_lateral_residual, std::abs(sig(1, 1)) / std::max(a, 1.0));
      res.peak_stress = a;
      res.strain_at_peak = strain;
    }
    if (a < drop * res.peak_stress) past_peak = true;
    if (record_every > 0 && step % record_every == 0)
      res.history.push_back({(step + 1) * dt, strain, sig(0, 0), sig(1, 1), st.D, st.JGP});
    if (past_peak) break;
  }
  res.final_D = st.D;
  return res;
}

}  // namespace mpmfrag::tonge_ramesh
