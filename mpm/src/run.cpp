/// @file run.cpp
/// mpm-frag time loop (no physics here; see solver.hpp): snapshots, series, progress, the last
/// good state on failure, checkpoints (periodic, at the end and on SIGTERM/SIGINT) and --restart.
#include "mpm/run.hpp"

#include <omp.h>
#include <spdlog/spdlog.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <optional>

#include "common/build_check.hpp"
#include "common/finite.hpp"
#include "common/log.hpp"
#include "common/run_dir.hpp"
#include "common/run_identity.hpp"
#include "common/status.hpp"
#include "common/stop_signal.hpp"
#include "mpm/checkpoint.hpp"
#include "mpm/memory_bounds.hpp"
#include "mpm/output.hpp"
#include "mpm/run_directory.hpp"
#include "mpm/scene_setup.hpp"

namespace mpmfrag {
namespace {

// output.snapshot_interval stays in the run identity: snapshot times cut the time steps.
const std::vector<std::string> kRestartFree = {"time.end",           "time.max_steps",         "output.directory",
                                               "output.series_every", "output.progress_interval",
                                               "output.checkpoint_every", "output.checkpoint_wall", "run.threads",
                                               "run.backup_every"};

}  // namespace

const std::vector<std::string>& restart_free_keys() { return kRestartFree; }

RunSummary run_mpm(const common::Scene& scene, const common::Provenance& prov, const std::string& restart) {
  check_memory(scene);  // exit 2 naming the keys, before the grid or the particles are allocated
  Setup st = build_setup(scene);
  // Identity of this run, recorded in its checkpoints: --restart refuses another run's.
  const common::RunIdentity ident = common::run_identity(scene, kRestartFree, {});
  // The run locks output.directory and writes into a staging directory, published into it
  // when the run completes (common/run_dir.hpp): an interrupted or failed run leaves the
  // previous run's files as they were. rc.out_dir is the staging directory below. A restart
  // continues in the staging directory of the interrupted run whose checkpoint it reads.
  const std::unique_ptr<common::RunDirectory> rdp = open_run_directory(st.run, restart);
  common::RunDirectory& rd = *rdp;
  RunConfig rc = st.run;
  rc.out_dir = rd.staging();
  if (rc.threads > 0) omp_set_num_threads(rc.threads);
  const std::string ckpt_path = (std::filesystem::path(rc.out_dir) / (rc.prefix + "_checkpoint.h5")).string();

  std::optional<Checkpoint> ck;
  if (!restart.empty()) {
    ck = read_checkpoint(restart);
    const common::RunIdentity theirs = common::RunIdentity::parse(ck->identity);
    const std::string diff = common::RunIdentity::differences(ident, "this run", theirs, "checkpoint");
    if (!diff.empty())
      throw common::InputError(restart + ": checkpoint of another run (run identity " + theirs.digest() +
                               ") than this scene's (run identity " + ident.digest() + "); they differ in " + diff);
    apply_materials(*ck, st.materials, restart);
    st.particles = std::move(ck->particles);
    carry_snapshots(rd, st.run, restart, ck->solver.step);  // a published run's snapshots up to the checkpoint
  }

  const std::size_t n = st.particles.size();
  log_bodies(st.bodies);
  Solver solver(st.solver, st.grid, std::move(st.particles), std::move(st.materials));
  solver.set_drives(st.drives);  // [[body]] drive.* (body_drive.hpp)
  std::vector<std::size_t> drive_bodies;
  for (const BodyDrive& d : st.drives) drive_bodies.push_back(d.body);
  RunSummary sum;
  sum.particles = n;
  sum.bytes_per_particle = solver.bytes_per_particle();
  spdlog::info("mpm-frag: {} particles, {} materials, grid {}x{}x{} nodes (h = {:.4g} m), {} threads", n,
               solver.materials().size(), st.grid.shape[0], st.grid.shape[1], st.grid.shape[2],
               st.grid.cell_size[0], omp_get_max_threads());
  spdlog::info("memory: {:.1f} bytes/particle (particles + material state), grid {:.1f} MB",
               sum.bytes_per_particle, solver.grid_bytes() / 1e6);
  spdlog::info("solver: {} / {} / FLIP {:.3g} / Courant {:.3g} / artificial viscosity {}",
               shape_kind_name(st.solver.shape), common::choice_name(kSchemes, st.solver.scheme), st.solver.flip,
               st.solver.courant, st.solver.artificial_viscosity ? "on" : "off");
  for (const MaterialSlot& m : solver.materials())
    spdlog::info("material '{}' ({}): {} particles, c_ref = {:.1f} m/s, {} state field(s)", m.name, m.style->name,
                 m.end - m.begin, m.model->reference_wave_speed(), m.state.size());

  const auto t0 = std::chrono::steady_clock::now();
  auto wall = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
  DriverState drv;
  if (ck) {
    solver.resume(std::move(ck->solver));
    drv = std::move(ck->driver);
    if (!(rc.snapshot_interval > 0)) drv.next_snapshot = rc.t_end;  // initial and final only: this end
    spdlog::info("restarted from {} at step {} (t = {:.6g} s)", restart, solver.step_count(), solver.time());
    if (const std::string note = common::other_build_note(restart); !note.empty()) spdlog::warn("restart: {}", note);
  } else {
    solver.initialize();
  }
  const std::string series_path = (std::filesystem::path(rc.out_dir) / (rc.prefix + "_series.csv")).string();
  SeriesWriter series(series_path, drive_bodies, ck ? std::optional<std::string>(std::move(drv.series)) : std::nullopt);
  ck.reset();
  sum.series_path = series_path;
  auto write_snap = [&](const ParticleSet& ps, const std::vector<MaterialSlot>& mats, double t, std::int64_t step,
                        const std::string& tag) {
    const std::string path = snap_name(rc, tag, step);
    const common::ParticleSnapshot snap = make_snapshot(ps, mats, solver.grid(), t, step);
    try {
      common::check_output_particles(snap, path);  // never Inf/NaN in an output (exit 3)
    } catch (common::NumericalError& e) {
      std::string saved;
      if (tag != "failed_" && solver.backup().valid) {
        const Backup& b = solver.backup();
        saved = snap_name(rc, "failed_", b.step);
        common::ParticleSnapshot good = make_snapshot(b.particles, b.materials, solver.grid(), b.time, b.step);
        common::check_output_particles(good, saved);
        common::write_particle_snapshot(saved, good, prov);
      }
      spdlog::error("{}; last good state saved to {}", e.what(), saved.empty() ? "(none)" : saved);
      e.set_saved_state(saved);
      throw;
    }
    common::write_particle_snapshot(path, snap, prov);
    return path;
  };
  // Particles removed at the grid edge (grid.outflow = "remove"): all of them so far, with
  // ballistic positions at the current time, in <prefix>_outflow.h5 next to each snapshot.
  std::size_t reported_out = solver.outflow_count();
  auto write_outflow = [&]() {
    if (solver.outflow_count() == 0) return;
    const std::string path = (std::filesystem::path(rc.out_dir) / (rc.prefix + "_outflow.h5")).string();
    common::write_particle_snapshot(path, solver.outflow_snapshot(), prov);
    if (solver.outflow_count() != reported_out) {
      const Diagnostics d = solver.diagnostics();
      spdlog::info("outflow: {} particles ({:.4g} kg, {:.3g} % of the mass) have left the grid by t = {:.6g} s -> {}",
                   d.removed, d.removed_mass, 100 * d.removed_mass / d.mass, solver.time(), path);
      reported_out = solver.outflow_count();
    }
  };
  auto checkpoint = [&]() {
    drv.series = series.text();
    write_checkpoint(ckpt_path, solver, drv, prov, ident.text());
    drv.series.clear();
    spdlog::info("checkpoint at step {} -> {}", solver.step_count(), ckpt_path);
  };
  if (restart.empty()) {
    drv.initial = solver.diagnostics();
    series.write(0, 0.0, 0.0, drv.initial, solver.drive_loads());
    sum.last_snapshot = write_snap(solver.particles(), solver.materials(), 0.0, 0, "");
    drv.next_snapshot = rc.snapshot_interval > 0 ? rc.snapshot_interval : rc.t_end;
    drv.first_dt = solver.stable_dt();
    drv.min_dt = 1e300;
    spdlog::info("first dt = {:.4g} s ({} limit)", drv.first_dt, solver.dt_capped() ? "time.dt_max" : "CFL");
  }
  sum.initial = drv.initial;
  sum.first_dt = drv.first_dt;
  const double E0 = sum.initial.total();
  common::Progress progress("mpm-frag", solver.time(), rc.t_end, rc.progress_interval);
  const std::int64_t ckpt_every = scene.integer("output.checkpoint_every");
  const double ckpt_wall = scene.real("output.checkpoint_wall");
  double last_ckpt_wall = 0;
  const common::StopSignals stop;  // SIGTERM/SIGINT: checkpoint after the step, exit 128 + signal
  bool warned_cap = false;
  double dt = 0;
  while (solver.time() < rc.t_end * (1 - 1e-12)) {
    if (rc.max_steps > 0 && solver.step_count() >= rc.max_steps) {
      spdlog::warn("stopping at time.max_steps = {} (t = {:.6g} s < end {:.6g} s)", rc.max_steps, solver.time(), rc.t_end);
      break;
    }
    if (solver.step_count() % rc.backup_every == 0) solver.save_backup();
    dt = solver.stable_dt();
    if (!solver.dt_capped() && st.solver.dt_max < 1e29 && !warned_cap) {
      spdlog::warn("time.dt_max = {:.3g} s exceeds the stable (CFL) step {:.3g} s; using the CFL step", st.solver.dt_max, dt);
      warned_cap = true;
    }
    const double target = std::min(drv.next_snapshot, rc.t_end);
    if (solver.time() + dt > target) dt = target - solver.time();
    if (!(dt > 0)) dt = solver.stable_dt();
    try {
      solver.step(dt);
    } catch (const SolverFailure& f) {
      std::string path;
      if (f.state_intact) {
        path = write_snap(solver.particles(), solver.materials(), solver.time(), solver.step_count(), "failed_");
      } else if (solver.backup().valid) {
        const Backup& b = solver.backup();
        path = write_snap(b.particles, b.materials, b.time, b.step, "failed_");
      }
      write_outflow();
      series.write(solver.step_count(), solver.time(), dt, solver.diagnostics(), solver.drive_loads());
      series.commit();  // the series up to the failure replaces an earlier one
      spdlog::error("last good state saved to {}", path.empty() ? "(none)" : path);
      throw common::NumericalError(std::string(f.what()), path);
    }
    drv.min_dt = std::min(drv.min_dt, dt);
    drv.max_dt = std::max(drv.max_dt, dt);
    const bool at_snap = solver.time() >= drv.next_snapshot * (1 - 1e-12);
    const bool at_end = solver.time() >= rc.t_end * (1 - 1e-12);
    if (solver.step_count() % rc.series_every == 0 || at_end || at_snap) {
      const Diagnostics d = solver.diagnostics();
      series.write(solver.step_count(), solver.time(), dt, d, solver.drive_loads());
      progress.update(solver.step_count(), solver.time(), dt, E0 != 0 ? (d.total() - E0) / std::fabs(E0) : 0.0);
    }
    if (at_snap) {
      if (!at_end) {  // the final snapshot follows the loop
        sum.last_snapshot = write_snap(solver.particles(), solver.materials(), solver.time(), solver.step_count(), "");
        write_outflow();
      }
      drv.next_snapshot += rc.snapshot_interval;  // also at the end: a continuation to a later end
    }
    if (const int sig = stop.pending()) {
      checkpoint();
      write_outflow();
      series.commit();
      spdlog::warn("interrupted by signal {} at step {}; continue with --restart {}", sig, solver.step_count(), ckpt_path);
      sum.signal = sig;
      sum.steps = solver.step_count();
      sum.time = solver.time();
      return sum;
    }
    if ((ckpt_every > 0 && solver.step_count() % ckpt_every == 0) ||
        (ckpt_wall > 0 && wall() - last_ckpt_wall > ckpt_wall)) {
      checkpoint();
      last_ckpt_wall = wall();
    }
  }
  sum.min_dt = drv.min_dt;
  sum.max_dt = drv.max_dt;
  sum.final = solver.diagnostics();
  sum.last_snapshot = write_snap(solver.particles(), solver.materials(), solver.time(), solver.step_count(), "");
  write_outflow();
  checkpoint();
  series.commit();
  rd.publish();
  auto published = [&](const std::string& p) {
    return (std::filesystem::path(st.run.out_dir) / std::filesystem::path(p).filename()).string();
  };
  sum.last_snapshot = published(sum.last_snapshot);
  sum.series_path = published(sum.series_path);
  spdlog::info("run complete: outputs published in {}", st.run.out_dir);
  sum.steps = solver.step_count();
  sum.time = solver.time();
  sum.wall_s = wall();
  progress.update(sum.steps, sum.time, dt, E0 != 0 ? (sum.final.total() - E0) / std::fabs(E0) : 0.0, true);
  const double us = sum.wall_s * 1e6 / (static_cast<double>(n) * std::max<std::int64_t>(1, sum.steps));
  spdlog::info("done: {} steps to t = {:.6g} s in {:.2f} s wall ({:.3f} us per particle-step, {} threads)", sum.steps,
               sum.time, sum.wall_s, us, omp_get_max_threads());
  spdlog::info("energy: E0 = {:.6g} J, E = {:.6g} J (kinetic {:.6g}, internal {:.6g}), change {:+.3f} %", E0,
               sum.final.total(), sum.final.kinetic, sum.final.internal,
               E0 != 0 ? 100 * (sum.final.total() - E0) / std::fabs(E0) : 0.0);
  return sum;
}

}  // namespace mpmfrag
