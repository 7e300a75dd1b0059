/// @file dt_rule.hpp
/// Choosing k_n and the timestep (Schwartz, Richardson & Michel 2012 §2.1, §2.7; pkdgrav
/// `src/ss/demparams.c`, summarised in shared/reference/ssdem.md §1.7):
///   kinetic regime  k_n = m v_max^2 / x_max^2,  x_max = f s (f = 1 % by default)
///   static regime   k_n = phi rho a_g H s / x_max  (pressure of a column of height H, packing phi)
///   k_n = max(kinetic, static); contact duration tau = pi sqrt(mu / (k_n (1 - xi^2))) with
///   mu = m/2 (equal spheres) and xi the damping ratio from e_n; dt = tau / N_steps (default 30).
/// The run refuses a dt that gives fewer than `min_steps` (default 10) steps per contact for the
/// stiffest/lightest pair present (InputError, exit code 2): no sub-stepping.
#pragma once
#include "ssdem/contact_params.hpp"
#include "ssdem/sphere_summary.hpp"
#include "ssdem/spheres.hpp"

namespace ssdem {

struct DtAdvice {
  double kn_kinetic = 0, kn_static = 0, kn = 0;
  double tau = 0;  ///< contact duration [s]
  double dt = 0;   ///< tau / steps_per_contact [s]
};

/// k_n and dt for spheres of mass m and radius s at speed vmax.
/// rho_phi_ag_H: phi * rho * a_g * H for the static criterion (0 to skip).
DtAdvice choose_kn_dt(double m, double s, double vmax, double en, double overlap_frac = 0.01,
                      double steps_per_contact = 30.0, double rho_phi_ag_H = 0.0);

/// Shortest contact duration over the spheres present (lightest pair; wall contacts use m).
double shortest_contact_time(const ContactParams& p, const Spheres& sp, bool walls);
double shortest_contact_time(const ContactParams& p, const SphereSummary& s, bool walls);

/// Contact time of two spheres of the median mass (Hertz: at half the largest radius, as
/// shortest_contact_time): the typical pair of a body.
double median_contact_time(const ContactParams& p, const Spheres& sp);
double median_contact_time(const ContactParams& p, const SphereSummary& s);

/// Multi-rate level ladder anchored on a reference contact time (time.level_anchor = median):
/// the base step h = tau_ref / (N 2^m) with m the smallest integer giving h <= tau_min / N, so the
/// reference pair gets exactly N steps on level m (h is taken 1e-12 smaller, so that rounding in
/// the level rule cannot put it a level finer) and every pair still gets >= N on its level.
/// (With h = tau_min / N, a pair of contact time r tau_min, 2^l <= r < 2^(l+1), gets N r / 2^l
/// steps, up to 2N: the pipeline's hand-off, almost all spheres of one mass (r = 2.93-3.02),
/// would step 1.47-1.51x more often than needed.) Returns m, or -1 when tau_ref <= tau_min (no anchoring). The
/// scene applies it only where it saves >= 10 % of the reference pair's steps (r / 2^floor(log2 r)
/// >= 1.1): a finer base step costs per-base-step work (drift, reach test, levels) and shortens
/// gravity blocks counted in base steps (a pair at r = 4.14 would gain 3.5 % only).
int anchored_levels(double tau_ref, double tau_min);

/// Throw common::InputError if dt resolves the shortest contact with fewer than min_steps steps.
void check_dt(const ContactParams& p, const Spheres& sp, bool walls, double dt, double min_steps);
void check_dt(const ContactParams& p, const SphereSummary& s, bool walls, double dt, double min_steps);

}  // namespace ssdem
