/// @file main.cpp
/// mpm-frag: 3D explicit MPM (uGIMP) for hypervelocity impacts. Thin main over the mpm library.
#include "common/cli.hpp"
#include "mpm/run.hpp"
#include "mpm/scene_setup.hpp"

int main(int argc, char** argv) {
  common::ToolApp app("mpm-frag", "3D explicit Material Point Method (uGIMP) for impacts", mpmfrag::mpm_schema());
  std::string restart;
  app.cli().add_option("--restart", restart, "continue from a checkpoint file (bit-identical)");
  return app.run(argc, argv, [&](const common::Scene& scene, const common::Provenance& prov) {
    const mpmfrag::RunSummary sum = mpmfrag::run_mpm(scene, prov, restart);
    return sum.signal ? 128 + sum.signal : 0;
  });
}
