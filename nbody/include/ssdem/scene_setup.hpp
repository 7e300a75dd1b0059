/// @file scene_setup.hpp
/// The ssdem-grav scene schema and its translation into a SimConfig and initial spheres.
///
/// Sections: [time] (dt, end, dt rule), [initial] (file or generator), [gravity] (self-gravity
/// solver, opening angle, update interval, uniform field), [contact] (enabled, preset, parts and
/// their parameters, k_n rule), [[wall]] (planes), [output] (directory, snapshots, series,
/// checkpoints, progress), [run] (seed). Key names shared with mpm-frag are spelt as there; the
/// old names (output.dir, output.snapshot_every, initial.seed) are deprecated aliases.
/// `ssdem-grav --help-params` prints every key with unit, range and help.
#pragma once
#include <string>

#include "common/schema.hpp"
#include "ssdem/contact_params.hpp"
#include "ssdem/simulation.hpp"

namespace ssdem {

/// The contact-part registry with the built-in parts.
const ContactPartRegistry& builtin_contact_parts();

/// Full scene schema of ssdem-grav.
common::Schema ssdem_schema();

/// Initial spheres from the scene (file or generator).
Spheres initial_spheres(const common::Scene& scene);

/// Simulation configuration; resolves the k_n / dt rule against `sp` when k_n or dt are 0
/// ("auto"). `info` (optional) receives a human-readable summary of the choices.
SimConfig sim_config(const common::Scene& scene, const Spheres& sp, std::string* info = nullptr);

}  // namespace ssdem
