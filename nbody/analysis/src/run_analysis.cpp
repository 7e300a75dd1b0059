/// @file run_analysis.cpp
/// ssdem-analyse driver (analysis/run_analysis.hpp): reads snapshots and applies fof/bound/momentum/damage_profile; the outputs are written by analysis_outputs.cpp.
#include "analysis/run_analysis.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numeric>

#include "analysis/escape_speed.hpp"
#include "common/h5.hpp"
#include "common/particle_file.hpp"
#include "common/status.hpp"

namespace analysis {

namespace {

Eigen::Vector3d centre_of_mass(const double* x, const double* m, std::size_t n, const char* sel) {
  Eigen::Vector3d s = Eigen::Vector3d::Zero();
  double M = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    if (sel && !sel[i]) continue;
    s += m[i] * Eigen::Vector3d(x + 3 * i);
    M += m[i];
  }
  return M > 0 ? Eigen::Vector3d(s / M) : Eigen::Vector3d::Zero();
}

struct Header {
  std::string file, format, tool;
  double time = 0.0;       ///< N-body clock: 0 for the hand-off file (ssdem-grav starts at t = 0)
  double file_time = 0.0;  ///< the file's own `time` attribute
};

Header read_header(const std::string& path) {
  namespace h5 = common::h5;
  h5::quiet_errors();
  h5::Handle f = h5::open_file_read(path);
  Header h;
  h.file = path;
  if (!h5::has_attr(f, "format")) throw common::InputError(path, "/format", "missing format attribute (not a suite file)");
  h.format = h5::read_attr_string(f, "format", path);
  if (h5::has_attr(f, "time")) h.file_time = h5::read_attr_double(f, "time", path);
  if (h5::exists(f, "provenance")) h.tool = h5::read_provenance(f, path).tool;
  // mpm2spheres stamps its output with the MPM time; ssdem-grav restarts the clock at 0 from it.
  h.time = h.tool == "mpm2spheres" ? 0.0 : h.file_time;
  return h;
}

Eigen::Vector3d profile_axis(const AnalyseConfig& cfg, std::vector<std::string>& notes) {
  if (cfg.axis) return *cfg.axis;
  if ((cfg.impact.impactor_velocity - cfg.impact.target_velocity).norm() > 0) return cfg.impact.direction();
  notes.push_back("damage profile axis: no impact velocity given, using +z");
  return Eigen::Vector3d::UnitZ();
}

void add_profiles(AnalysisOutcome& o, const AnalyseConfig& cfg, const std::string& file, const std::string& stage,
                  double time, const std::string& set, const double* x, const double* m, const double* d,
                  std::size_t n, const char* sel, const Eigen::Vector3d& axis, const char* origin_sel = nullptr) {
  ProfileSpec spec;
  spec.axis = axis;
  spec.origin = cfg.origin ? *cfg.origin : centre_of_mass(x, m, n, origin_sel ? origin_sel : sel);
  spec.bins = cfg.axial_bins;
  spec.cylinder_radius = cfg.cylinder_radius;
  // Default range: the body, not the ejecta cloud (which may be 100x larger): 1.25 x the target
  // radius when known, else 1.3 x the radius about the origin holding 80 % of the mass.
  double reach = 1.25 * cfg.target_radius;
  if (!(reach > 0)) {
    std::vector<std::pair<double, double>> dm;
    for (std::size_t i = 0; i < n; ++i)
      if (!sel || sel[i]) dm.emplace_back((Eigen::Vector3d(x + 3 * i) - spec.origin).norm(), m[i]);
    std::sort(dm.begin(), dm.end());
    double total = 0.0, acc = 0.0;
    for (const auto& e : dm) total += e.second;
    reach = 0.0;
    for (const auto& e : dm) {
      acc += e.second;
      reach = e.first;
      if (acc >= 0.8 * total) break;
    }
    reach *= 1.3;
  }
  if (cfg.range_lo < cfg.range_hi) {
    spec.lo = cfg.range_lo;
    spec.hi = cfg.range_hi;
  } else if (reach > 0) {
    spec.lo = -reach;
    spec.hi = reach;
  }
  ProfileRecord r{file, stage, time, set, "axial", spec.origin, axis, axial_profile(x, m, d, n, spec, sel)};
  o.profiles.push_back(r);
  spec.bins = cfg.radial_bins;
  spec.lo = 0.0;
  spec.hi = reach > 0 ? reach : 0.0;
  if (cfg.range_lo < cfg.range_hi) spec.hi = std::max(std::abs(cfg.range_lo), std::abs(cfg.range_hi));
  r.kind = "radial";
  r.bins = radial_profile(x, m, d, n, spec, sel);
  o.profiles.push_back(r);
}

}  // namespace

SnapshotResult analyse_snapshot(const common::SphereSet& s, const AnalyseConfig& cfg, double eps,
                                std::vector<char>* sphere_bound, double parent_body_mass) {
  SnapshotResult r;
  r.time = s.time;
  r.step = s.step;
  r.n_spheres = s.count();
  const FofResult fof = friends_of_friends(s.position.data(), s.radius.data(), s.mass.data(), s.count(), eps);
  r.n_clumps = fof.count();
  r.n_singles = fof.singles();
  r.lr_count = fof.count() ? static_cast<std::size_t>(fof.clump_count[0]) : 0;
  const ClumpProps cp = clump_properties(s.position.data(), s.velocity.data(), s.mass.data(), s.count(), fof);
  r.bound = bound_to_largest(cp, cfg.G, cfg.max_iterations);
  if (r.bound.iterations >= cfg.max_iterations)
    spdlog::warn("t = {} s: bound-mass iteration hit bound.max_iterations = {}", s.time, cfg.max_iterations);
  if (r.bound.lr_mass > 0) r.lr_velocity = r.bound.lr_momentum / r.bound.lr_mass;
  if (r.bound.bound_mass > 0) r.bound_velocity = r.bound.bound_momentum / r.bound.bound_mass;
  if (cfg.impact.valid()) r.beta = momentum_enhancement(r.bound, cfg.impact);
  // Sphere-by-sphere escape speed about the bound remnant, a uniform sphere of radius R_ref =
  // impact.target_radius x (M_bound / M_PB)^(1/3) if given, else sqrt(5/3) x its rms radius.
  {
    double R = 0.0;
    if (cfg.target_radius > 0 && parent_body_mass > 0) {
      R = cfg.target_radius * std::cbrt(r.bound.bound_mass / parent_body_mass);
    } else {
      double m2 = 0.0, mm = 0.0;
      for (std::size_t i = 0; i < s.count(); ++i) {
        if (!r.bound.bound[fof.clump_of[i]]) continue;
        m2 += s.mass[i] * (Eigen::Vector3d(&s.position[3 * i]) - r.bound.bound_com).squaredNorm();
        mm += s.mass[i];
      }
      R = mm > 0 ? std::sqrt(5.0 / 3.0 * m2 / mm) : 0.0;
    }
    if (!(R > 0)) R = s.radius.empty() ? 1.0 : s.radius[0];
    const SpeedEscape se = escape_by_speed(s.position.data(), s.velocity.data(), s.mass.data(), s.count(),
                                           r.bound.bound_mass, R, r.bound.bound_com, r.bound_velocity, cfg.G);
    r.speed_escaping_mass = se.escaping_mass;
    r.speed_reference_radius = R;
    if (cfg.impact.valid()) {
      const Eigen::Vector3d p = se.escaping_momentum - se.escaping_mass * cfg.impact.target_velocity;
      r.beta_escape_speed = 1.0 - p.dot(cfg.impact.direction()) / cfg.impact.impactor_momentum();
    }
  }
  if (sphere_bound) {
    sphere_bound->assign(s.count(), 0);
    for (std::size_t i = 0; i < s.count(); ++i) (*sphere_bound)[i] = r.bound.bound[fof.clump_of[i]];
  }
  r.bound.bound.clear();
  r.bound.bound.shrink_to_fit();
  return r;
}

AnalysisOutcome run_analysis(const AnalyseConfig& cfg_in) {
  AnalyseConfig cfg = cfg_in;
  if (cfg.inputs.empty()) throw common::InputError(cfg.scene_source, "inputs", "no snapshot given");
  std::string impact_source = "scene";
  std::optional<MpmImpact> mpm0;
  if (!cfg.impact_from_mpm.empty()) {
    mpm0 = impact_from_mpm(cfg.impact_from_mpm);
    if (!cfg.impactor_mass_given) cfg.impact.impactor_mass = mpm0->impactor_mass;
    if (!cfg.impactor_velocity_given) cfg.impact.impactor_velocity = mpm0->impactor_velocity;
    if (!cfg.target_velocity_given) cfg.impact.target_velocity = mpm0->target_velocity;
    if (!cfg.parent_body_mass_given) cfg.parent_body_mass = mpm0->target_mass;
    impact_source = "initial MPM snapshot " + cfg.impact_from_mpm + " for the values not given in the scene";
    spdlog::info("{}: impactor {} particles, {:.6g} kg at [{:.6g}, {:.6g}, {:.6g}] m/s; target {} particles, {:.6g} kg",
                 cfg.impact_from_mpm, mpm0->impactor_particles, mpm0->impactor_mass, mpm0->impactor_velocity[0],
                 mpm0->impactor_velocity[1], mpm0->impactor_velocity[2], mpm0->target_particles, mpm0->target_mass);
    if (cfg.impact.impactor_mass > 0 && !cfg.impact.valid())
      throw common::InputError(cfg.impact_from_mpm, "/particles/velocity", "impactor and target velocities coincide");
  }
  std::vector<Header> heads;
  for (const auto& f : cfg.inputs) {
    Header h = read_header(f);
    if (h.format != common::kSphereFormat)
      throw common::InputError(f, "/format", "is \"" + h.format + "\", expected \"" + common::kSphereFormat +
                                                 "\" (ssdem-analyse reads mpm2spheres/ssdem-grav sphere files; "
                                                 "pass an MPM snapshot with --mpm)");
    heads.push_back(h);
  }
  std::stable_sort(heads.begin(), heads.end(), [](const Header& a, const Header& b) { return a.time < b.time; });

  AnalysisOutcome o;
  o.cfg = cfg;
  o.impact_source = impact_source;
  if (mpm0) o.mpm_impact = *mpm0;
  const Eigen::Vector3d axis = profile_axis(cfg, o.notes);
  common::SphereSet last;
  std::vector<char> last_bound;
  for (std::size_t k = 0; k < heads.size(); ++k) {
    common::SphereSet s = common::read_sphere_set(heads[k].file);
    if (s.count() == 0) throw common::InputError(heads[k].file, "/spheres", "contains no spheres");
    if (k == 0) {
      o.link_length = cfg.link_length > 0 ? cfg.link_length
                                          : default_link_length(s.radius.data(), s.count(), cfg.link_fraction);
      if (cfg.parent_body_mass > 0) {
        o.parent_body_mass = cfg.parent_body_mass;
        o.parent_body_mass_source = (mpm0 && !cfg.parent_body_mass_given)
                                        ? "target particles of " + cfg.impact_from_mpm
                                        : "scene (impact.parent_body_mass)";
      } else {
        o.parent_body_mass = std::accumulate(s.mass.begin(), s.mass.end(), 0.0);
        o.parent_body_mass_source = "total mass of the earliest snapshot (" + heads[k].file + ")";
      }
      const common::Field* d = s.field(cfg.damage_field);
      if (d && d->ncomp == 1 && heads.size() > 1)
        add_profiles(o, cfg, heads[k].file, "handoff", heads[k].time, "all", s.position.data(), s.mass.data(),
                     d->values.data(), s.count(), nullptr, axis);
    }
    std::vector<char> bound;
    SnapshotResult r =
        analyse_snapshot(s, cfg, o.link_length, k + 1 == heads.size() ? &bound : nullptr, o.parent_body_mass);
    r.file = heads[k].file;
    r.time = heads[k].time;
    spdlog::info("{}: t = {:.6g} s, {} spheres, {} clumps, M_LR/M_PB = {:.6f}, bound {:.6f}{}", r.file, r.time,
                 r.n_spheres, r.n_clumps, r.bound.lr_mass / o.parent_body_mass,
                 r.bound.bound_mass / o.parent_body_mass,
                 r.beta ? fmt::format(", beta = {:.6f}", r.beta->beta) : std::string());
    o.rows.push_back(std::move(r));
    if (k + 1 == heads.size()) {
      last = std::move(s);
      last_bound = std::move(bound);
    }
  }
  // End of the N-body run: all material and the bound remnant.
  const common::Field* d = last.field(cfg.damage_field);
  if (d && d->ncomp == 1) {
    const auto& r = o.rows.back();
    // both about the bound remnant's centre of mass (escaping ejecta would drag the COM of "all"
    // far from the body)
    add_profiles(o, cfg, r.file, "nbody_end", r.time, "all", last.position.data(), last.mass.data(),
                 d->values.data(), last.count(), nullptr, axis, last_bound.data());
    add_profiles(o, cfg, r.file, "nbody_end", r.time, "bound", last.position.data(), last.mass.data(),
                 d->values.data(), last.count(), last_bound.data(), axis);
  } else {
    o.notes.push_back("no scalar '" + cfg.damage_field + "' field in " + o.rows.back().file +
                      ": no end-of-N-body damage profile");
  }
  // End of MPM.
  if (!cfg.damage_mpm.empty()) {
    const Header h = read_header(cfg.damage_mpm);
    if (h.format == common::kParticleFormat) {
      const common::ParticleSnapshot p = common::read_particle_snapshot(cfg.damage_mpm);
      const common::Field* f = p.field(cfg.damage_field);
      if (!f || f->ncomp != 1)  // a scene without a damage model writes none: not an error
        o.notes.push_back(cfg.damage_mpm + ": /particles/" + cfg.damage_field +
                          " missing or not scalar: no end-of-MPM damage profile");
      else
        add_profiles(o, cfg, cfg.damage_mpm, "mpm_end", p.time, "all", p.position.data(), p.mass.data(),
                     f->values.data(), p.count(), nullptr, axis);
    } else if (h.format == common::kSphereFormat) {
      const common::SphereSet p = common::read_sphere_set(cfg.damage_mpm);
      const common::Field* f = p.field(cfg.damage_field);
      if (!f || f->ncomp != 1)
        o.notes.push_back(cfg.damage_mpm + ": /spheres/" + cfg.damage_field +
                          " missing or not scalar: no end-of-MPM damage profile");
      else
        add_profiles(o, cfg, cfg.damage_mpm, "mpm_end", p.time, "all", p.position.data(), p.mass.data(),
                     f->values.data(), p.count(), nullptr, axis);
    } else {
      throw common::InputError(cfg.damage_mpm, "/format",
                               "is \"" + h.format + "\", expected mpm-frag.particles or ssdem.spheres");
    }
  }
  for (const auto& n : o.notes) spdlog::warn("{}", n);
  return o;
}

}  // namespace analysis
