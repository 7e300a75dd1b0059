/// @file outcome_checks.cpp
/// ssdem-analyse: every number about to be written checked finite (run_analysis.hpp,
/// check_outcome_finite); a NaN or Inf ends the tool with exit 3 naming the quantity.
#include "analysis/run_analysis.hpp"
#include "common/finite.hpp"

namespace analysis {

void check_outcome_finite(const AnalysisOutcome& o, const std::string& path) {
  auto check = [&](const std::string& what, const double* v, std::size_t n, const std::string& name) {
    common::require_finite(v, n, path + ": " + what, name);
  };
  check("analysis", &o.parent_body_mass, 1, "parent_body_mass");
  check("analysis", &o.link_length, 1, "link_length");
  for (const SnapshotResult& r : o.rows) {
    const std::string at = r.file + " (t = " + std::to_string(r.time) + " s)";
    const BoundResult& b = r.bound;
    const double scalars[] = {r.time, b.total_mass, b.lr_mass, b.bound_mass, b.escaping_mass, r.speed_escaping_mass};
    const char* names[] = {"time", "total_mass", "M_LR", "bound_mass", "escaping_mass", "speed_escaping_mass"};
    for (std::size_t k = 0; k < 6; ++k) check(at, &scalars[k], 1, names[k]);
    check(at, b.escaping_momentum.data(), 3, "escaping_momentum");
    check(at, r.lr_velocity.data(), 3, "largest_remnant_velocity");
    check(at, r.bound_velocity.data(), 3, "bound_remnant_velocity");
    if (r.beta) {
      const BetaResult& e = *r.beta;
      const double betas[] = {e.beta, e.beta_lr, e.beta_ejecta, e.beta_total, e.momentum_error, e.escaping_momentum_along};
      const char* bn[] = {"beta", "beta_lr", "beta_ejecta", "beta_total", "momentum_error", "escaping_momentum_along_impact"};
      for (std::size_t k = 0; k < 6; ++k) check(at, &betas[k], 1, bn[k]);
      if (e.beta_vector) check(at, &*e.beta_vector, 1, "beta_vector");
    }
    if (r.beta_escape_speed) check(at, &*r.beta_escape_speed, 1, "beta_escape_speed");
  }
  for (const ProfileRecord& p : o.profiles)
    for (const ProfileBin& bin : p.bins) {
      const double v[] = {bin.lo, bin.hi, bin.mass};  // mean is NaN for an empty bin (written blank)
      check(p.source + " damage profile (" + p.stage + ")", v, 3, "bin lo/hi/mass");
    }
}

}  // namespace analysis
