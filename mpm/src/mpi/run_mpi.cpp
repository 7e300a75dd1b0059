/// @file run_mpi.cpp
/// mpm-frag time loop on MPI ranks (run_mpi.hpp; no physics here): dt = the global stable step
/// cut at snapshot times, DomainSolver steps, series rows and snapshots from rank 0.
#include "mpm/mpi/run_mpi.hpp"

#include <omp.h>
#include <spdlog/spdlog.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include "common/status.hpp"
#include "mpm/memory_bounds.hpp"
#include "mpm/mpi/domain.hpp"
#include "mpm/output.hpp"
#include "mpm/scene_setup.hpp"

namespace mpmfrag::mpi {

RunSummary run_mpm_mpi(const common::Scene& scene, const common::Provenance& prov, const std::string& restart) {
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  if (rank != 0) spdlog::set_level(spdlog::level::warn);
  if (!restart.empty())
    throw common::InputError("--restart is not available on more than one MPI rank yet (restart on one rank)");
  check_memory(scene);
  const Setup st = build_setup(scene);
  const RunConfig& rc = st.run;
  if (rc.threads > 0) omp_set_num_threads(rc.threads);
  if (scene.integer("output.checkpoint_every") > 0 || scene.real("output.checkpoint_wall") > 0)
    spdlog::warn("checkpoints are not written on more than one MPI rank yet (output.checkpoint_* ignored)");
  if (rank == 0) log_bodies(st.bodies);
  DomainSolver dom(MPI_COMM_WORLD, st);
  const Slabs& sl = dom.slabs();
  std::string cuts;
  for (const int c : sl.cut) cuts += (cuts.empty() ? "" : " ") + std::to_string(c);
  spdlog::info("mpm-frag (MPI): {} particles on {} ranks x {} threads, grid {}x{}x{} nodes cut along axis {} into slabs at planes {}",
               st.particles.size(), size, omp_get_max_threads(), st.grid.shape[0], st.grid.shape[1], st.grid.shape[2],
               "xyz"[sl.axis], cuts);
  if (rank == 0) std::filesystem::create_directories(rc.out_dir);
  auto snap_path = [&](std::int64_t step) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "_%06lld.h5", static_cast<long long>(step));
    return (std::filesystem::path(rc.out_dir) / (rc.prefix + buf)).string();
  };
  RunSummary sum;
  sum.particles = st.particles.size();
  auto write_snap = [&]() {
    ParticleSet ps;
    std::vector<MaterialSlot> mats;
    dom.gather(0, ps, mats);
    if (rank != 0) return;
    const std::string path = snap_path(dom.step_count());
    const common::ParticleSnapshot snap = make_snapshot(ps, mats, st.grid, dom.time(), dom.step_count());
    common::write_particle_snapshot(path, snap, prov);
    sum.last_snapshot = path;
  };
  const std::string series_path = (std::filesystem::path(rc.out_dir) / (rc.prefix + "_series.csv")).string();
  std::unique_ptr<SeriesWriter> series;
  if (rank == 0) series = std::make_unique<SeriesWriter>(series_path, std::vector<std::size_t>{});
  const auto t0 = std::chrono::steady_clock::now();
  dom.initialize();
  sum.initial = dom.diagnostics();
  if (series) series->write(0, 0.0, 0.0, sum.initial, {});
  write_snap();
  double next_snap = rc.snapshot_interval > 0 ? rc.snapshot_interval : rc.t_end;
  sum.first_dt = dom.stable_dt();
  sum.min_dt = 1e300;
  double dt = 0;
  try {
    while (dom.time() < rc.t_end * (1 - 1e-12)) {
      if (rc.max_steps > 0 && dom.step_count() >= rc.max_steps) break;
      dt = dom.stable_dt();
      const double target = std::min(next_snap, rc.t_end);
      if (dom.time() + dt > target) dt = target - dom.time();
      if (!(dt > 0)) dt = dom.stable_dt();
      dom.step(dt);
      sum.min_dt = std::min(sum.min_dt, dt);
      sum.max_dt = std::max(sum.max_dt, dt);
      const bool at_snap = dom.time() >= next_snap * (1 - 1e-12);
      const bool at_end = dom.time() >= rc.t_end * (1 - 1e-12);
      if (dom.step_count() % rc.series_every == 0 || at_end || at_snap) {
        const Diagnostics d = dom.diagnostics();
        if (series) series->write(dom.step_count(), dom.time(), dt, d, {});
      }
      if (at_snap) {
        if (!at_end) write_snap();
        next_snap += rc.snapshot_interval;
      }
    }
  } catch (const SolverFailure& f) {  // thrown on every rank (collective failure flags)
    if (series) series->commit();
    throw common::NumericalError(std::string(f.what()), "");
  }
  sum.final = dom.diagnostics();
  write_snap();
  if (series) series->commit();
  sum.series_path = series_path;
  sum.steps = dom.step_count();
  sum.time = dom.time();
  sum.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const DomainStats& s = dom.stats();
  double c[4] = {s.halo_bytes, s.migrate_bytes, static_cast<double>(s.migrated), 0.0};
  MPI_Allreduce(MPI_IN_PLACE, c, 4, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
  const double E0 = sum.initial.total();
  spdlog::info("done: {} steps to t = {:.6g} s in {:.2f} s wall on {} ranks x {} threads ({:.3f} us per particle-step)",
               sum.steps, sum.time, sum.wall_s, size, omp_get_max_threads(),
               sum.wall_s * 1e6 / (static_cast<double>(sum.particles) * std::max<std::int64_t>(1, sum.steps)));
  spdlog::info("communication: halo {:.3g} MB, migration and gathers {:.3g} MB, {} particle moves, {} rebalancings",
               c[0] / 1e6, c[1] / 1e6, static_cast<long long>(c[2]), s.rebalances);
  spdlog::info("energy: E0 = {:.6g} J, E = {:.6g} J, change {:+.3f} %; mass {:.9g} kg (initial {:.9g})", E0,
               sum.final.total(), E0 != 0 ? 100 * (sum.final.total() - E0) / std::fabs(E0) : 0.0, sum.final.mass,
               sum.initial.mass);
  return sum;
}

}  // namespace mpmfrag::mpi
