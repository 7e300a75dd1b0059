/// @file ssdem_grav.cpp
/// ssdem-grav: self-gravity + soft-sphere DEM. Thin main over the nbody library (run.hpp).
#include "common/cli.hpp"
#include "ssdem/run.hpp"
#include "ssdem/scene_setup.hpp"

int main(int argc, char** argv) {
  common::ToolApp app("ssdem-grav", "Self-gravity (octree) + soft-sphere DEM (Schwartz 2012, Zhang 2017)",
                      ssdem::ssdem_schema());
  std::string restart;
  app.cli().add_option("--restart", restart, "continue from a checkpoint file (bit-identical)");
  return app.run(argc, argv, [&](const common::Scene& scene, const common::Provenance& prov) {
    return ssdem::run_ssdem(scene, prov, restart);
  });
}
