/// @file analysis_outputs.cpp
/// ssdem-analyse outputs (analysis/run_analysis.hpp): the time-series CSV, the damage-profile CSV,
/// the summary JSON and their atomic, all-or-nothing write.
#include <spdlog/spdlog.h>

#include <cmath>
#include <filesystem>
#include <sstream>

#include "analysis/json_writer.hpp"
#include "analysis/run_analysis.hpp"
#include "common/atomic_file.hpp"
#include "common/series_csv.hpp"
#include "common/status.hpp"

namespace analysis {

namespace {

std::string fmt_num(double v) {
  if (!std::isfinite(v)) return "";
  std::ostringstream o;
  o.precision(12);
  o << v;
  return o.str();
}

}  // namespace

std::string timeseries_csv(const AnalysisOutcome& o) {
  // 12 significant digits, NaN/Inf and absent values as empty cells (as fmt_num).
  common::SeriesTable t(common::SeriesFormat({{"time", "s"},
                                              {"M_LR_over_M_PB", "1"},
                                              {"bound_mass_fraction", "1"},
                                              {"beta", "1"},
                                              {"n_clumps", ""},
                                              {"escaping_mass", "kg"},
                                              {"step", ""},
                                              {"file", ""},
                                              {"n_spheres", ""},
                                              {"n_single", ""},
                                              {"lr_spheres", ""},
                                              {"M_LR", "kg"},
                                              {"bound_mass", "kg"},
                                              {"total_mass", "kg"},
                                              {"n_bound_clumps", ""},
                                              {"p_esc_x", "kg m/s"},
                                              {"p_esc_y", "kg m/s"},
                                              {"p_esc_z", "kg m/s"},
                                              {"p_esc_along_impact", "kg m/s"},
                                              {"beta_lr", "1"},
                                              {"beta_ejecta", "1"},
                                              {"beta_vector", "1"},
                                              {"beta_total", "1"},
                                              {"momentum_error", "1"},
                                              {"bound_iterations", ""},
                                              {"speed_escaping_mass", "kg"},
                                              {"beta_escape_speed", "1"}},
                                             {.precision = 12, .blank_non_finite = true}));
  const double mpb = o.parent_body_mass;
  for (const auto& r : o.rows) {
    const auto& b = r.bound;
    const Eigen::Vector3d pe = r.beta ? r.beta->escaping_momentum : b.escaping_momentum;
    auto beta = [&](double BetaResult::*m) { return r.beta ? std::optional<double>((*r.beta).*m) : std::nullopt; };
    common::SeriesRow row = t.row();
    row.num(r.time).num(b.lr_mass / mpb).num(b.bound_mass / mpb).num(beta(&BetaResult::beta));
    row.integer(r.n_clumps).num(b.escaping_mass).integer(r.step).text(r.file);
    row.integer(r.n_spheres).integer(r.n_singles).integer(r.lr_count);
    row.num(b.lr_mass).num(b.bound_mass).num(b.total_mass).integer(b.n_bound_clumps);
    row.num(pe[0]).num(pe[1]).num(pe[2]).num(beta(&BetaResult::escaping_momentum_along));
    row.num(beta(&BetaResult::beta_lr)).num(beta(&BetaResult::beta_ejecta));
    row.num(r.beta ? r.beta->beta_vector : std::nullopt);
    row.num(beta(&BetaResult::beta_total)).num(beta(&BetaResult::momentum_error));
    row.integer(b.iterations).num(r.speed_escaping_mass).num(r.beta_escape_speed);
    t.add(row);
  }
  return t.str();
}

std::string damage_csv(const AnalysisOutcome& o) {
  std::ostringstream s;
  s << "stage,source,time,set,kind,bin,lo,hi,centre,count,mass,mean_damage\n";
  for (const auto& p : o.profiles)
    for (std::size_t k = 0; k < p.bins.size(); ++k) {
      const auto& b = p.bins[k];
      s << p.stage << ',' << p.source << ',' << fmt_num(p.time) << ',' << p.set << ',' << p.kind << ',' << k << ','
        << fmt_num(b.lo) << ',' << fmt_num(b.hi) << ',' << fmt_num(b.centre()) << ',' << b.count << ','
        << fmt_num(b.mass) << ',' << fmt_num(b.mean) << '\n';
    }
  return s.str();
}

namespace {
std::string out_path(const AnalyseConfig& c, const std::string& suffix) { return c.prefix + suffix; }
}  // namespace

std::string summary_json(const AnalysisOutcome& o, const AnalyseConfig& cfg_in, const common::Provenance& prov) {
  const AnalyseConfig& cfg = o.cfg ? *o.cfg : cfg_in;  // the values actually used
  JsonWriter j;
  j.begin_object();
  j.value("format", "ssdem-analyse.summary").value("format_version", 1LL);
  j.begin_object("provenance")
      .value("tool", prov.tool)
      .value("version", prov.version)
      .value("git_sha", prov.git_sha)
      .value("command_line", prov.command_line)
      .value("scene", prov.scene_toml)
      .end_object();
  std::vector<std::string> files;
  for (const auto& r : o.rows) files.push_back(r.file);
  j.begin_object("inputs")
      .value("snapshots", files)
      .value("mpm_snapshot", cfg.damage_mpm)
      .value("impactor_mass", cfg.impact.impactor_mass)
      .value("impactor_velocity", cfg.impact.impactor_velocity)
      .value("target_velocity", cfg.impact.target_velocity)
      .value("impact_speed", cfg.impact.relative_velocity().norm())
      .value("impactor_momentum", cfg.impact.impactor_momentum())
      .value("impact_direction", cfg.impact.direction())
      .value("impact_source", o.impact_source.empty() ? std::string("scene") : o.impact_source)
      .value("impact_from_mpm", cfg.impact_from_mpm);
  if (o.mpm_impact) {
    j.begin_object("mpm_initial")
        .value("impactor_mass", o.mpm_impact->impactor_mass)
        .value("impactor_velocity", o.mpm_impact->impactor_velocity)
        .value("impactor_particles", static_cast<long long>(o.mpm_impact->impactor_particles))
        .value("target_mass", o.mpm_impact->target_mass)
        .value("target_velocity", o.mpm_impact->target_velocity)
        .value("target_particles", static_cast<long long>(o.mpm_impact->target_particles))
        .end_object();
  }
  j
      .value("parent_body_mass", o.parent_body_mass)
      .value("parent_body_mass_source", o.parent_body_mass_source)
      .value("target_radius", cfg.target_radius)
      .value("G", cfg.G)
      .value("link_length", o.link_length)
      .value("link_fraction", cfg.link_length > 0 ? std::optional<double>() : std::optional<double>(cfg.link_fraction))
      .value("damage_field", cfg.damage_field)
      .end_object();
  j.begin_object("definitions")
      .value("frame", "velocities and momenta in the rest frame of the target before impact: v - impact.target_velocity")
      .value("clumps", "friends-of-friends on sphere surfaces: i and j linked if |x_i - x_j| - r_i - r_j < link_length")
      .value("largest_remnant", "most massive clump (M_LR)")
      .value("bound", "clumps added iteratively to the largest remnant while 0.5|v_k - V|^2 - G (M + m_k)/|r_k - R| < 0 "
                      "(M, R, V: mass, centre of mass and centre-of-mass velocity of the current remnant)")
      .value("escaping", "all material not bound to the largest remnant")
      .value("beta", "beta = P_bound . U_hat / (m_imp |U|): momentum of the bound remnant (incl. embedded impactor "
                     "material) along the impact direction over the impactor momentum (Holsapple & Housen 2012)")
      .value("beta_lr", "as beta with the largest clump only")
      .value("beta_ejecta", "1 - P_esc . U_hat / (m_imp |U|); equals beta when momentum is conserved")
      .value("beta_vector", "Cheng et al. 2023 eq. 1: M dv = m U + m (beta-1)(E.U) E, E parallel to P_bound - m U")
      .value("beta_total", "P_bound . U_hat / P_total . U_hat: the snapshot's own total momentum as reference "
                           "(equals beta when P_total = m_imp U)")
      .value("beta_escape_speed", "1 - P_esc,speed . U_hat / (m_imp |U|) with every sphere escaping on its own if "
                                  "0.5|v - V|^2 + Phi(|x - C|) >= 0, Phi of a uniform sphere of the bound mass, radius "
                                  "speed_reference_radius, centred on the bound remnant (usable at hand-off time)")
      .value("momentum_error", "|P_total - m_imp U| / (m_imp |U|)")
      .value("M_LR_over_M_PB", "largest-clump mass over parent-body mass")
      .value("bound_mass_fraction", "bound-remnant mass over parent-body mass")
      .value("damage_profile", "mass-weighted mean damage in bins of (x - origin).axis (axial) or |x - origin| (radial); "
                               "range [-L, L] (axial) and [0, L] (radial) with L = damage.range, else 1.25 x "
                               "impact.target_radius, else 1.3 x the radius holding 80 % of the profiled mass; "
                               "origin = centre of mass of the profiled set (at the end of the N-body run: of the bound remnant) unless "
                               "damage.origin is given; "
                               "axis = impact direction unless damage.axis is given (impact site at negative axial coordinate)")
      .end_object();
  if (!o.rows.empty()) {
    const auto& r = o.rows.back();
    const auto& b = r.bound;
    const double mpb = o.parent_body_mass;
    j.begin_object("final")
        .value("file", r.file)
        .value("time", r.time)
        .value("step", r.step)
        .value("n_spheres", static_cast<long long>(r.n_spheres))
        .value("total_mass", b.total_mass)
        .value("n_clumps", static_cast<long long>(r.n_clumps))
        .value("n_single_spheres", static_cast<long long>(r.n_singles))
        .value("largest_remnant_spheres", static_cast<long long>(r.lr_count))
        .value("M_LR", b.lr_mass)
        .value("M_LR_over_M_PB", b.lr_mass / mpb)
        .value("largest_remnant_velocity", r.lr_velocity)
        .value("bound_mass", b.bound_mass)
        .value("bound_mass_fraction", b.bound_mass / mpb)
        .value("n_bound_clumps", static_cast<long long>(b.n_bound_clumps))
        .value("bound_remnant_velocity", r.bound_velocity)
        .value("bound_iterations", static_cast<long long>(b.iterations))
        .value("escaping_mass", b.escaping_mass)
        .value("escaping_mass_fraction", b.escaping_mass / mpb)
        .value("speed_escaping_mass", r.speed_escaping_mass)
        .value("speed_reference_radius", r.speed_reference_radius);
    if (r.beta) {
      j.value("escaping_momentum", r.beta->escaping_momentum)
          .value("escaping_momentum_along_impact", r.beta->escaping_momentum_along)
          .value("beta", r.beta->beta)
          .value("beta_lr", r.beta->beta_lr)
          .value("beta_ejecta", r.beta->beta_ejecta)
          .value("beta_vector", r.beta->beta_vector)
          .value("beta_total", r.beta->beta_total)
          .value("beta_escape_speed", r.beta_escape_speed)
          .value("momentum_error", r.beta->momentum_error);
    } else {
      j.value("escaping_momentum", b.escaping_momentum)
          .null("escaping_momentum_along_impact")
          .null("beta")
          .null("beta_lr")
          .null("beta_ejecta")
          .null("beta_vector")
          .null("beta_total")
          .null("beta_escape_speed")
          .null("momentum_error");
    }
    j.end_object();
  }
  j.begin_object("outputs")
      .value("summary_json", out_path(cfg, ".json"))
      .value("timeseries_csv", out_path(cfg, ".timeseries.csv"))
      .value("damage_csv", out_path(cfg, ".damage.csv"))
      .end_object();
  j.value("notes", o.notes);
  j.end_object();
  return j.str();
}

void write_outputs(const AnalysisOutcome& o, const AnalyseConfig& cfg, const common::Provenance& prov) {
  const std::filesystem::path parent = std::filesystem::path(cfg.prefix).parent_path();
  if (!parent.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(parent, ec);
    if (ec) throw common::IoError("cannot create directory " + parent.string() + ": " + ec.message());
  }
  check_outcome_finite(o, out_path(cfg, ".json"));
  // the three files as a set: all written to temporaries, renamed only when all succeeded (the
  // JSON last: its presence means the set is complete); a failure leaves the earlier set as it was
  common::write_text_set_atomic({{out_path(cfg, ".timeseries.csv"), timeseries_csv(o)},
                                 {out_path(cfg, ".damage.csv"), damage_csv(o)},
                                 {out_path(cfg, ".json"), summary_json(o, cfg, prov)}});
  spdlog::info("wrote {}.json, {}.timeseries.csv, {}.damage.csv", cfg.prefix, cfg.prefix, cfg.prefix);
}

}  // namespace analysis
