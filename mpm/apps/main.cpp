/// @file main.cpp
/// mpm-frag: 3D explicit MPM (uGIMP) for hypervelocity impacts. Thin main over the mpm library;
/// the MPI build (MPM_MPI) runs mpi/run_mpi.hpp on more than one rank.
#include "common/cli.hpp"
#include "mpm/run.hpp"
#include "mpm/scene_setup.hpp"
#ifdef MPM_MPI
#include <mpi.h>

#include "mpm/mpi/run_mpi.hpp"
#endif

int main(int argc, char** argv) {
#ifdef MPM_MPI
  int level = 0, ranks = 1;
  MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &level);
  MPI_Comm_size(MPI_COMM_WORLD, &ranks);
#endif
  common::ToolApp app("mpm-frag", "3D explicit Material Point Method (uGIMP) for impacts", mpmfrag::mpm_schema());
  std::string restart;
  app.cli().add_option("--restart", restart, "continue from a checkpoint file (bit-identical)");
  const int rc = app.run(argc, argv, [&](const common::Scene& scene, const common::Provenance& prov) {
#ifdef MPM_MPI
    if (ranks > 1) {
      const mpmfrag::RunSummary sum = mpmfrag::mpi::run_mpm_mpi(scene, prov, restart);
      return sum.signal ? 128 + sum.signal : 0;
    }
#endif
    const mpmfrag::RunSummary sum = mpmfrag::run_mpm(scene, prov, restart);
    return sum.signal ? 128 + sum.signal : 0;
  });
#ifdef MPM_MPI
  // a failure stops every rank (a rank left in a collective would wait for ever); a signal
  // (exit 128 + signal) is acted on by every rank after the same step: they finish together
  if (rc != 0 && rc < 128 && ranks > 1) MPI_Abort(MPI_COMM_WORLD, rc);
  MPI_Finalize();
#endif
  return rc;
}
