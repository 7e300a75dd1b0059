/// @file run.hpp
/// The ssdem-grav driver: builds the simulation from a scene (or a checkpoint), runs it with
/// snapshots, a time-series CSV, progress lines and checkpoints (periodic, at the end and on
/// SIGTERM/SIGINT), and on a numerical failure saves the last good state and throws
/// common::NumericalError (exit code 3).
///
/// Outputs in output.directory (written in <dir>/.staging-<pid>, published on success: common/run_dir.hpp): snap_<step>.h5 (+ .xmf), series.csv, checkpoint.h5,
/// failed_state.h5 (only after a failure), run_info.txt (choices made by the dt rule).
/// Interrupted by SIGTERM/SIGINT: checkpoint written, exit code 128 + signal number.
#pragma once
#include <string>

#include <cstdint>

#include "common/provenance.hpp"
#include "common/run_identity.hpp"
#include "common/schema.hpp"
#include "common/series_csv.hpp"
#include "ssdem/simulation.hpp"

namespace ssdem {

/// Run a scene; `restart` = checkpoint file to continue from ("" = fresh start).
/// Returns the process exit code (0, or 128+signal when interrupted).
/// `sort`: renumber the spheres in memory as run.sort_every asks (sphere_order.hpp); the MPI build
/// passes false at every rank count, so that one rank and N ranks give the same bits.
int run_ssdem(const common::Scene& scene, const common::Provenance& prov, const std::string& restart,
              bool sort = true);

/// Shared with the MPI driver (mpi/run_mpi.hpp), so both write the same files.
namespace detail {
/// Identity of a run, recorded in its checkpoints: --restart refuses another run's. Keys a restart
/// may change: time.end, every output.* key, run.sort_every (the order in memory: round-off
/// only; a checkpoint records it) and gravity.group (the sink group size: a cost setting, forces
/// change within the tree's error; its default went from 64 to 256 on 2026-12-06).
common::RunIdentity run_identity(const common::Scene& scene);
/// A checkpoint's recorded identity (its text) without the keys run_identity leaves out, so that
/// checkpoints written while such a key was still recorded continue.
common::RunIdentity checkpoint_identity(const std::string& text);
/// --restart's check of the checkpoint `restart` (recorded identity `recorded`, "" = none) against
/// this run's `ident`: common::InputError naming the differing keys (and the checkpoint's recorded
/// digest) for another run's; with `log`, a warning for a checkpoint without an identity and for
/// one whose recorded gravity.group differs from this run's (it continues, not bit-identically).
void check_restart_identity(const common::Scene& scene, const common::RunIdentity& ident, const std::string& restart,
                            const std::string& recorded, bool log);
bool is_output(const std::string& name);                              ///< a file a run writes
std::string snap_name(const std::string& dir, std::int64_t step);     ///< <dir>/snap_<step>.h5
std::int64_t snap_step(const std::string& name);                      ///< step of a snapshot name, or -1
common::SeriesFormat series_format();                                 ///< series.csv columns
common::SeriesFormat series_format(bool bonds);                       ///< with the bond columns if `bonds`
/// One series.csv row from the diagnostics d at (step, time); E0 = the run's initial
/// Diagnostics::accounted() (energy_error_J = accounted - E0); wall = elapsed wall seconds;
/// `bonds`: the four bond columns of series_format(true) follow.
void series_row(common::SeriesRow& r, std::int64_t step, double time, const Diagnostics& d, double E0,
                double wall, bool bonds);
/// |accounted - E0| / |E0| (the progress line's dE/E0; E0 = 0: relative to the kinetic energy).
double relative_energy_error(const Diagnostics& d, double E0);
/// The run's energy balance at d, for the log and run_info.txt (one line).
std::string energy_report(const Diagnostics& d, double E0);
/// The bonds at the end of a run (one line): n bonds, `broken` of them broken, the energy
/// `stored` in the intact ones and that `released` by the broken ones [J].
std::string bond_report(std::size_t n, std::size_t broken, double stored, double released);
/// When a run writes what: end time and step (rounded up to a gravity-block boundary), snapshot
/// interval, checkpoint cadences, series cadence (a multiple of the fixed gravity block), paths.
struct OutputPlan {
  double t_end = 0, snap_dt = 0, ckpt_wall = 0;
  std::int64_t series_every = 1, ckpt_every = 0, n_end = 0;
  std::vector<double> times;
  std::string series_path, ckpt_path;
};
OutputPlan output_plan(const common::Scene& scene, const SimConfig& cfg, const std::string& dir);
/// levels.csv (multi-rate runs): step, time, spheres per level 0..15 and coarser, promotions,
/// sphere evaluations so far; one row per series row.
common::SeriesFormat levels_format();
void levels_row(common::SeriesRow& r, std::int64_t step, double time, const LevelStats& ls);
/// The run's level use for the log and run_info.txt (one line): sphere-time share per level,
/// final histogram, promotions, evaluations against single rate.
std::string levels_report(const LevelStats& ls, std::int64_t steps, std::size_t spheres);
}  // namespace detail

}  // namespace ssdem
