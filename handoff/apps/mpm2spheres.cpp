/// @file mpm2spheres.cpp
/// mpm2spheres: MPM particle snapshot -> soft spheres for ssdem-grav, with a conservation audit.
#include "common/cli.hpp"
#include "handoff/handoff_scene.hpp"
#include "handoff/run_handoff.hpp"

int main(int argc, char** argv) {
  common::ToolApp app("mpm2spheres",
                      "Hand-off from an mpm-frag particle snapshot to an ssdem.spheres file "
                      "(El Mir, Ramesh & Richardson 2019, section 4.2), with a mass, momentum and energy audit.",
                      handoff::handoff_schema(), /*scene_required=*/false);
  app.add_scene_flag("-i,--input", "input", "particle snapshot to read");
  app.add_scene_flag("-o,--output", "output", "sphere file to write");
  app.add_scene_flag("--method", "method", "paper | conserving");
  app.add_scene_flag("--outflow", "outflow", "mpm-frag outflow file (particles that left the grid) to hand off too");
  app.add_scene_flag("--coarsen", "coarsen", "sphere cell edge in MPM cells");
  app.add_scene_flag("--ss", "export.ss", "also write a pkdgrav .ss file");
  app.add_scene_flag("--max-ke-loss", "audit.max_energy_loss", "fail (exit 3) above this relative KE loss");
  return app.run(argc, argv, [](const common::Scene& scene, const common::Provenance& prov) {
    return handoff::run_handoff(handoff::handoff_config(scene), prov);
  });
}
