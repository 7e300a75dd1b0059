/// @file handoff_scene.cpp
/// Implementation of handoff/handoff_scene.hpp (the header states the contract, and for physics the equations and sources).
#include "handoff/handoff_scene.hpp"

#include "common/status.hpp"

#include <cmath>
#include <filesystem>
#include <sstream>

namespace handoff {

common::Schema handoff_schema() {
  common::Schema s("mpm2spheres: hand-off from an mpm-frag particle snapshot to an ssdem.spheres file");
  s.add_string("input", std::nullopt, "particle snapshot (format mpm-frag.particles) to read");
  s.add_string("outflow", std::string(""),
               "mpm-frag <prefix>_outflow.h5 (particles removed at the grid edge, grid.outflow = \"remove\"): "
               "handed off with the same one-sphere-per-cell rule on the lattice extended past the grid (empty: none)");
  s.add_string("output", std::nullopt, "sphere file (format ssdem.spheres) to write; an .xmf sidecar is written beside it");
  s.add_choice("method", HandoffMethod::paper, kHandoffMethods,
               "paper: El Mir et al. 2019 (mass and momentum exact, KE loss reported); conserving: paper spheres "
               "then a global velocity/spin correction restoring KE and angular momentum exactly");
  s.add_choice("shape", mpmfrag::ShapeKind::ugimp, mpmfrag::kShapeKinds, "MPM shape functions for the projection (as in mpm-frag)");
  s.add_int("coarsen", 1, 1, 64, "sphere cell edge in MPM cells (spheres of radius coarsen*h/2)");
  s.add_string("carry", std::string("damage"),
               "comma-separated scalar particle fields mass-averaged onto the spheres (missing defaults are skipped)");
  s.add_real("select.min_damage", 0.0, "1", 0.0, 1.0, "drop particles with damage below this (0 keeps all)");
  s.add_real("select.max_speed", 0.0, "m/s", 0.0, 1e8, "drop particles faster than this (0: no limit)");
  s.add_real_list("select.exclude_materials", std::vector<double>{}, "1", 0.0, 1e9, "material ids to drop");
  s.add_real("audit.max_energy_loss", 1.0, "1", 0.0, 1.0,
             "fail with exit code 3 (no sphere file written) if the relative kinetic-energy loss exceeds this");
  s.add_string("audit.json", std::string(""), "audit JSON path (default: <output without .h5>.audit.json)");
  s.add_string("export.ss", std::string(""), "also write a pkdgrav .ss file here (empty: none)");
  s.add_choice("export.ss_units", SsUnitSystem::pkdgrav, kSsUnitSystems, "units of the .ss file (pkdgrav: G = 1, AU, M_sun)");
  s.add_int("export.ss_color", 3, 0, 255, "pkdgrav colour code written for every sphere");
  // bonds between face-adjacent spheres, scaled by damage (face_bonds.hpp); key names as in ssdem-grav
  s.add_bool("bonds.enabled", false,
             "write /bonds: a parallel bond between the spheres of every pair of face-adjacent cells with "
             "max damage < bonds.damage_critical, stiffness and strength x (1 - D / D_c)");
  s.add_real("bonds.kn", 0.0, "N/m^3", 0.0, 1e30,
             "intact bond normal stiffness per unit area (E = kn L0 of the equivalent beam; > 0 with bonds.enabled)");
  s.add_real("bonds.ks", 0.0, "N/m^3", 0.0, 1e30, "intact bond shear stiffness per unit area");
  s.add_real("bonds.sigma_c", 1e300, "Pa", 0.0, 1e300, "intact bond tensile strength");
  s.add_real("bonds.tau_c", 1e300, "Pa", 0.0, 1e300, "intact bond shear strength");
  s.add_real("bonds.radius_ratio", 1.0, "1", 0.0, 10.0, "bond radius / sphere radius", true);
  s.add_real("bonds.damage_critical", 0.125, "1", 0.0, 1.0,
             "D_c: no bond where the larger damage of the two spheres is >= D_c; factor 1 - D/D_c below "
             "(default: Tonge-Ramesh basalt's critical damage, El Mir et al. 2019 Table 1, beyond which the "
             "material flows as a granular medium)", true);
  return s;
}

HandoffConfig handoff_config(const common::Scene& sc) {
  HandoffConfig c;
  c.input = sc.string("input");
  c.output = sc.string("output");
  c.outflow = sc.string("outflow");
  c.method = sc.choice("method", kHandoffMethods);
  c.projection.shape = sc.choice("shape", mpmfrag::kShapeKinds);
  c.projection.coarsen = static_cast<int>(sc.integer("coarsen"));
  std::stringstream fields(sc.string("carry"));
  for (std::string f; std::getline(fields, f, ',');) {
    f.erase(0, f.find_first_not_of(" \t"));
    f.erase(f.find_last_not_of(" \t") + 1);
    if (!f.empty()) c.projection.carry_fields.push_back(f);
  }
  c.carry_given = sc.given("carry");
  c.select.min_damage = sc.real("select.min_damage");
  c.select.max_speed = sc.real("select.max_speed");
  for (double m : sc.real_list("select.exclude_materials")) {
    if (m != std::floor(m)) throw common::InputError(sc.source(), "select.exclude_materials", "material ids are integers");
    c.select.exclude_materials.push_back(static_cast<int>(m));
  }
  c.max_energy_loss = sc.real("audit.max_energy_loss");
  c.audit_json = sc.string("audit.json");
  if (c.audit_json.empty()) {
    std::filesystem::path p(c.output);
    c.audit_json = (p.parent_path() / (p.stem().string() + ".audit.json")).string();
  }
  c.ss_path = sc.string("export.ss");
  c.ss_units = sc.choice("export.ss_units", kSsUnitSystems);
  c.ss_color = static_cast<int>(sc.integer("export.ss_color"));
  c.bonds.enabled = sc.boolean("bonds.enabled");
  c.bonds.kn = sc.real("bonds.kn");
  c.bonds.ks = sc.real("bonds.ks");
  c.bonds.sigma_c = sc.real("bonds.sigma_c");
  c.bonds.tau_c = sc.real("bonds.tau_c");
  c.bonds.radius_ratio = sc.real("bonds.radius_ratio");
  c.bonds.damage_critical = sc.real("bonds.damage_critical");
  if (c.bonds.enabled && !(c.bonds.kn > 0.0))
    throw common::InputError(sc.source(), "bonds.kn", "must be > 0 when bonds.enabled = true (range (0, 1e30] N/m^3)");
  return c;
}

}  // namespace handoff
