/// @file resume.cpp
/// The solver's carried state for checkpoints (SolverResume, solver.hpp): what a step reads
/// besides the particles and the material state arrays.
#include <string>

#include "common/particle_file.hpp"
#include "mpm/solver.hpp"

namespace mpmfrag {

SolverResume Solver::resume_state() const {
  SolverResume s;
  s.time = time_;
  s.step = step_;
  s.max_speed = max_speed_;
  s.min_node_mass = m_min_;
  s.outflow = out_;
  s.outflow_time = out_time_;
  s.outflow_fields = out_fields_;
  s.outflow_init = out_init_;
  s.outflow_totals = out_diag_;
  s.drive_loads = drive_load_;
  return s;
}

void Solver::resume(SolverResume s) {
  if (s.outflow.size() != s.outflow_time.size() || s.outflow_fields.size() != s.outflow_init.size())
    throw common::InputError("checkpoint: the outflow record's arrays disagree in size");
  if (s.drive_loads.size() != drives_.size())
    throw common::InputError("checkpoint: " + std::to_string(s.drive_loads.size()) + " drive loads, the scene has " +
                             std::to_string(drives_.size()) + " driven bodies");
  drive_load_ = std::move(s.drive_loads);
  time_ = s.time;
  step_ = s.step;
  max_speed_ = s.max_speed;
  m_min_ = s.min_node_mass;
  out_ = std::move(s.outflow);
  out_time_ = std::move(s.outflow_time);
  out_fields_ = std::move(s.outflow_fields);
  out_init_ = std::move(s.outflow_init);
  out_diag_ = s.outflow_totals;
}

}  // namespace mpmfrag
