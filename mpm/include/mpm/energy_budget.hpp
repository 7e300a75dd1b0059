/// @file energy_budget.hpp
/// The MPM energy budget: the energy-consistent transfer scheme `solver.scheme = "midpoint"` and
/// the partition of the internal energy written to <prefix>_series.csv and the impact report.
///
/// ## Why the other schemes do not conserve energy
/// With grid forces f_i = -sum_p V_p sigma_p . grad S_ip (P2G) and a velocity gradient
/// L_p = sum_i u_i (x) grad S_ip (G2P), the identity sum_p V_p sigma_p : L_p(u) = -sum_i f_i . u_i
/// holds for ANY grid velocity u. The grid's kinetic energy changes by
///   dK_grid = sum_i m_i (|v*_i|^2 - |v_i|^2)/2 = sum_i f_i . (v_i + v*_i)/2 dt,
/// so the stress work balances it exactly only if the stress power is that of the force,
/// V_n sigma_n : L, evaluated at u = (v_i + v*_i)/2. USL (u = v*) loses sum_i m_i |dv_i|^2 / 2
/// per step, USF (u = v) gains it, MUSL (u = v**) lies between; at the seed paper's impact,
/// dv_i is of the order of the impact speed within a few steps, and the demo (1 km cells) changes
/// K + U by -13.6 % (USL), +9.7 % (USF), +12.3 % (MUSL, FLIP) and -17.5 % (MUSL, FLIP 0.99) in 10 s.
/// (Bardenhagen 2002, JCP 180:383 analyses this energy error; shared/reference/mpm.md §5.)
///
/// ## The midpoint scheme
///   P2G m, m v, f(sigma_n, V_n, q_n) -> v -> BC -> v* = v + dt f/m -> BC ->
///   G2P: v_p <- FLIP blend (solver.flip; 1 recommended), x_p += dt sum S v*,
///        L_p = sum_i v*_i (x) grad S_ip, F, V, material update         (the USL step)
///        e_p += dt V_n (sigma_n - q_n I) : L_mid / m_p,  L_mid = sum_i (v_i + v*_i)/2 (x) grad S_ip
///                                                                    (= -f . v_mid dt, exact)
///        e_p += h_p,  h_p = m_p/2 [sum_i S_ip |v*_i - v_i|^2 - |sum_i S_ip (v*_i - v_i)|^2] / m_p
///               + (|v_FLIP|^2 - |v_p,new|^2)/2   (the second term only when solver.flip < 1).
/// The particles' kinetic energy with FLIP changes by the grid's first-order term exactly
/// (sum_p m_p v_p . sum_i S_ip dv_i = sum_i m_i v_i . dv_i) but its second-order term by
/// sum_p m_p |dv_p|^2/2 <= sum_i m_i |dv_i|^2/2 (Jensen): the difference is the part of the grid's
/// kinetic energy that the particle velocities cannot hold (the variance of dv_i over a particle's
/// stencil). h_p >= 0 puts it, particle by particle, into internal energy: the kinetic-energy
/// fix-up of ALE remapping (DeBar 1974, UCID-19683; the KE lost in a momentum remap becomes
/// heat), applied to the G2P remap. With it, K + U changes only by the work of external forces,
/// the boundary conditions and round-off (the demo: 0.000 %). The heat h_p is numerical; it is
/// concentrated where the velocity increment is rough on the scale of a cell (shock fronts,
/// contact), as artificial viscosity heating is, and it is shown as its own column.
/// The stress itself is updated with L from v* as in USL: that step is symplectic for elastic
/// waves (amplification factor 1), whereas a stress update from L_mid amplifies a wave of
/// Courant number lambda by 1 + lambda^2/4 per step (measured: two elastic spheres gain 26 E0 of
/// kinetic energy). Only the energy bookkeeping uses L_mid, so for an EOS the pressure sees
/// e_n from the same power that moved the grid. The stored elastic energy of a style then differs
/// from the deviatoric work by the time-integration error (damage_J for an elastic style).
///
/// ## Partition (series.csv columns, all in J, summed over all particles incl. outflow)
///   kinetic_J      K = sum m |v|^2 / 2
///   internal_J     U = sum m e (all stress work, shock and transfer heating)
///   total_J        K + U
///   eos_J          volumetric stress work int -p tr D dt V (EOS compression and heating)
///   elastic_J      stored deviatoric elastic energy (material style: Material::stored_energies)
///   plastic_J      plastic / granular (and compaction) dissipation reported by the style
///   damage_J       deviatoric work neither stored nor dissipated by flow: released by crack
///                  growth (damaged moduli) — for an elastic style its time-integration error
///   shock_heat_J   artificial viscosity heating int q |tr D| dt V
///   transfer_heat_J the transfer fix-up h (scheme "midpoint")
/// eos + elastic + plastic + damage + shock_heat + transfer_heat = internal by construction.
/// The Tonge–Ramesh compaction dissipation is volumetric work, so it appears in eos_J AND in
/// plastic_J and makes damage_J smaller by the same amount.
#pragma once
#include "mpm/solver.hpp"

namespace mpmfrag {

/// The partition of the internal energy (see above) [J].
struct EnergyBudget {
  double eos = 0, elastic = 0, plastic = 0, damage = 0, shock_heat = 0, transfer_heat = 0;
};

inline EnergyBudget energy_budget(const Diagnostics& d) {
  EnergyBudget e;
  e.shock_heat = d.heat_shock;
  e.transfer_heat = d.heat_transfer;
  e.elastic = d.elastic;
  e.plastic = d.dissipated;
  e.damage = d.work_dev - d.elastic - d.dissipated;
  e.eos = d.internal - d.work_dev - d.heat_shock - d.heat_transfer;
  return e;
}

}  // namespace mpmfrag
