/// @file ssdem_analyse.cpp
/// ssdem-analyse: reaccumulation analysis of ssdem.spheres snapshots (clumps, largest remnant,
/// bound mass, escaping mass and momentum, beta, damage profiles).
#include <string>
#include <vector>

#include "analysis/analyse_scene.hpp"
#include "analysis/run_analysis.hpp"
#include "common/cli.hpp"

int main(int argc, char** argv) {
  common::ToolApp app("ssdem-analyse",
                      "Reaccumulation analysis of ssdem.spheres snapshots: friends-of-friends clumps on sphere "
                      "surfaces, largest remnant, mass bound to it (two-body energy), escaping mass and momentum, "
                      "momentum enhancement beta, damage profiles along the impact axis (El Mir et al. 2019, Fig. 6).",
                      analysis::analyse_schema(), /*scene_required=*/false);
  std::vector<std::string> inputs;
  app.cli().add_option("inputs", inputs, "ssdem.spheres snapshots (sorted by their time attribute)");
  app.add_scene_flag("-o,--output-prefix", "output.prefix",
                     "writes <prefix>.json, <prefix>.timeseries.csv, <prefix>.damage.csv");
  app.add_scene_flag("--mpm", "damage.mpm_snapshot", "mpm-frag snapshot for the end-of-MPM damage profile");
  app.add_scene_flag("--mpm-initial", "impact.from_mpm",
                     "mpm-frag snapshot at t = 0: impactor/target masses and velocities as discretised");
  app.add_scene_flag("--impactor-mass", "impact.impactor_mass", "impactor mass [kg]");
  app.add_scene_flag("--impactor-velocity", "impact.impactor_velocity", "impactor velocity [m/s], e.g. [0,0,-5000]");
  app.add_scene_flag("--parent-mass", "impact.parent_body_mass", "parent-body mass M_PB [kg]");
  app.add_scene_flag("--link-fraction", "fof.link_fraction", "surface linking length / median radius");
  return app.run(argc, argv, [&](const common::Scene& scene, const common::Provenance& prov) {
    analysis::AnalyseConfig cfg = analysis::analyse_config(scene);
    cfg.inputs = inputs;
    const analysis::AnalysisOutcome o = analysis::run_analysis(cfg);
    analysis::write_outputs(o, cfg, prov);
    return 0;
  });
}
