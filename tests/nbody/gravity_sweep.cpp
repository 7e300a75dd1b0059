/// @file gravity_sweep.cpp
/// nbody-gravity-sweep: rms relative force error of the tree against direct summation and the
/// cost of one tree force evaluation (us per sphere, median of `reps`, current OMP thread count)
/// across opening angle, leaf bucket size and sink group size, on a sphere file (the dense pile, the debris cloud),
/// to choose gravity.theta and gravity.bucket by measurement (pipelines/nbody, nbody-gravity-sweep).
/// Usage: nbody-gravity-sweep SPHERES.h5 [thetas=0.3,0.4,0.5,0.6,0.7] [buckets=8,16] [groups=32,64,128] [reps=3]
/// SWEEP_NO_DIRECT set (to anything but "" or "0") in the environment: cost only, no direct summation (O(N^2): minutes at 2e5
/// spheres); the error columns then read "-".
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

#include "common/sphere_file.hpp"
#include "ssdem/gravity.hpp"
#include "ssdem/io.hpp"

namespace {
std::vector<double> list(const char* s) {
  std::vector<double> v;
  std::stringstream ss(s);
  for (std::string t; std::getline(ss, t, ',');) v.push_back(std::stod(t));
  return v;
}
}  // namespace

int main(int argc, char** argv) {
  using namespace ssdem;
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s SPHERES.h5 [thetas] [buckets] [groups] [reps]\n", argv[0]);
    return 2;
  }
  const Spheres sp = from_sphere_set(common::read_sphere_set(argv[1]));
  const std::vector<double> thetas = list(argc > 2 ? argv[2] : "0.3,0.4,0.5,0.6,0.7");
  const std::vector<double> buckets = list(argc > 3 ? argv[3] : "8,16");
  const std::vector<double> groups = list(argc > 4 ? argv[4] : "32,64,128");
  const int reps = argc > 5 ? std::atoi(argv[5]) : 3;
  const char* nd = std::getenv("SWEEP_NO_DIRECT");
  const bool no_direct = nd != nullptr && *nd != '\0' && std::string(nd) != "0";
  std::vector<Vec3> ad;
  if (!no_direct) direct_gravity(sp, 1.0, ad);
  double arms = 0;
  for (const Vec3& v : ad) arms += v.squaredNorm();
  arms = std::sqrt(arms / static_cast<double>(sp.size()));
  std::printf("%zu spheres, %d threads\n| theta | bucket | group | us/sphere | cells/sphere | particles/sphere (near) | "
              "rms rel error (floor 0.1 a_rms) | max |\n|---|---|---|---|---|---|---|---|\n",
              sp.size(), omp_get_max_threads());
  for (double th : thetas)
    for (double b : buckets)
      for (double gs : groups) {
      GravityParams gp;
      gp.G = 1.0;
      gp.theta = th;
      gp.bucket = static_cast<int>(b);
      gp.group = static_cast<int>(gs);
      TreeGravity tree(gp);
      std::vector<Vec3> a;
      std::vector<double> t;
      for (int r = 0; r < reps; ++r) {
        const double t0 = omp_get_wtime();
        tree.compute(sp, a);
        t.push_back(omp_get_wtime() - t0);
      }
      std::sort(t.begin(), t.end());
      // relative to |a_i|, floored at 0.1 x the rms acceleration: at the centre of a symmetric
      // pile |a| -> 0 and one sphere's relative error would dominate the rms
      double e2 = 0, emax = 0;
      for (std::size_t i = 0; i < ad.size(); ++i) {
        const double e = (a[i] - ad[i]).norm() / std::max(ad[i].norm(), 0.1 * arms);
        e2 += e * e;
        emax = std::max(emax, e);
      }
      char err[64] = "- | -";
      if (!no_direct) std::snprintf(err, sizeof err, "%.2e | %.2e", std::sqrt(e2 / static_cast<double>(sp.size())), emax);
      std::printf("| %.2f | %d | %d | %.3f | %.0f | %.0f (%.0f) | %s |\n", th, gp.bucket, gp.group,
                  1e6 * t[t.size() / 2] / static_cast<double>(sp.size()), tree.stats().cell_interactions,
                  tree.stats().particle_interactions, tree.stats().near_interactions, err);
      std::fflush(stdout);
    }
  return 0;
}
