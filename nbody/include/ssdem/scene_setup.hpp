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
#include "ssdem/sphere_summary.hpp"

namespace ssdem {

/// The contact-part registry with the built-in parts.
const ContactPartRegistry& builtin_contact_parts();

/// Full scene schema of ssdem-grav.
common::Schema ssdem_schema();

/// Initial spheres from the scene (file or generator). `file_bonds` (optional) receives the bonds
/// of an ssdem.spheres input file (its /bonds group, common/bond_file.hpp; empty if none).
Spheres initial_spheres(const common::Scene& scene, BondSet* file_bonds = nullptr);

/// The scene's ssdem.spheres input file if an MPI rank may read only its block of it (initial.source
/// = "file", no bonds in the file, bonds.generate off: mpi/domain_sim.hpp, "Input in blocks"); ""
/// otherwise (a generator, a .ss file, bonds: every rank builds or reads all the spheres).
std::string block_input_file(const common::Scene& scene);

/// Simulation configuration; resolves the k_n / dt rule against `sp` when k_n or dt are 0
/// ("auto"). `info` (optional) receives a human-readable summary of the choices.
/// Bonds: bonds.generate, or the input file's bonds (`file_bonds`) when bonds.from_file is true
/// (the default: a hand-off file's bonds are used automatically); both at once is an InputError.
/// With time.dt = 0 the step resolves the shortest bond mode like a contact (dt_rule.hpp).
/// `checkpoint` (a restart): the path of the checkpoint whose bonds `file_bonds` then holds; they
/// are the run's bonds whatever their origin (bonds.* cannot change over a restart, run identity),
/// so nothing is generated and `info` names the checkpoint as their source.
SimConfig sim_config(const common::Scene& scene, const Spheres& sp, std::string* info = nullptr,
                     const BondSet* file_bonds = nullptr, const std::string& checkpoint = std::string());
/// The same from the spheres' summary (sphere_summary.hpp; what an MPI rank that read only its
/// block of the spheres has). `all`: every sphere, needed only where bonds are generated or given
/// (their contact times); null without bonds (std::logic_error if bonds then need it). Equal to
/// the overload above whenever `sum` = summarise(all).
SimConfig sim_config(const common::Scene& scene, const SphereSummary& sum, const Spheres* all, std::string* info,
                     const BondSet* file_bonds, const std::string& checkpoint);

}  // namespace ssdem
