/// @file analyse_scene.cpp
/// Implementation of analysis/analyse_scene.hpp (the header states the contract, and for physics the equations and sources).
#include "analysis/analyse_scene.hpp"

#include <algorithm>
#include <numeric>

#include "common/particle_file.hpp"
#include "common/status.hpp"

namespace analysis {

common::Schema analyse_schema() {
  common::Schema s("ssdem-analyse: clumps, bound mass, largest remnant, beta and damage profiles of ssdem.spheres snapshots");
  const double inf = std::numeric_limits<double>::infinity();
  s.add_real("impact.impactor_mass", 0.0, "kg", 0.0, inf, "impactor mass m (0: unknown, beta is not computed)");
  s.add_vec3("impact.impactor_velocity", Eigen::Vector3d::Zero(), "m/s", -inf, inf,
             "impactor velocity before impact, simulation frame");
  s.add_vec3("impact.target_velocity", Eigen::Vector3d::Zero(), "m/s", -inf, inf,
             "target velocity before impact, simulation frame (beta is evaluated in the target's pre-impact rest frame)");
  s.add_real("impact.parent_body_mass", 0.0, "kg", 0.0, inf,
             "parent-body mass M_PB for M_LR/M_PB (0: total mass of the earliest snapshot)");
  s.add_real("impact.target_radius", 0.0, "m", 0.0, inf, "target radius: default damage-profile range and recorded for the report (0: unknown)");
  s.add_string("impact.from_mpm", std::string(""),
               "initial mpm-frag snapshot (t = 0): impactor and target masses and velocities as discretised, "
               "for every impact.* value not given (empty: none)");
  s.add_real("fof.link_fraction", 0.2, "1", 0.0, 100.0,
             "surface linking length eps as a fraction of the median sphere radius (0.2 = pkdgrav rpa's L = 1.1 for equal spheres)");
  s.add_real("fof.link_length", 0.0, "m", 0.0, inf, "absolute surface linking length eps (> 0 overrides link_fraction)");
  s.add_real("gravity.G", 6.674e-11, "m^3/(kg s^2)", 0.0, inf, "gravitational constant", true);
  s.add_int("bound.max_iterations", 1000, 1, 1000000, "cap on the bound-mass passes");
  s.add_string("damage.field", std::string("damage"), "per-item scalar field profiled");
  s.add_string("damage.mpm_snapshot", std::string(""),
               "mpm-frag particle snapshot (or ssdem.spheres file) for the end-of-MPM damage profile (empty: none)");
  s.add_int("damage.bins", 20, 1, 100000, "bins of the profile along the impact axis");
  s.add_int("damage.radial_bins", 20, 1, 100000, "radial shells of the radial profile");
  s.add_real_list("damage.range", std::vector<double>{}, "m", -inf, inf,
                  "[lo, hi] of the axial coordinate (empty: +-1.25 impact.target_radius, or +-1.3 x the 80 %-mass radius)");
  s.add_real("damage.cylinder_radius", 0.0, "m", 0.0, inf,
             "axial profile: only items within this distance of the axis (0: all)");
  s.add_real_list("damage.axis", std::vector<double>{}, "1", -inf, inf,
                  "profile axis [x, y, z] (empty: the impact direction U/|U|, else +z)");
  s.add_real_list("damage.origin", std::vector<double>{}, "m", -inf, inf,
                  "profile origin [x, y, z] (empty: centre of mass of the profiled set; of the bound remnant at the end of the N-body run)");
  s.add_string("output.prefix", std::string("analysis"),
               "output path prefix: <prefix>.json, <prefix>.timeseries.csv, <prefix>.damage.csv");
  return s;
}

MpmImpact impact_from_mpm(const std::string& path) {
  const common::ParticleSnapshot p = common::read_particle_snapshot(path);
  const std::size_t n = p.count();
  if (n < 2) throw common::InputError(path, "/particles", "needs target and impactor particles");
  // mass-weighted median of each velocity component
  Eigen::Vector3d vref;
  std::vector<std::size_t> order(n);
  for (int d = 0; d < 3; ++d) {
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(),
              [&](std::size_t a, std::size_t b) { return p.velocity[3 * a + d] < p.velocity[3 * b + d]; });
    const double total = std::accumulate(p.mass.begin(), p.mass.end(), 0.0);
    double acc = 0.0;
    for (std::size_t k : order) {
      acc += p.mass[k];
      vref[d] = p.velocity[3 * k + d];
      if (acc >= 0.5 * total) break;
    }
  }
  double dmax = 0.0;
  for (std::size_t i = 0; i < n; ++i) dmax = std::max(dmax, (Eigen::Vector3d(&p.velocity[3 * i]) - vref).norm());
  if (!(dmax > 0))
    throw common::InputError(path, "/particles/velocity", "all particles move together: no impactor to identify");
  MpmImpact r;
  Eigen::Vector3d pi = Eigen::Vector3d::Zero(), pt = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d v(&p.velocity[3 * i]);
    if ((v - vref).norm() > 0.5 * dmax) {
      r.impactor_mass += p.mass[i];
      pi += p.mass[i] * v;
      ++r.impactor_particles;
    } else {
      r.target_mass += p.mass[i];
      pt += p.mass[i] * v;
      ++r.target_particles;
    }
  }
  r.impactor_velocity = pi / r.impactor_mass;
  r.target_velocity = pt / r.target_mass;
  if (r.impactor_mass >= r.target_mass)
    throw common::InputError(path, "/particles/velocity",
                             "the fast group is not lighter than the rest: cannot tell impactor from target");
  return r;
}

AnalyseConfig analyse_config(const common::Scene& sc) {
  AnalyseConfig c;
  c.scene_source = sc.source();
  c.impact.impactor_mass = sc.real("impact.impactor_mass");
  c.impact.impactor_velocity = sc.vec3("impact.impactor_velocity");
  c.impact.target_velocity = sc.vec3("impact.target_velocity");
  if (c.impact.impactor_mass > 0 && !c.impact.valid() && sc.string("impact.from_mpm").empty())
    throw common::InputError(sc.source(), "impact.impactor_velocity",
                             "must differ from impact.target_velocity when impact.impactor_mass > 0");
  c.parent_body_mass = sc.real("impact.parent_body_mass");
  c.target_radius = sc.real("impact.target_radius");
  c.link_fraction = sc.real("fof.link_fraction");
  c.link_length = sc.real("fof.link_length");
  c.G = sc.real("gravity.G");
  c.max_iterations = static_cast<int>(sc.integer("bound.max_iterations"));
  c.damage_field = sc.string("damage.field");
  c.damage_mpm = sc.string("damage.mpm_snapshot");
  c.axial_bins = static_cast<int>(sc.integer("damage.bins"));
  c.radial_bins = static_cast<int>(sc.integer("damage.radial_bins"));
  const auto range = sc.real_list("damage.range");
  if (!range.empty()) {
    if (range.size() != 2 || !(range[0] < range[1]))
      throw common::InputError(sc.source(), "damage.range", "expected [lo, hi] with lo < hi");
    c.range_lo = range[0];
    c.range_hi = range[1];
  }
  c.cylinder_radius = sc.real("damage.cylinder_radius");
  const auto axis = sc.real_list("damage.axis");
  if (!axis.empty()) {
    const Eigen::Vector3d a = axis.size() == 3 ? Eigen::Vector3d(axis[0], axis[1], axis[2]) : Eigen::Vector3d::Zero();
    if (!(a.norm() > 0)) throw common::InputError(sc.source(), "damage.axis", "expected [x, y, z], a non-zero vector, or []");
    c.axis = a.normalized();
  }
  const auto origin = sc.real_list("damage.origin");
  if (!origin.empty()) {
    if (origin.size() != 3) throw common::InputError(sc.source(), "damage.origin", "expected [x, y, z] or []");
    c.origin = Eigen::Vector3d(origin[0], origin[1], origin[2]);
  }
  c.impact_from_mpm = sc.string("impact.from_mpm");
  c.impactor_mass_given = sc.given("impact.impactor_mass");
  c.impactor_velocity_given = sc.given("impact.impactor_velocity");
  c.target_velocity_given = sc.given("impact.target_velocity");
  c.parent_body_mass_given = sc.given("impact.parent_body_mass");
  c.prefix = sc.string("output.prefix");
  if (c.prefix.empty()) throw common::InputError(sc.source(), "output.prefix", "must not be empty");
  return c;
}

}  // namespace analysis
