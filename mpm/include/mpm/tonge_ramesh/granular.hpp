/// @file granular.hpp
/// Granular flow of the comminuted material and P–alpha pore compaction (Tonge & Ramesh 2016;
/// ARL-SR-0344 Eqs. 13–15; PTR `calcGranularFlow`, `calcJGPFromPressure`).
///
/// Drucker–Prager cone in Rendulic coordinates of the Kirchhoff stress tau = p_K I + tau_dev:
///   sigma_s = |tau_dev|, sigma_p = tr(tau)/sqrt3 = sqrt3 p_K,  f = sigma_s + A(sigma_p - B).
/// Closed-form associative return in the energy norm (eta_G = 2G/(3K)): Delta = f/(A^2+eta_G),
/// sigma_p <- sigma_p - A Delta, sigma_s <- sigma_s - eta_G Delta; apex (sigma_s=0, sigma_p = B)
/// if the return passes the vertex. QUIRK (PTR uses B/3 in one apex branch, B/sqrt3 in the other):
/// fixed, both use p_K = B/sqrt3. K here is the exact tangent d p_K/d ln J_EL of the damaged EOS.
/// Dilatancy: Delta ln J_GP solves p_K(J/J_GP) = p* exactly (Newton, exact slope).
/// Deviator: I_el <- 1 + (I_tr-1)|tau_dev|^2/|tau_tr|^2, be <- tau_dev/G + I_el I.
/// Energy check (PTR): stored-energy drop dW = 1/2(p_tr+p*) Delta ln J_GP + 3G/2 (I_tr - I_el);
/// if dW < 0 the dilatancy is backtracked by 0.9 (<= 100 times, then 0).
/// Reported dissipation = p* Delta ln J_GP + tau_dev:(tau_tr - tau_dev)/(2G) (= Delta A B/(3K) >= 0
/// for the cone with constant moduli).
///
/// P–alpha (alpha = J_GP, P = -p_K/J the aggregate pressure, compression +), crush curve
///   alpha_c(P) = 1 + (alpha_e-1)((P_c-P)/(P_c-P_e))^2   for P_e <= P < P_c,
///              = alpha_e - ln(P/P_e)/kappa               for 0 < P < P_e,  kappa = (P_c-P_e)/(2P_e(alpha_e-1)),
///              = 1 for P >= P_c; no compaction for P <= 0.
/// If alpha > alpha_c(P(alpha)) the new alpha is the root of alpha - alpha_c(P(alpha)) on [1, alpha]
/// with P evaluated exactly through the EOS (safeguarded secant/bisection instead of PTR's
/// linearised Newton: same fixed point, guaranteed bracket). Dissipation 1/2(p_old+p_new) Delta ln alpha.
#pragma once
#include <Eigen/Core>

#include "mpm/tonge_ramesh/params.hpp"

namespace mpmfrag::tonge_ramesh {

/// Crush-curve distension alpha_c(P) (P aggregate pressure, compression positive).
double crush_alpha(const Params& p, const Derived& d, double P);

/// Granular return at damage D. `be` is the isochoric elastic left Cauchy–Green tensor (in/out),
/// `JGP` the distension (in/out), J the total Jacobian, e the specific energy.
/// Returns the dissipated energy per reference volume (>= 0 up to round-off).
double granular_flow(const Params& p, const Derived& d, double D, double J, double e, double dt,
                     Eigen::Matrix3d& be, double& JGP, double& gp_strain);

/// P–alpha compaction at damage D; updates JGP (>= 1). Returns the dissipation per reference volume.
double pa_compaction(const Params& p, const Derived& d, double D, double J, double e, double dt,
                     double& JGP);

}  // namespace mpmfrag::tonge_ramesh
