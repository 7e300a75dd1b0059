/// @file point_update.hpp
/// One constitutive update of the Tonge–Ramesh model at a material point, in the order of PTR
/// `advanceTimeSigmaL` (Tonge 2015, ARL-SR-0344 §4; tonge-ramesh spec §10):
///  0. Hughes–Winget rotation of sigma_n with W = skew(L); d = sym(L).
///  1. J_EL = J_{n+1}/J_GP,n.
///  2. be_n = J_n dev(sigma_n)/G(D_n) + I_el,n I.
///  3. Trial be_tr = fbar be_n fbar^T, V = I + d dt + (d dt)^2/2, fbar = V/det(V)^(1/3).
///  5. Damage: trial full step with the end-of-step Cauchy trial stress
///     sigma = (G(D_n) dev(be_tr) + p_K(J_EL, D_n) I)/J; if Delta D > MaxDamageInc and the point is
///     not localized, M = ceil(Delta D/MaxDamageInc) sub-steps (capped at Params::max_substeps) with
///     ln J_EL and dev(be) interpolated linearly and the stress evaluated at each sub-step END with
///     the current moduli. QUIRK (PTR evaluates at the sub-step start and mixes two volumetric
///     measures): fixed as recommended.
///  6. Granular flow if D >= D_c, then P–alpha (granular.hpp).
///  7. sigma_{n+1} = (p_K(J/J_GP, D) I + G(D) dev(be))/J_{n+1}.
///  8. Specific energy e_{n+1} = e_n + dt/(2 rho0) (tau_n + tau_{n+1}) : d (El Mir Tillotson
///     coupling is not specified; this explicit-energy update is the SPH-Tillotson convention).
/// Kirchhoff mean stress p_K = J_EL (-p_T(rho0/J_EL, e)) K(D)/K0 (moduli.hpp).
///
/// QUIRKs of the public Uintah PTR code (tonge-ramesh spec) and what this implementation does:
///  * flaw-size spread sqrt(E[s^6]/n) (§4.4): FIXED, variance of s^3 (flaws.hpp) — statistics.
///  * Kirchhoff stress fed to the wing-crack routine (§7.1): FIXED, Cauchy (physically the far
///    field; difference O(|J-1|)).
///  * friction term active on open (tensile) flaw faces (§7.3): FIXED by default (no friction on
///    open faces); Params::friction_in_tension reproduces PTR (lowers tensile onset ~10 %).
///  * sub-step stress at the sub-step start, mixed volumetric measures (§7.5): FIXED, ln J_EL and
///    dev(be) interpolated, stress at the sub-step end.
///  * useOldStress divides by J_old (§7.5.3): not applicable, only the trial-stress path
///    (useOldStress = 0) is implemented.
///  * apex mean stress B/3 in one branch (§8): FIXED, B/sqrt3 in both (granular.hpp).
///  * PTR wave speed = 0 with damage on / rho0 with granular flow (§12): FIXED, wave_speed() uses
///    the undamaged aggregate tangent over the aggregate density (conservative; derivation below).
///  * Uintah wrapper passes J one increment ahead (§12): FIXED, J_n = J_{n+1}/det(I + L dt)
///    (style.cpp via mpmfrag::jacobian_old).
///  * PTR throws on non-converged inner iterations (§12): replaced by bounded iterations with
///    fallbacks (granular.cpp) and a bad_input status that the solver turns into exit 3.
/// Deviations: no flaw-interaction ellipse (far-field stress drives the wing cracks), K0 = A
/// (reference) in the damaged-moduli formulas, explicit specific energy e_n in the pressure.
#pragma once
#include <Eigen/Core>
#include <cstdint>

#include "mpm/tonge_ramesh/params.hpp"

namespace mpmfrag::tonge_ramesh {

/// Largest number of flaw bins per point (stack scratch in the update).
inline constexpr int kMaxBins = 256;

/// Scalar state of one material point (per-bin arrays are passed separately).
struct PointState {
  double Iel = 1.0;        ///< tr(be)/3 >= 1
  double D = 0.0;          ///< damage
  double JGP = 1.0;        ///< granular Jacobian = P–alpha distension
  double gp_strain = 0.0;  ///< accumulated granular deviatoric strain
  double gp_energy = 0.0;  ///< dissipated energy per reference volume [J/m^3]
  double e = 0.0;          ///< specific internal energy [J/kg]
  int flags = 0;           ///< 1: D >= D_c, 2: J_GP >= JLoc
};

/// Kinematic input of one step.
struct StepInput {
  Eigen::Matrix3d L = Eigen::Matrix3d::Zero();  ///< velocity gradient [1/s]
  double dt = 0.0;                              ///< [s]
  double Jn = 1.0, Jnp1 = 1.0;                  ///< det F at start / end of step
};

/// Result of one update.
enum class UpdateStatus { ok = 0, bad_input = 1 };

/// Diagnostics of one update.
struct StepDiag {
  int substeps = 1;          ///< damage sub-steps used
  bool capped = false;       ///< sub-step count hit Params::max_substeps
  double dissipation = 0.0;  ///< granular + compaction dissipation this step [J/m^3]
};

/// Advance one point: sigma (Cauchy, in/out), state, bins (omega, s: const; l: in/out).
/// On bad input (non-finite, J <= 0) returns bad_input; sigma and the scalar state are then left
/// unchanged (the caller treats it as a numerical failure).
UpdateStatus update_point(const Params& p, const Derived& d, const StepInput& in,
                          Eigen::Matrix3d& sigma, PointState& st, int nbins, const double* omega,
                          const double* s, double* l, StepDiag* diag = nullptr);

/// Initial state after flaw sampling: D0 = sum omega s^3 (capped) if include_initial_damage.
PointState initial_state(const Params& p, int nbins, const double* omega, const double* s);

/// Longitudinal wave speed for the time step, c^2 = K_T(rho_s, e)/rho_s + (4/3) G0/rho0, with
/// undamaged moduli (damage only softens) and the matrix density rho_s = rho0 J_GP/J.
/// Derivation: the Cauchy mean stress is p_K(J_EL)/J (moduli.hpp), so at fixed J_GP its tangent
/// is d sigma_m / d ln J = ratio K_T / J_GP exactly; the deviator G dev(be)/J has the uniaxial
/// tangent (4/3) G I_el / J up to a term of first order in the elastic deviatoric strain
/// (<~1 % at yield; left out, within the Courant number's margin). Over the aggregate density
/// rho0/J these give K_T/rho_s and (4/3) G/rho0: a distended (J_GP >> 1) granular aggregate is
/// soft and light in the same ratio, so it is as fast as its matrix. Granular flow, P–alpha
/// compaction and damage only lower the tangent, and where K_T < 0.1 A the floor raises it.
/// K_T is taken at fixed e (the update's pressure uses e_n, so within a step the stiffness the
/// scheme sees is K_T); the isentropic modulus of a hot shocked state is larger (about 2x at
/// 56 GPa and 4.5 MJ/kg), a margin the Courant number 0.3 has not been shown to need: the
/// impact outcome at 30 s changes by < 8 % for Courant numbers from 0.03 to 0.3 (mpm/README.md).
/// Until 2026-12-05 this divided by rho0/J, which overstated c by ~sqrt(J): 101 km/s instead of
/// 4.3 km/s for the DART impactor's particles at J = 587, J_GP = 504 (the measured 1.4e-5 s step).
double wave_speed(const Params& p, double J, double JGP, double e);

/// Bulk sound speed for the artificial viscosity, sqrt(ratio K_T / rho_s) with the damaged ratio
/// K(D)/K0 (same derivation, volumetric part only).
double bulk_speed(const Params& p, const Derived& d, double J, double JGP, double e, double D);

}  // namespace mpmfrag::tonge_ramesh
