/// @file run_mpi.cpp
/// ssdem-grav driver on several MPI ranks (run_mpi.hpp).
#include "ssdem/mpi/run_mpi.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>
#include <sstream>

#include "common/atomic_file.hpp"
#include "common/build_check.hpp"
#include "common/finite.hpp"
#include "common/log.hpp"
#include "common/run_dir.hpp"
#include "common/run_identity.hpp"
#include "common/series_csv.hpp"
#include "common/sorted_rows.hpp"
#include "common/sphere_file.hpp"
#include "common/status.hpp"
#include "common/stop_signal.hpp"
#include "ssdem/io.hpp"
#include "ssdem/mpi/domain_sim.hpp"
#include "ssdem/mpi/io_mpi.hpp"
#include "ssdem/mpi/sphere_summary_mpi.hpp"
#include "ssdem/run.hpp"
#include "ssdem/scene_setup.hpp"

namespace ssdem::mpi {
namespace {
// Rank 0 only runs `f`; every rank learns whether it threw, and the others then stop with exit 4.
template <class F>
void on_root(Comm& comm, F&& f) {
  int ok = 1;
  std::exception_ptr err;
  if (comm.rank == 0) try {
      f();
    } catch (...) {
      ok = 0;
      err = std::current_exception();
    }
  MPI_Bcast(&ok, 1, MPI_INT, 0, comm.c);
  if (err) std::rethrow_exception(err);
  if (!ok) throw common::IoError("rank 0 failed (its message above); stopping");
}
// This rank's block of n rows (common::dense_first: the blocks the collective writers use).
common::h5::RowRange block_rows(const Comm& comm, std::size_t n) {
  const std::size_t lo = common::mpi::dense_first(n, comm.size, comm.rank);
  return common::h5::RowRange{lo, common::mpi::dense_first(n, comm.size, comm.rank + 1) - lo};
}
std::string block_line(const Comm& comm, std::size_t n) {
  const std::size_t P = static_cast<std::size_t>(comm.size);
  return "input: " + std::to_string(n) + " spheres read in blocks, at most " + std::to_string((n + P - 1) / P) +
         " rows per rank\n";
}
}  // namespace

int run_ssdem_mpi(const common::Scene& sc, const common::Provenance& prov, const std::string& restart) {
  Comm comm;
  if (comm.rank != 0) spdlog::set_level(spdlog::level::err);
  const common::RunIdentity ident = ssdem::detail::run_identity(sc);
  const std::string out_dir = sc.string("output.directory");
  std::unique_ptr<common::RunDirectory> rd;
  on_root(comm, [&] {
    rd = std::make_unique<common::RunDirectory>(
        out_dir, "ssdem-grav", detail::is_output,
        restart.empty() ? std::string() : common::RunDirectory::staging_of(out_dir, restart));
  });
  const std::string dir = comm.bcast(rd ? rd->staging() : std::string());  // every rank writes there (collective files)

  std::unique_ptr<DomainSim> sim;
  std::string info;
  double energy0 = NAN;  // the run's initial accounted energy (a restart: the checkpoint's)
  std::string input_line;  // how the input was read (run_info.txt)
  if (restart.empty()) {
    const std::string bf = block_input_file(sc);
    if (!bf.empty()) {  // each rank reads its block of rows only (domain_sim.hpp, "Input in blocks")
      const std::size_t n = common::sphere_file_shape(bf).count;
      if (n == 0) throw common::InputError(bf + ": no spheres");
      const common::h5::RowRange rows = block_rows(comm, n);
      const common::SphereSet in = common::read_sphere_rows(bf, rows);
      common::check_input_spheres(in, bf, "/spheres/", rows.offset);
      SimState st;
      st.sp = from_sphere_set(in);
      const SphereSummary sum = summarise(comm, st.sp);
      const SimConfig cfg = sim_config(sc, sum, nullptr, &info, nullptr, std::string());
      sim = std::make_unique<DomainSim>(comm, st, DomainSim::Block{rows.offset, sum, false, bf}, cfg);
      input_line = block_line(comm, n);
    } else {
      BondSet file_bonds;
      Spheres sp = initial_spheres(sc, &file_bonds);
      const SimConfig cfg = sim_config(sc, sp, &info, &file_bonds);
      sim = std::make_unique<DomainSim>(comm, sp, cfg);
      input_line = "input: every rank built or read all " + std::to_string(sp.size()) +
                   " spheres (a generator, a .ss file or bonds)\n";
    }
  } else {
    double dt0 = 0, kn0 = 0;
    int every0 = 0;
    std::string ck_ident;
    const CheckpointShape shape = checkpoint_shape(restart);
    const bool blocks = !shape.bonds;  // with bonds every rank reads the whole checkpoint
    const common::h5::RowRange sph = block_rows(comm, shape.spheres);
    SimState st = blocks ? read_checkpoint_rows(restart, sph, block_rows(comm, shape.history),
                                                &dt0, &every0, &kn0, &ck_ident)
                         : read_checkpoint(restart, &dt0, &every0, &kn0, &ck_ident);
    st.sphere_order.clear();  // the rows are in file order; MPI ranks keep it (sphere_order.hpp)
    ssdem::detail::check_restart_identity(sc, ident, restart, ck_ident, comm.rank == 0);
    on_root(comm, [&] {
      if (!common::RunDirectory::staging_of(out_dir, restart).empty()) return;
      rd->carry("series.csv");  // continuing a published run: its series and snapshots up to the checkpoint
      if (std::filesystem::exists(std::filesystem::path(out_dir) / "levels.csv")) rd->carry("levels.csv");
      for (const auto& e : std::filesystem::directory_iterator(out_dir)) {
        const std::string n = e.path().filename().string();
        const std::int64_t s = detail::snap_step(n);
        if (s >= 0 && s <= st.step) rd->carry(n);
      }
    });
    const SphereSummary sum = blocks ? summarise(comm, st.sp) : SphereSummary{};
    SimConfig cfg = blocks ? sim_config(sc, sum, nullptr, &info, nullptr, restart) : sim_config(sc, st.sp, &info, &st.bonds, restart);
    if (cfg.contacts && kn0 > 0.0) cfg.contact.kn = kn0;  // the checkpoint's values: the continuation is exact
    cfg.dt = dt0;
    if (!cfg.adaptive_gravity) cfg.gravity_every = every0;
    st.gravity_block = every0;
    energy0 = st.energy0;
    if (blocks) {
      sim = std::make_unique<DomainSim>(comm, st, DomainSim::Block{sph.offset, sum, true, restart}, cfg);
      input_line = block_line(comm, shape.spheres);
    } else {
      sim = std::make_unique<DomainSim>(comm, st, cfg);
      input_line = "input: every rank read all " + std::to_string(shape.spheres) + " spheres of the checkpoint (bonds)\n";
    }
    info += "restarted from " + restart + " at step " + std::to_string(sim->step_count()) + "\n";
    if (const std::string note = comm.rank == 0 ? common::other_build_note(restart) : std::string(); !note.empty()) {
      spdlog::warn("restart: {}", note);  // (rank 0 writes run_info.txt)
      info += note + "\n";
    }
  }
  const SimConfig& cfg = sim->config();
  const std::int64_t first_step = sim->step_count();
  std::ostringstream ri;
  ri << info << input_line << "spheres: " << sim->global_count() << "\nMPI ranks: " << comm.size << "\ndt = " << cfg.dt
     << " s\nself-gravity: " << (cfg.self_gravity ? (cfg.direct_gravity ? "direct" : "tree") : "off")
     << "\ncontacts: " << (cfg.contacts ? "on" : "off") << " (pair kernel in packs of " << ContactSystem::lanes()
     << ")\nk_n = " << cfg.contact.kn
     << " N/m, parts mask = " << cfg.contact.parts << "\nthread teams: size (MPI ranks; run.teams "
     << "applies to one process)\n";
  if (cfg.teams == TeamMode::every_pass || cfg.teams == TeamMode::one_thread)
    on_root(comm, [] { spdlog::warn("run.teams: MPI ranks use the size rule; the setting applies to one process"); });
  const std::string run_info = ri.str();
  on_root(comm, [&] { common::write_text_atomic((std::filesystem::path(dir) / "run_info.txt").string(), run_info); });
  spdlog::info("ssdem-grav on {} MPI ranks: {} spheres, dt = {} s", comm.size, sim->global_count(), cfg.dt);

  const auto [t_end, snap_dt, ckpt_wall, series_every, ckpt_every, n_end, times, series_path, ckpt_path] =
      detail::output_plan(sc, cfg, dir);
  sim->set_end_step(n_end);
  // a verified state every ~100 steps for the save after a numerical failure (as run.cpp)
  sim->set_keep_last_good(std::max<std::int64_t>(cfg.gravity_every, 100 / cfg.gravity_every * cfg.gravity_every));

  std::unique_ptr<common::SeriesFile> series;
  on_root(comm, [&] {
    series = std::make_unique<common::SeriesFile>(series_path, detail::series_format(sim->global_bonds() > 0),
                                                  restart.empty() ? std::nullopt : std::optional(sim->step_count()));
  });
  std::unique_ptr<common::SeriesFile> levels;  // levels.csv of multi-rate runs, as the serial driver's
  on_root(comm, [&] {
    if (cfg.multirate)
      levels = std::make_unique<common::SeriesFile>((std::filesystem::path(dir) / "levels.csv").string(),
                                                    detail::levels_format(),
                                                    restart.empty() ? std::nullopt : std::optional(sim->step_count()));
  });
  common::Progress progress("ssdem-grav", sim->time(), t_end, sc.real("output.progress_interval"));
  double E0 = energy0, last_rel = 0.0;
  // Nothing is gathered: a series row from the ranks' exact sums, snapshots and checkpoints
  // written by every rank together (io_mpi.hpp)
  auto output = [&](bool row, bool snap) {
    if (!row && !snap) return;
    const std::int64_t step = sim->step_count();
    const double time = sim->time();
    const Diagnostics d = row ? sim->diagnostics() : Diagnostics{};
    const LevelStats ls = row ? sim->gather_level_stats() : LevelStats{};
    if (row) {  // every rank (d is the same bits everywhere): a NaN is exit 3 on all of them
      const double e[] = {d.kinetic, d.rotational, d.potential_self, d.potential_uniform, d.elastic, d.total()};
      common::require_finite(e, 6, series_path, "energies at step " + std::to_string(step));
      if (std::isnan(E0)) E0 = d.accounted();  // checkpoints record it
    }
    on_root(comm, [&] {
      if (row && levels) {
        common::SeriesRow lr = levels->row();
        detail::levels_row(lr, step, time, ls);
        levels->write(lr);
      }
      if (row) {
        common::SeriesRow r = series->row();
        detail::series_row(r, step, time, d, E0, progress.elapsed(), sim->global_bonds() > 0);
        series->write(r);
        last_rel = detail::relative_energy_error(d, E0);
        progress.update(step, time, cfg.dt, last_rel);
      }
    });
    if (snap) write_snapshot_mpi(comm, detail::snap_name(dir, step), *sim, sim->local_state(), prov);
  };
  auto header = [&](const DomainSim::Local& L) {
    return StateHeader{cfg.dt, L.st.gravity_block, cfg.contact.kn, ident.text(), cfg.self_gravity, L.has_prev, cfg.multirate};
  };
  auto checkpoint = [&](const std::string& path) {
    const DomainSim::Local L = sim->local_state();
    write_checkpoint_mpi(comm, path, *sim, L, header(L), E0, prov);
    spdlog::info("checkpoint at step {} -> {}", L.st.step, path);
  };
  double next_snap = snap_dt > 0 ? (std::floor(sim->time() / snap_dt + 1e-9) + 1) * snap_dt : INFINITY;
  std::size_t next_time = 0;
  while (next_time < times.size() && times[next_time] < sim->time() - 1e-12) ++next_time;
  const common::StopSignals stop;
  if (restart.empty()) output(true, true);
  double last_ckpt_wall = progress.elapsed();
  std::int64_t next_row = (sim->step_count() / series_every + 1) * series_every;
  std::int64_t next_ckpt = ckpt_every > 0 ? (sim->step_count() / ckpt_every + 1) * ckpt_every : 0;
  try {
    while (sim->step_count() < n_end) {
      sim->want_potential(sim->step_count() + 1 >= std::min(next_row, n_end));  // as run.cpp
      sim->step();
      const std::int64_t s = sim->step_count();
      if (!sim->at_gravity_boundary()) continue;
      const bool row = s >= next_row || s >= n_end;
      if (row) next_row = (s / series_every + 1) * series_every;
      bool snap = s >= n_end;
      if (sim->time() >= next_snap - 1e-9 * cfg.dt) {
        snap = true;
        while (next_snap <= sim->time() + 1e-9 * cfg.dt) next_snap += snap_dt;
      }
      while (next_time < times.size() && sim->time() >= times[next_time] - 1e-9 * cfg.dt) {
        snap = true;
        ++next_time;
      }
      output(row, snap);
      // a signal on any rank, or rank 0's wall-clock checkpoint, decided together
      int flags[2] = {stop.pending(), comm.rank == 0 && ckpt_wall > 0 && progress.elapsed() - last_ckpt_wall > ckpt_wall};
      MPI_Allreduce(MPI_IN_PLACE, flags, 2, MPI_INT, MPI_MAX, comm.c);
      if (flags[0] != 0) {
        checkpoint(ckpt_path);
        on_root(comm, [&] {
          series->commit();
          if (levels) levels->commit();
        });
        spdlog::warn("interrupted by signal {} at step {}; restart with --restart {}", flags[0], s, ckpt_path);
        return 128 + flags[0];
      }
      if ((ckpt_every > 0 && s >= next_ckpt) || flags[1]) {
        checkpoint(ckpt_path);
        last_ckpt_wall = progress.elapsed();
        if (ckpt_every > 0) next_ckpt = (s / ckpt_every + 1) * ckpt_every;
      }
    }
    sim->settle();  // a run ending inside a gravity block: its last steps' check, before the checkpoint
  } catch (common::NumericalError& e) {
    // check_state is collective: every rank is here at the same step. As the serial driver: the
    // last verified state as a checkpoint (restartable), else the failing state as a snapshot.
    const std::string failed = (std::filesystem::path(dir) / "failed_state.h5").string();
    const std::optional<DomainSim::Local> good = sim->last_good_local();
    if (good) {
      write_checkpoint_mpi(comm, failed, *sim, *good, header(*good), E0, prov);
      spdlog::error("{}; last good state (step {}) saved to {}", e.what(), good->st.step, failed);
    } else {
      write_snapshot_mpi(comm, failed, *sim, sim->local_state(), prov);
      spdlog::error("{}; failing state saved to {}", e.what(), failed);
    }
    on_root(comm, [&] {
      series->commit();
      if (levels) levels->commit();
    });
    e.set_saved_state(failed);
    throw;
  }
  checkpoint(ckpt_path);
  const DomainStats& ds = sim->stats();
  const PhaseTimes& t = sim->times();
  std::ostringstream os;
  os << "rank " << comm.rank << ": " << sim->owned() << " own spheres, " << sim->ghosts() << " ghosts; "
     << ds.exchanges << " exchanges, " << ds.rebalances << " decompositions, " << t.gravity_evals
     << " gravity evaluations; sent per step: halo " << ds.bytes_halo / std::max<double>(ds.steps, 1)
     << " B, exchanges " << ds.bytes_exchange / std::max<double>(ds.steps, 1) << " B, gravity "
     << ds.bytes_gravity / std::max<double>(ds.steps, 1) << " B; communication " << ds.wall_comm
     << " s; bytes per own sphere " << sim->bytes_per_owned_sphere();
  if (cfg.multirate)
    os << "; multi-rate equalisation rounds " << ds.level_rounds << " in " << ds.steps << " base steps";
  os << "; steps with a mover check " << ds.mover_checks << " (tested and reduced " << ds.mover_reductions << ")";
  if (cfg.contacts)
    os << "; ghost-ghost pairs skipped " << ds.foreign_pairs << "; pair evaluations " << ds.kernel_pairs
       << ", of which with a ghost member (also evaluated on its owner) " << ds.shared_pairs;
  if (sim->global_bonds() > 0) os << "; bonds held " << sim->local_bonds() << " (those across ranks on both)";
  if (const DistributedTree* tr = sim->tree(); tr && tr->stats().evaluations > 0) {
    const LetStats& g = tr->stats();
    const double ne = g.evaluations;
    os << "; gravity tree per evaluation: " << g.gravity_spheres / ne << " spheres walked here ("
       << g.moved_spheres / ne << " from other ranks), imported " << g.imported_particles / ne << " particles and "
       << g.imported_nodes / ne << " cells, sent " << (g.bytes_owners + g.bytes_top + g.bytes_let) / ne
       << " B (to and from gravity owners " << g.bytes_owners / ne << ", top tree " << g.bytes_top / ne
       << ", locally essential trees " << g.bytes_let / ne << "); top cells " << g.top_cells << ", maximal cells "
       << g.maximal_cells << ", tree memory " << tr->bytes() << " B; seconds per evaluation: top tree "
       << g.t_top / ne << ", to and from owners " << g.t_owners / ne << ", build " << g.t_build / ne
       << ", locally essential trees " << g.t_let / ne << ", walk " << g.t_walk / ne;
  }
  std::string lines;
  if (sim->global_bonds() > 0) {  // as the serial driver's last line (collective: the ranks' exact sums)
    const Diagnostics bd = sim->diagnostics();
    lines += detail::bond_report(bd.bonds, bd.bonds_broken, bd.bond_elastic, bd.bond_released) + "\n";
  }
  const LevelStats ls = sim->gather_level_stats();
  if (cfg.multirate)
    lines += detail::levels_report(ls, sim->step_count() - first_step, sim->global_count()) + "\n";
  {
    std::vector<int> counts;
    const std::string s = os.str();
    const std::vector<char> all = comm.gather(std::vector<char>(s.begin(), s.end()), 0, &counts);
    std::size_t off = 0;
    for (int c : counts) {
      lines += std::string(all.begin() + off, all.begin() + off + c) + "\n";
      off += c;
    }
  }
  on_root(comm, [&] {
    series->commit();
    if (levels) levels->commit();
    common::write_text_atomic((std::filesystem::path(dir) / "run_info.txt").string(), run_info + lines);
    rd->publish();
    spdlog::info("MPI decomposition:\n{}", lines);
    spdlog::info("run complete: outputs published in {}", out_dir);
  });
  progress.update(sim->step_count(), sim->time(), cfg.dt, last_rel, true);
  spdlog::info("done: {} steps; wall s: gravity {:.3f} ({} evals), neighbours {:.3f}, contacts {:.3f}, integrate "
               "{:.3f}, communication {:.3f}",
               t.steps, t.gravity, t.gravity_evals, t.neighbours, t.contacts, t.integrate, ds.wall_comm);
  return 0;
}

}  // namespace ssdem::mpi
