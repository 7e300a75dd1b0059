/// @file run_mpi.cpp
/// mpm-frag time loop on MPI ranks (run_mpi.hpp; no physics here): dt = the global stable step
/// cut at snapshot times, DomainSolver steps, series rows and progress from rank 0, snapshots
/// written by every rank together (snapshot_mpi.hpp), checkpoints (periodic, at the end, on
/// SIGTERM/SIGINT) and --restart (checkpoint_mpi.hpp), the run directory held by rank 0
/// (run_directory.hpp: locked, staged, published when the run completes) and the last good
/// state saved by every rank together on a failure.
#include "mpm/mpi/run_mpi.hpp"

#include <omp.h>
#include <spdlog/spdlog.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include "common/agreed.hpp"
#include "common/build_check.hpp"
#include "common/log.hpp"
#include "common/run_identity.hpp"
#include "common/status.hpp"
#include "common/stop_signal.hpp"
#include "mpm/memory_bounds.hpp"
#include "mpm/mpi/checkpoint_mpi.hpp"
#include "mpm/mpi/domain.hpp"
#include "mpm/mpi/snapshot_mpi.hpp"
#include "mpm/output.hpp"
#include "mpm/run_directory.hpp"
#include "mpm/scene_setup.hpp"

namespace mpmfrag::mpi {

RunSummary run_mpm_mpi(const common::Scene& scene, const common::Provenance& prov, const std::string& restart) {
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  if (rank != 0) spdlog::set_level(spdlog::level::warn);
  Comm comm(MPI_COMM_WORLD);
  {  // exit 2 on every rank if this node cannot hold its ranks' share of the scene
    MPI_Comm node;
    int here = 1;
    MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, rank, MPI_INFO_NULL, &node);
    MPI_Comm_size(node, &here);
    MPI_Comm_free(&node);
    common::mpi::agreed(comm, [&] {
      check_memory(scene, node_memory(), builtin_materials(), size, here);         // the node's ranks together
      check_memory(scene, process_memory_limit(), builtin_materials(), size, 1);  // one rank, RLIMIT_AS
    });
  }
  // every rank generates the scene and keeps its own box's particles (none for a restart)
  std::pair<Setup, Orb> part = distributed_setup(MPI_COMM_WORLD, scene, restart.empty());
  Setup& st = part.first;
  // Rank 0 locks output.directory and every rank writes into its staging directory, published
  // when the run completes (run_directory.hpp): a failed or interrupted run leaves the previous
  // run's files as they were; a restart continues in the staging directory of the interrupted
  // run whose checkpoint it reads.
  std::unique_ptr<common::RunDirectory> run_dir;
  common::mpi::agreed(comm, [&] {
    if (rank == 0) run_dir = open_run_directory(st.run, restart);
  });
  RunConfig rc = st.run;
  rc.out_dir = comm.bcast(run_dir ? run_dir->staging() : std::string());
  if (rc.threads > 0) omp_set_num_threads(rc.threads);
  // identity of this run, recorded in its checkpoints (the serial driver's: any rank count)
  const common::RunIdentity ident = common::run_identity(scene, restart_free_keys(), {});
  if (rank == 0) log_bodies(st.bodies);
  std::unique_ptr<DomainSolver> domp;
  DriverState drv;
  if (!restart.empty()) {
    RestartData rd = read_checkpoint_mpi(comm, restart, ident);  // each rank its part of the rows
    common::mpi::agreed(comm, [&] { apply_materials(rd.ck, st.materials, restart); });
    st.particles = std::move(rd.ck.particles);
    domp = std::make_unique<DomainSolver>(MPI_COMM_WORLD, st, rd.layout);
    resume(*domp, rd);
    drv = std::move(rd.ck.driver);
    common::mpi::agreed(comm, [&] {  // a published run's snapshots up to the checkpoint
      if (run_dir) carry_snapshots(*run_dir, st.run, restart, domp->step_count());
    });
    if (!(rc.snapshot_interval > 0)) drv.next_snapshot = rc.t_end;  // initial and final only: this end
    spdlog::info("restarted from {} ({} ranks) at step {} (t = {:.6g} s)", restart,
                 rd.layout.ranks == 0 ? std::string("one rank") : std::to_string(rd.layout.ranks),
                 domp->step_count(), domp->time());
    if (comm.rank == 0)
      if (const std::string note = common::other_build_note(restart); !note.empty()) spdlog::warn("restart: {}", note);
  } else {
    domp = std::make_unique<DomainSolver>(MPI_COMM_WORLD, st, part.second);
  }
  DomainSolver& dom = *domp;
  long long ntot = static_cast<long long>(dom.local().particles().size());
  comm.sum(&ntot, 1);
  spdlog::info("mpm-frag (MPI): {} particles on {} ranks x {} threads, grid {}x{}x{} nodes cut by ORB into {}", ntot, size,
               omp_get_max_threads(), st.grid.shape[0], st.grid.shape[1], st.grid.shape[2], dom.orb().describe());
  const std::string ckpt_path = (std::filesystem::path(rc.out_dir) / (rc.prefix + "_checkpoint.h5")).string();
  RunSummary sum;
  sum.particles = static_cast<std::size_t>(ntot);
  // the last good state, `<prefix>_failed_<step>.h5`: the current state if a failure left it
  // intact, else the ranks' backups of the same earlier step ("" if there is none yet)
  auto write_failed = [&](bool intact) {
    if (intact) {
      const std::string path = snap_name(rc, "failed_", dom.step_count());
      write_snapshot_mpi(comm, dom.local().particles(), dom.local().materials(), st.grid, dom.time(),
                         dom.step_count(), path, prov);
      return path;
    }
    if (!comm.all(dom.backup().valid)) return std::string();
    const Backup& b = dom.backup();
    const std::string path = snap_name(rc, "failed_", b.step);
    write_snapshot_mpi(comm, b.particles, b.materials, st.grid, b.time, b.step, path, prov);
    return path;
  };
  auto write_snap = [&]() {  // collective parallel HDF5: no rank holds every particle
    const std::string path = snap_name(rc, "", dom.step_count());
    try {
      write_snapshot_mpi(comm, dom.local().particles(), dom.local().materials(), st.grid, dom.time(),
                         dom.step_count(), path, prov);
    } catch (common::NumericalError& e) {  // a value that is not finite (every rank): save the backup
      const std::string saved = write_failed(false);
      if (rank == 0) spdlog::error("{}; last good state saved to {}", e.what(), saved.empty() ? "(none)" : saved);
      e.set_saved_state(saved);
      throw;
    }
    sum.last_snapshot = path;
  };
  // Particles removed at the grid edge (grid.outflow = "remove"): every rank's record written
  // together, in <prefix>_outflow.h5 next to each snapshot (as on one rank).
  long long reported_out = static_cast<long long>(dom.local().outflow_count());  // a restart's record
  comm.sum(&reported_out, 1);
  auto write_outflow = [&]() {
    if (!st.solver.outflow_remove) return;
    const OutflowRecord out = dom.local_outflow();
    long long n = static_cast<long long>(out.ps.size());
    comm.sum(&n, 1);
    if (n == 0) return;
    const std::string path = (std::filesystem::path(rc.out_dir) / (rc.prefix + "_outflow.h5")).string();
    write_outflow_mpi(comm, out, st.grid, dom.time(), dom.step_count(), path, prov);
    if (n != reported_out)
      spdlog::info("outflow: {} particles ({:.4g} kg) have left the grid by t = {:.6g} s -> {}", n, out.totals.mass,
                   dom.time(), path);
    reported_out = n;
  };
  const std::string series_path = (std::filesystem::path(rc.out_dir) / (rc.prefix + "_series.csv")).string();
  std::vector<std::size_t> drive_bodies;  // [[body]] drive.*: the load columns (the same on every rank)
  for (const BodyDrive& d : st.drives) drive_bodies.push_back(d.body);
  std::unique_ptr<SeriesWriter> series;
  if (rank == 0)
    series = std::make_unique<SeriesWriter>(series_path, drive_bodies,
                                            restart.empty() ? std::nullopt : std::optional<std::string>(std::move(drv.series)));
  drv.series.clear();
  auto commit_series = [&]() {  // rank 0's file; a failure there fails every rank alike
    common::mpi::agreed(comm, [&] {
      if (series) series->commit();
    });
  };
  auto checkpoint = [&]() {
    if (series) drv.series = series->text();
    write_checkpoint_mpi(dom, ckpt_path, drv, prov, ident.text());
    drv.series.clear();
    spdlog::info("checkpoint at step {} -> {}", dom.step_count(), ckpt_path);
  };
  const auto t0 = std::chrono::steady_clock::now();
  auto wall = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
  if (restart.empty()) {
    dom.initialize();
    drv.initial = dom.diagnostics();
    if (series) series->write(0, 0.0, 0.0, drv.initial, dom.local().drive_loads());
    write_snap();
    drv.next_snapshot = rc.snapshot_interval > 0 ? rc.snapshot_interval : rc.t_end;
    drv.first_dt = dom.stable_dt();
    drv.min_dt = 1e300;
    spdlog::info("first dt = {:.4g} s ({} limit)", drv.first_dt, dom.local().dt_capped() ? "time.dt_max" : "CFL");
  }
  sum.initial = drv.initial;
  sum.first_dt = drv.first_dt;
  const double E0 = sum.initial.total();
  common::Progress progress("mpm-frag", dom.time(), rc.t_end, rc.progress_interval);
  const std::int64_t ckpt_every = scene.integer("output.checkpoint_every");
  const double ckpt_wall = scene.real("output.checkpoint_wall");
  double last_ckpt_wall = 0;
  const common::StopSignals stop;  // SIGTERM/SIGINT: checkpoint after the step, exit 128 + signal
  double dt = 0;
  try {
    while (dom.time() < rc.t_end * (1 - 1e-12)) {
      if (rc.max_steps > 0 && dom.step_count() >= rc.max_steps) {
        if (rank == 0) spdlog::warn("stopping at time.max_steps = {} (t = {:.6g} s < end {:.6g} s)", rc.max_steps, dom.time(), rc.t_end);
        break;
      }
      if (dom.step_count() % rc.backup_every == 0) dom.save_backup();
      dt = dom.stable_dt();
      const double target = std::min(drv.next_snapshot, rc.t_end);
      if (dom.time() + dt > target) dt = target - dom.time();
      if (!(dt > 0)) dt = dom.stable_dt();
      dom.step(dt);
      drv.min_dt = std::min(drv.min_dt, dt);
      drv.max_dt = std::max(drv.max_dt, dt);
      const bool at_snap = dom.time() >= drv.next_snapshot * (1 - 1e-12);
      const bool at_end = dom.time() >= rc.t_end * (1 - 1e-12);
      if (dom.step_count() % rc.series_every == 0 || at_end || at_snap) {
        const Diagnostics d = dom.diagnostics();
        if (series) series->write(dom.step_count(), dom.time(), dt, d, dom.local().drive_loads());
        if (rank == 0) progress.update(dom.step_count(), dom.time(), dt, E0 != 0 ? (d.total() - E0) / std::fabs(E0) : 0.0);
      }
      if (at_snap) {
        if (!at_end) {  // the final snapshot follows the loop
          write_snap();
          write_outflow();
        }
        drv.next_snapshot += rc.snapshot_interval;  // also at the end: a continuation to a later end
      }
      // a signal or the wall-clock interval may reach the ranks at different steps: act on the
      // maximum over the ranks (every rank decides the same)
      double due[2] = {static_cast<double>(stop.pending()), ckpt_wall > 0 && wall() - last_ckpt_wall > ckpt_wall ? 1.0 : 0.0};
      dom.comm().max(due, 2);
      if (due[0] > 0) {
        checkpoint();
        write_outflow();
        commit_series();
        const int sig = static_cast<int>(due[0]);
        spdlog::warn("interrupted by signal {} at step {}; continue with --restart {}", sig, dom.step_count(), ckpt_path);
        sum.signal = sig;
        sum.steps = dom.step_count();
        sum.time = dom.time();
        return sum;
      }
      if ((ckpt_every > 0 && dom.step_count() % ckpt_every == 0) || due[1] > 0) {
        checkpoint();
        last_ckpt_wall = wall();
      }
    }
  } catch (const SolverFailure& f) {  // thrown on every rank (collective failure flags)
    const std::string path = write_failed(comm.all(f.state_intact));
    write_outflow();
    const Diagnostics d = dom.diagnostics();
    if (series) series->write(dom.step_count(), dom.time(), dt, d, dom.local().drive_loads());
    commit_series();  // the series up to the failure, in the staging directory
    if (rank == 0) spdlog::error("last good state saved to {}", path.empty() ? "(none)" : path);
    throw common::NumericalError(std::string(f.what()), path);
  }
  sum.min_dt = drv.min_dt;
  sum.max_dt = drv.max_dt;
  sum.final = dom.diagnostics();
  write_snap();
  write_outflow();
  checkpoint();
  commit_series();
  common::mpi::agreed(comm, [&] {
    if (run_dir) run_dir->publish();
  });
  auto published = [&](const std::string& p) {
    return (std::filesystem::path(st.run.out_dir) / std::filesystem::path(p).filename()).string();
  };
  sum.last_snapshot = published(sum.last_snapshot);
  sum.series_path = published(series_path);
  spdlog::info("run complete: outputs published in {}", st.run.out_dir);
  sum.steps = dom.step_count();
  sum.time = dom.time();
  sum.wall_s = wall();
  const DomainStats& s = dom.stats();
  double c[4] = {s.halo_bytes, s.migrate_bytes, static_cast<double>(s.migrated), 0.0};
  MPI_Allreduce(MPI_IN_PLACE, c, 4, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
  progress.update(sum.steps, sum.time, dt, E0 != 0 ? (sum.final.total() - E0) / std::fabs(E0) : 0.0, true);
  spdlog::info("done: {} steps to t = {:.6g} s in {:.2f} s wall on {} ranks x {} threads ({:.3f} us per particle-step)",
               sum.steps, sum.time, sum.wall_s, size, omp_get_max_threads(),
               sum.wall_s * 1e6 / (static_cast<double>(sum.particles) * std::max<std::int64_t>(1, sum.steps)));
  spdlog::info("communication: halo {:.3g} MB, migration and gathers {:.3g} MB, {} particle moves, {} rebalancings "
               "({} left out for memory); work imbalance max W_r / mean W_r before rebalancing: mean {:.3f}, "
               "largest {:.3f} over {} checks",
               c[0] / 1e6, c[1] / 1e6, static_cast<long long>(c[2]), s.rebalances, s.rebalances_skipped,
               s.imbalance_checks > 0 ? s.imbalance_sum / static_cast<double>(s.imbalance_checks) : 1.0,
               s.imbalance_checks > 0 ? s.imbalance_max : 1.0, s.imbalance_checks);
  spdlog::info("energy: E0 = {:.6g} J, E = {:.6g} J, change {:+.3f} %; mass {:.9g} kg (initial {:.9g})", E0,
               sum.final.total(), E0 != 0 ? 100 * (sum.final.total() - E0) / std::fabs(E0) : 0.0, sum.final.mass,
               sum.initial.mass);
  return sum;
}

}  // namespace mpmfrag::mpi
