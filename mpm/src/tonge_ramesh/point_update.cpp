/// @file point_update.cpp
/// Tonge–Ramesh constitutive update at one point (order of operations and deviations from PTR
/// in point_update.hpp; Tonge & Ramesh 2016 JMPS 86:117; El Mir et al. 2019 Icarus 321:1013).
#include "mpm/tonge_ramesh/point_update.hpp"

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

#include "mpm/tonge_ramesh/granular.hpp"
#include "mpm/tonge_ramesh/micromechanics.hpp"
#include "mpm/tonge_ramesh/moduli.hpp"

namespace mpmfrag::tonge_ramesh {

namespace {
using M3 = Eigen::Matrix3d;

inline M3 dev(const M3& a) { return a - (a.trace() / 3.0) * M3::Identity(); }

/// Most compressive and most tensile principal stress.
inline void principal_ab(const M3& sig, double& sa, double& sb) {
  Eigen::SelfAdjointEigenSolver<M3> es;
  es.computeDirect(sig, Eigen::EigenvaluesOnly);
  sa = es.eigenvalues()(0);
  sb = es.eigenvalues()(2);
}

inline bool finite(const M3& a) { return a.allFinite(); }
}  // namespace

PointState initial_state(const Params& p, int nbins, const double* omega, const double* s) {
  PointState st;
  if (p.use_damage && p.include_initial_damage) {
    double D = 0.0;
    for (int k = 0; k < nbins; ++k) D += omega[k] * s[k] * s[k] * s[k];
    st.D = std::min(D, p.max_damage);
  }
  if (st.D >= p.critical_damage - 1e-8) st.flags |= 1;
  return st;
}

namespace {
// K_T / rho_s of the matrix at eta = J_GP/J (K_T floored at 0.1 A): the undamaged bulk part of c^2.
double bulk_c2(const Params& p, double J, double JGP, double e) {
  const double eta = JGP / J;
  const double KT = std::max(tillotson_tangent(p.eos, p.density, eta, e), 0.1 * p.eos.A);
  return KT / (p.density * eta);
}
}  // namespace

double wave_speed(const Params& p, double J, double JGP, double e) {
  // Aggregate tangent at fixed J_GP (point_update.hpp): bulk ratio K_T / J_GP, shear G / J, over
  // the aggregate density rho0 / J, i.e. K_T over the matrix density plus G over rho0.
  return std::sqrt(bulk_c2(p, J, JGP, e) + 4.0 / 3.0 * p.shear_modulus / p.density);
}

double bulk_speed(const Params& p, const Derived& d, double J, double JGP, double e, double D) {
  return std::sqrt(bulk_c2(p, J, JGP, e) * (damaged_bulk(d, D) / d.K0));
}

UpdateStatus update_point(const Params& p, const Derived& d, const StepInput& in, M3& sigma,
                          PointState& st, int nbins, const double* omega, const double* s,
                          double* l, StepDiag* diag) {
  if (!(in.Jn > 0.0 && in.Jnp1 > 0.0 && in.dt >= 0.0 && std::isfinite(in.dt)) || !finite(in.L) ||
      !finite(sigma) || !(st.JGP > 0.0) || !std::isfinite(st.e) || nbins > kMaxBins)
    return UpdateStatus::bad_input;
  const M3 I = M3::Identity();
  const double dt = in.dt;
  const M3 dL = 0.5 * (in.L + in.L.transpose()) * dt;
  const M3 Wdt = 0.5 * (in.L - in.L.transpose()) * dt;

  // 0. Hughes–Winget incremental rotation of the old stress.
  const M3 Q = I + (I - 0.5 * Wdt).inverse() * Wdt;
  const M3 sig_n = Q * sigma * Q.transpose();

  // 1.–3. Kinematics and trial elastic state.
  const double JGPn = st.JGP;
  const double Dn = st.D;
  const double Gn = damaged_shear(p, d, Dn);
  const M3 be_n = (in.Jn / Gn) * dev(sig_n) + st.Iel * I;
  const M3 V = I + dL + 0.5 * dL * dL;
  const double detV = V.determinant();
  if (!(detV > 0.0)) return UpdateStatus::bad_input;
  const M3 fbar = V / std::cbrt(detV);
  M3 be = fbar * be_n * fbar.transpose();
  double Itr = be.trace() / 3.0;
  if (Itr < 1.0) {  // round-off guard (PTR): keep the deviator, restore I_el >= 1
    const double nn = dev(be_n).norm(), nt = dev(be).norm();
    Itr = nn > 0.0 ? 1.0 + (st.Iel - 1.0) * nt / nn : 1.0 + nt;
    be = dev(be) + Itr * I;
  }
  const double x_n = std::log(in.Jn / JGPn);
  const double x_tr = std::log(in.Jnp1 / JGPn);

  // 5. Damage growth.
  int substeps = 1;
  bool capped = false;
  double D = Dn;
  if (p.use_damage && Dn < p.max_damage * (1.0 - 1e-8) && dt > 0.0) {
    double lsave[kMaxBins];
    std::copy(l, l + nbins, lsave);
    const double ratio_n = damaged_bulk(d, Dn) / d.K0;
    const M3 dev_tr = dev(be);
    const M3 tau_tr = Gn * dev_tr + kirchhoff_mean(p, std::exp(x_tr), st.e, ratio_n) * I;
    double sa, sb;
    principal_ab(tau_tr / in.Jnp1, sa, sb);
    const double Dtrial = advance_cracks(p, d, sa, sb, dt, nbins, omega, s, l);
    D = Dtrial;
    if (Dtrial - Dn > p.max_damage_inc && !(st.flags & 1)) {
      std::copy(lsave, lsave + nbins, l);
      int M = static_cast<int>(std::ceil((Dtrial - Dn) / p.max_damage_inc));
      if (M > p.max_substeps) {
        M = p.max_substeps;
        capped = true;
      }
      substeps = M;
      const M3 dev_n = dev(be_n);
      const double h = dt / M;
      D = Dn;
      for (int i = 1; i <= M; ++i) {
        const double t = double(i) / M;
        const double x = x_n + t * (x_tr - x_n);
        const M3 Bd = dev_n + t * (dev_tr - dev_n);
        const double Gi = damaged_shear(p, d, D), ri = damaged_bulk(d, D) / d.K0;
        const M3 tau = Gi * Bd + kirchhoff_mean(p, std::exp(x), st.e, ri) * I;
        principal_ab(tau / (std::exp(x) * JGPn), sa, sb);
        D = advance_cracks(p, d, sa, sb, h, nbins, omega, s, l);
        if (D >= p.max_damage * (1.0 - 1e-8)) break;
      }
    }
    D = std::max(D, Dn);  // monotone (cap/round-off)
  }
  if (D >= p.critical_damage - 1e-8) st.flags |= 1;

  // 6. Granular flow and compaction.
  double JGP = JGPn;
  double diss = 0.0;
  if (p.use_granular) {
    if (!p.use_damage || D >= p.critical_damage - 1e-8)
      diss += granular_flow(p, d, D, in.Jnp1, st.e, dt, be, JGP, st.gp_strain);
    diss += pa_compaction(p, d, D, in.Jnp1, st.e, dt, JGP);
    if (JGP >= p.j_loc) st.flags |= 2;
  }

  // 7. Final stress.
  const double ratio = damaged_bulk(d, D) / d.K0;
  const double G = damaged_shear(p, d, D);
  const double pK = kirchhoff_mean(p, in.Jnp1 / JGP, st.e, ratio);
  const M3 tau_new = pK * I + G * dev(be);
  const M3 sig_new = tau_new / in.Jnp1;
  if (!finite(sig_new)) return UpdateStatus::bad_input;

  // 8. Energy.
  const M3 dsym = 0.5 * (in.L + in.L.transpose());
  st.e += dt / (2.0 * p.density) * ((in.Jn * sig_n + tau_new).cwiseProduct(dsym)).sum();
  st.Iel = be.trace() / 3.0;
  st.D = D;
  st.JGP = JGP;
  st.gp_energy += diss;
  sigma = sig_new;
  if (diag) {
    diag->substeps = substeps;
    diag->capped = capped;
    diag->dissipation = diss;
  }
  return UpdateStatus::ok;
}

}  // namespace mpmfrag::tonge_ramesh
