/// @file ssdem_grav.cpp
/// ssdem-grav: self-gravity + soft-sphere DEM. Thin main over the nbody library (run.hpp); the MPI
/// build (SSDEM_MPI) runs mpi/run_mpi.hpp on more than one rank.
#include <cstdio>

#include "common/cli.hpp"
#include "ssdem/run.hpp"
#include "ssdem/scene_setup.hpp"
#ifdef SSDEM_MPI
#include <mpi.h>

#include "ssdem/mpi/run_mpi.hpp"
#endif

int main(int argc, char** argv) {
#if defined(SSDEM_CONTACT_AVX2) && defined(__x86_64__)
  // the contact kernel was compiled for AVX2 (CMake SUITE_SIMD): say so rather than die on SIGILL
  if (!__builtin_cpu_supports("avx2")) {
    std::fprintf(stderr, "ssdem-grav: this binary was built with AVX2 (SUITE_SIMD) and this CPU has no AVX2; "
                         "rebuild with cmake -DSUITE_SIMD=baseline\n");
    return 4;
  }
#endif
#ifdef SSDEM_MPI
  int level = 0, ranks = 1;
  MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &level);
  MPI_Comm_size(MPI_COMM_WORLD, &ranks);
#endif
  common::ToolApp app("ssdem-grav", "Self-gravity (octree) + soft-sphere DEM (Schwartz 2012, Zhang 2017)",
                      ssdem::ssdem_schema());
  std::string restart;
  app.cli().add_option("--restart", restart, "continue from a checkpoint file (bit-identical)");
  const int rc = app.run(argc, argv, [&](const common::Scene& scene, const common::Provenance& prov) {
#ifdef SSDEM_MPI
    if (ranks > 1) return ssdem::mpi::run_ssdem_mpi(scene, prov, restart);
#endif
#ifdef SSDEM_MPI
    return ssdem::run_ssdem(scene, prov, restart, false);  // the MPI build keeps the file order
#else
    return ssdem::run_ssdem(scene, prov, restart);
#endif
  });
#ifdef SSDEM_MPI
  // a failure stops every rank (a rank left in a collective would wait for ever)
  if (rc != 0 && ranks > 1) MPI_Abort(MPI_COMM_WORLD, rc);
  MPI_Finalize();
#endif
  return rc;
}
