/// @file body_drive.hpp
/// Velocity-driven bodies (`[[body]] drive.*`), e.g. the platens of a Brazilian-disk or a
/// compression test (pipelines/damage): a kinematic velocity boundary condition on the grid
/// nodes the body occupies, the way a testing machine's stiff frame imposes the platen motion.
///
/// Prescribed velocity (a linear ramp from 0, so the body starts without an impact wave):
///     v_T(t) = v_drive min(t / t_ramp, 1)            (t_ramp = drive.ramp_time; 0: v_drive at once)
/// Constrained nodes C_k of drive k at a step: every node with a non-zero uGIMP/linear weight
/// S_ip > 0 of a particle p of the body (a node reached by two drives belongs to the first; a
/// round-off weight at the edge of the support does not count, drive.cpp).
/// In each grid stage of the step (Solver::step; the stages of the schedule in solver.hpp):
///     v_i  <- v_T(t_n)       for i in C_k, after v_i = (mv)_i / m_i and the face conditions
///     v*_i <- v_T(t_n + dt)  for i in C_k, after v*_i = v_i + dt f_i / m_i
///     (MUSL: v**_i <- v_T(t_n + dt) as well)
/// so every particle of the body, whose whole stencil is constrained, moves with
/// v_p^{n+1} = alpha (v_p + v_T(t_{n+1}) - v_T(t_n)) + (1 - alpha) v_T(t_{n+1}) = v_T(t_{n+1})
/// (partition of unity; the body's particle velocities are reset to v_T(t_n) before each P2G, so
/// round-off does not accumulate) and x_p^{n+1} = x_p^n + dt v_T(t_{n+1}). Its velocity gradient
/// is zero: the body is rigid, and its material (density, moduli) does not enter the result
/// (its wave speed is left out of the CFL step as well). Material that touches the body's
/// nodes sticks to it (one velocity field, solver.hpp).
///
/// Reaction (the platen load). With c1_i = v_T(t_n) - v_i and c2_i = v_T(t_n+1) - v*_i the
/// corrections the constraint makes to the unconstrained values, the FLIP/PIC update
/// v_p <- alpha (v_p + sum S (v* - v)) + (1 - alpha) sum S v* changes the total particle momentum
/// by sum_i m_i c2_i + (1 - alpha) sum_i m_i c1_i (internal forces sum to zero, sum_i grad S_ip = 0),
/// the impulse of the constraint. Less the body's own momentum change M_k (v_T(t_n+1) - v_T(t_n)):
///     J_k = sum_{i in C_k} m_i [c2_i + (1 - alpha) c1_i] - M_k (v_T(t_{n+1}) - v_T(t_n))
/// is the impulse the driven body gives the rest of the system in the step, exactly (to
/// round-off) the momentum change of all other particles when no face condition acts on them.
/// DriveLoad: force = J_k / dt of the last step [N] and impulse = sum of J_k since t = 0 [N s],
/// written to the series CSV as body<b>_F{x,y,z}_N and body<b>_J{x,y,z}_Ns (b = scene index of
/// the body); the load on a specimen over an interval is the impulse difference over its length.
#pragma once
#include <Eigen/Core>
#include <cstddef>
#include <cstdint>

namespace mpmfrag {

/// One driven body: the particles with ids in [id_begin, id_end).
struct BodyDrive {
  std::size_t body = 0;                                 ///< index of the [[body]] in the scene
  std::uint64_t id_begin = 0, id_end = 0;
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();  ///< v_drive [m/s]
  double ramp_time = 0.0;                               ///< t_ramp [s] (0: v_drive from the start)
  /// M_k [kg]: the body's mass, summed over all its particles in id order by build_setup (the
  /// same bits on one or many MPI ranks, at the start and after a restart); < 0: summed from
  /// the particles by Solver::set_drives (one process only).
  double mass = -1.0;
  /// v_T(t) [m/s]
  Eigen::Vector3d velocity_at(double t) const {
    return ramp_time > 0.0 && t < ramp_time ? Eigen::Vector3d(velocity * (t / ramp_time)) : velocity;
  }
  bool holds(std::uint64_t id) const { return id >= id_begin && id < id_end; }
};

/// The load of one drive on the rest of the system.
struct DriveLoad {
  Eigen::Vector3d force = Eigen::Vector3d::Zero();    ///< J / dt of the last step [N]
  Eigen::Vector3d impulse = Eigen::Vector3d::Zero();  ///< sum of J since t = 0 [N s]
};

}  // namespace mpmfrag
