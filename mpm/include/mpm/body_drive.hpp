/// @file body_drive.hpp
/// Velocity-driven bodies (`[[body]] drive.*`): the particles of a driven body are held at a
/// prescribed velocity by a relaxation body force, e.g. the platens of a Brazilian-disk or a
/// compression test (pipelines/damage). For every particle p of the body
///     a_p = (v_T(t) - v_p) / tau + dv_T/dt,      v_T(t) = v_drive min(t / t_ramp, 1)
/// (explicit relaxation: stable for dt < 2 tau, monotone for dt < tau, so tau = drive.relaxation_time
/// should exceed the time step; the ramp starts the
/// body without an impact wave). The force acts on the body's own particles only; the reaction
/// of the rest of the system on the body is overcome, as by a testing machine's stiff frame.
#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "mpm/solver.hpp"

namespace mpmfrag {

/// One driven body: the particles with ids in [id_begin, id_end).
struct BodyDrive {
  std::uint64_t id_begin = 0, id_end = 0;
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();  ///< v_drive [m/s]
  double ramp_time = 0.0;                               ///< t_ramp [s] (0: from the start)
  double relaxation_time = 1e-7;                        ///< tau [s]
};

/// The body-force callback of a list of drives (empty function if the list is empty).
BodyForce make_drive_force(std::vector<BodyDrive> drives);

}  // namespace mpmfrag
