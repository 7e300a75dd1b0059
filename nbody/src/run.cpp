/// @file run.cpp
/// ssdem-grav driver (run.hpp).
#include "ssdem/run.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <optional>
#include <sstream>
#include <vector>

#include "common/atomic_file.hpp"
#include "common/build_check.hpp"
#include "common/finite.hpp"
#include "common/log.hpp"
#include "common/run_dir.hpp"
#include "common/run_identity.hpp"
#include "common/series_csv.hpp"
#include "common/status.hpp"
#include "common/stop_signal.hpp"
#include "ssdem/io.hpp"
#include "ssdem/scene_setup.hpp"
#include "ssdem/sphere_order.hpp"

namespace ssdem {
namespace detail {
// Files a run of ssdem-grav writes into its output directory (for directories written before
// run manifests existed: the previous run's files a completed run removes).
bool is_output(const std::string& n) {
  std::string h5 = n;
  if (n.size() > 4 && n.compare(n.size() - 4, 4, ".xmf") == 0) h5 = n.substr(0, n.size() - 4) + ".h5";
  return h5 == "checkpoint.h5" || h5 == "failed_state.h5" || n == "series.csv" || n == "series.csv.partial" ||
         n == "levels.csv" || n == "levels.csv.partial" ||
         n == "run_info.txt" || (h5.rfind("snap_", 0) == 0 && h5.size() > 3 && h5.compare(h5.size() - 3, 3, ".h5") == 0);
}
// The step of a snapshot file name snap_<step>.h5 / .xmf, or -1.
std::int64_t snap_step(const std::string& n) {
  long long s = -1;
  char ext[8] = {0};
  if (std::sscanf(n.c_str(), "snap_%lld.%3s", &s, ext) == 2 && (std::string(ext) == "h5" || std::string(ext) == "xmf"))
    return s;
  return -1;
}

std::string snap_name(const std::string& dir, std::int64_t step) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "snap_%09lld.h5", static_cast<long long>(step));
  return (std::filesystem::path(dir) / buf).string();
}

// series.csv: one row per output step (diagnostics at a gravity-block boundary).
common::SeriesFormat series_format() {
  return common::SeriesFormat({{"step", ""},
                               {"time_s", "s"},
                               {"kinetic_J", "J"},
                               {"rotational_J", "J"},
                               {"potential_self_J", "J"},
                               {"potential_uniform_J", "J"},
                               {"elastic_J", "J"},
                               {"total_J", "J"},
                               {"dissipated_J", "J"},
                               {"energy_error_J", "J"},
                               {"px_kgm_s", "kg m/s"},
                               {"py_kgm_s", "kg m/s"},
                               {"pz_kgm_s", "kg m/s"},
                               {"Lx_kgm2_s", "kg m^2/s"},
                               {"Ly_kgm2_s", "kg m^2/s"},
                               {"Lz_kgm2_s", "kg m^2/s"},
                               {"contacts", ""},
                               {"wall_contacts", ""},
                               {"max_overlap_frac", "1"},
                               {"wall_s", "s"}},
                              {.precision = 17});
}
// With bonds, four more columns (bonds.hpp): the energy stored in intact bonds (part of
// elastic_J), the stored energy of the bonds broken so far (it has left total_J, so
// total_J + bond_released_J is what an undamped run conserves), intact and broken counts.
// Without bonds the series is as before (no bond columns).
common::SeriesFormat series_format(bool bonds) {
  if (!bonds) return series_format();
  std::vector<common::SeriesColumn> c = series_format().columns();
  c.insert(c.end(), {{"bond_elastic_J", "J"}, {"bond_released_J", "J"}, {"bonds_intact", ""}, {"bonds_broken", ""}});
  return common::SeriesFormat(std::move(c), {.precision = 17});
}
void series_row(common::SeriesRow& row, std::int64_t step, double time, const Diagnostics& d, double E0,
                double wall, bool bonds) {
  row.integer(step).num(time).num(d.kinetic).num(d.rotational);
  row.num(d.potential_self).num(d.potential_uniform).num(d.elastic).num(d.total());
  row.num(d.dissipated).num(d.accounted() - E0);
  row.num(d.momentum.x()).num(d.momentum.y()).num(d.momentum.z());
  row.num(d.angular_momentum.x()).num(d.angular_momentum.y()).num(d.angular_momentum.z());
  row.integer(d.contacts).integer(d.wall_contacts).num(d.max_overlap_frac).num(wall);
  if (bonds) row.num(d.bond_elastic).num(d.bond_released).integer(d.bonds - d.bonds_broken).integer(d.bonds_broken);
}
double relative_energy_error(const Diagnostics& d, double E0) {
  const double err = std::fabs(d.accounted() - E0);
  if (E0 != 0.0) return err / std::fabs(E0);
  const double k = d.kinetic + d.rotational;
  return k > 0.0 ? err / k : 0.0;
}
std::string energy_report(const Diagnostics& d, double E0) {
  std::ostringstream os;
  os.precision(6);
  os << "energy: E0 = " << E0 << " J; now conservative " << d.total() << " J + dissipated by contacts "
     << d.dissipated << " J + released by broken bonds " << d.bond_released << " J; error (sum - E0) "
     << d.accounted() - E0 << " J = " << relative_energy_error(d, E0) << " of |E0|";
  const double gone = d.dissipated + d.bond_released;
  if (gone > 0.0) os << ", " << std::fabs(d.accounted() - E0) / gone << " of the dissipated energy";
  return os.str();
}
OutputPlan output_plan(const common::Scene& sc, const SimConfig& cfg, const std::string& dir) {
  OutputPlan p;
  p.t_end = sc.real("time.end");
  const std::int64_t k = cfg.adaptive_gravity ? 1 : cfg.gravity_every;
  p.series_every = (sc.integer("output.series_every") + k - 1) / k * k;
  p.snap_dt = sc.real("output.snapshot_interval");
  p.times = sc.real_list("output.times");
  std::sort(p.times.begin(), p.times.end());
  p.ckpt_every = sc.integer("output.checkpoint_every");
  p.ckpt_wall = sc.real("output.checkpoint_wall");
  p.series_path = (std::filesystem::path(dir) / "series.csv").string();
  p.ckpt_path = (std::filesystem::path(dir) / "checkpoint.h5").string();
  // end on a gravity-block boundary (velocities physical there)
  p.n_end = static_cast<std::int64_t>(std::ceil(p.t_end / cfg.dt - 1e-9));
  p.n_end = (p.n_end + k - 1) / k * k;
  return p;
}
// levels.csv (multi-rate runs): spheres per level at each series row (a gravity-block boundary),
// promotions in the middle of a step and sphere force evaluations so far.
constexpr int kLevelColumns = 16;
common::SeriesFormat levels_format() {
  std::vector<common::SeriesColumn> cols = {{"step", ""}, {"time_s", "s"}};
  for (int l = 0; l < kLevelColumns; ++l) cols.push_back({"n_level" + std::to_string(l), ""});
  cols.push_back({"n_level_coarser", ""});
  cols.push_back({"promotions", ""});
  cols.push_back({"sphere_evaluations", ""});
  return common::SeriesFormat(cols, {.precision = 17});
}

void levels_row(common::SeriesRow& lr, std::int64_t step, double time, const LevelStats& ls) {
  lr.integer(step).num(time);
  std::int64_t coarser = 0;
  for (std::size_t l = kLevelColumns; l < ls.now.size(); ++l) coarser += ls.now[l];
  for (int l = 0; l < kLevelColumns; ++l) lr.integer(static_cast<std::size_t>(l) < ls.now.size() ? ls.now[l] : 0);
  lr.integer(coarser).integer(ls.promotions).integer(ls.evaluations);
}

// Levels used over the run: share of the simulated sphere-time per level.
std::string levels_report(const LevelStats& l, std::int64_t steps, std::size_t spheres) {
  double tot = 0;
  for (double t : l.sphere_time) tot += t;
  std::ostringstream os;
  os << "multi-rate levels (step = 2^l dt): sphere-time share";
  for (std::size_t k = 0; k < l.sphere_time.size(); ++k)
    if (l.sphere_time[k] > 0) os << " l" << k << " " << l.sphere_time[k] / tot;
  os << "; final histogram " << l.histogram_text() << "; " << l.promotions << " promotions in mid-step, "
     << l.evaluations << " sphere evaluations in " << steps << " base steps ("
     << static_cast<double>(l.evaluations) /
            std::max<double>(1.0, static_cast<double>(steps) * static_cast<double>(spheres))
     << " of single-rate)";
  return os.str();
}
std::string bond_report(std::size_t n, std::size_t broken, double stored, double released) {
  std::ostringstream os;
  os.precision(6);
  os << "bonds: " << n << " in all, " << broken << " broken, " << n - broken << " intact; stored in intact bonds "
     << stored << " J; stored energy of the broken bonds (released, left total_J) " << released << " J";
  return os.str();
}
}  // namespace detail
namespace {
using detail::is_output;
using detail::series_format;
using detail::snap_name;
using detail::snap_step;
std::string cadence_text(const SimConfig& c) {
  std::ostringstream os;
  if (c.adaptive_gravity)
    os << "cadence adaptive (gravity.tolerance = " << c.gravity_tolerance << ", max_every = " << c.gravity_max_every << ")";
  else
    os << "cadence fixed, every " << c.gravity_every << " steps";
  return os.str();
}

// Levels used over the run, with the bonds' own levels l_b (multirate_bonds.cpp).
std::string levels_report(const Simulation& sim) {
  std::string r = detail::levels_report(sim.level_stats(), sim.times().steps, sim.spheres().size());
  if (!sim.bond_levels().empty()) {
    std::vector<std::int64_t> h(64, 0);
    for (std::uint8_t b : sim.bond_levels()) ++h[b];
    r += "; bond levels l_b";
    for (std::size_t k = 0; k < h.size(); ++k)
      if (h[k] > 0) r += " l" + std::to_string(k) + ":" + std::to_string(h[k]);
  }
  return r;
}

// The cadence used and its estimated force error (simulation.hpp, error-controlled cadence).
std::string cadence_report(const Simulation& sim) {
  const CadenceStats& c = sim.cadence_stats();
  const PhaseTimes& t = sim.times();
  std::ostringstream os;
  os << "gravity cadence: " << t.gravity_evals << " evaluations in " << t.steps << " steps";
  if (c.blocks > 0)
    os << " (adaptive: mean block " << c.mean_block() << " steps, min " << c.min_block << ", max " << c.max_block
       << "; measured rms relative force change per block: max " << c.max_change << ", mean " << c.mean_change()
       << ", largest of one sphere " << c.max_change_one << "; estimated force error <= half of it)";
  return os.str();
}
// Bonds at the end of the run: counts and energies (the broken bonds' stored energy is reported,
// not lost: bonds.hpp).
std::string bond_report(const Simulation& sim) {
  const BondSystem& b = *sim.bond_system();
  return detail::bond_report(b.bonds().size(), b.broken_count(), b.elastic_energy(sim.spheres()), b.released_energy());
}
}  // namespace

namespace detail {
namespace {
const std::vector<std::string> kRestartMayChange = {"time.end", "output.", "run.sort_every", "gravity.group"};
}  // namespace
common::RunIdentity run_identity(const common::Scene& sc) {
  return common::run_identity(sc, kRestartMayChange, {"initial.file", "initial.ss"});
}
common::RunIdentity checkpoint_identity(const std::string& text) {
  return common::RunIdentity::parse(text).without(kRestartMayChange);
}
void check_restart_identity(const common::Scene& sc, const common::RunIdentity& ident, const std::string& restart,
                            const std::string& recorded, bool log) {
  if (recorded.empty()) {
    if (log)
      spdlog::warn("restart: {} records no run identity (written by an older version); cannot check that it "
                   "belongs to this scene", restart);
    return;
  }
  const common::RunIdentity all = common::RunIdentity::parse(recorded);
  const std::string diff = common::RunIdentity::differences(ident, "this run", all.without(kRestartMayChange), "checkpoint");
  if (!diff.empty())
    throw common::InputError(restart + ": checkpoint of another run (run identity " + all.digest() +
                             ") than this scene's (run identity " + ident.digest() + "); they differ in " + diff);
  const auto group = all.parts.find("gravity.group");
  const std::string now = std::to_string(sc.integer("gravity.group"));
  if (log && group != all.parts.end() && group->second != now)
    spdlog::warn("restart: {} ran with gravity.group = {}, this run uses {} (the tree's sink groups: forces "
                 "change within the tree's error, so the continuation is not bit-identical to an "
                 "uninterrupted run)", restart, group->second, now);
}
}  // namespace detail

int run_ssdem(const common::Scene& sc, const common::Provenance& prov, const std::string& restart, bool sort) {
  const common::RunIdentity ident = detail::run_identity(sc);
  const std::int64_t sort_every = sort ? sc.integer("run.sort_every") : 0;
  // The run locks output.directory and writes into a staging directory published when it
  // completes (common/run_dir.hpp); a restart continues in the staging directory of the
  // interrupted run whose checkpoint it reads, if the checkpoint lies in one.
  const std::string out_dir = sc.string("output.directory");
  common::RunDirectory rd(out_dir, "ssdem-grav", is_output,
                          restart.empty() ? std::string() : common::RunDirectory::staging_of(out_dir, restart));
  const std::string dir = rd.staging();

  std::unique_ptr<Simulation> sim;
  std::string info;
  double energy0 = NAN;
  SphereOrder order;  // file row of each stored sphere (sphere_order.hpp)
  if (restart.empty()) {
    BondSet file_bonds;
    Spheres sp = initial_spheres(sc, &file_bonds);
    const SimConfig cfg = sim_config(sc, sp, &info, &file_bonds);
    order = SphereOrder(sp.size());
    if (sort_every > 0) {
      const std::vector<std::uint32_t> perm = cell_order(sp);
      permute_spheres(sp, perm);
      order.renumber(perm);
    }
    sim = std::make_unique<Simulation>(std::move(sp), cfg);
  } else {
    double dt0 = 0, kn0 = 0;
    int every0 = 0;
    std::string ck_ident;
    SimState st = read_checkpoint(restart, &dt0, &every0, &kn0, &ck_ident);
    detail::check_restart_identity(sc, ident, restart, ck_ident, true);
    if (common::RunDirectory::staging_of(out_dir, restart).empty()) {
      // continuing a published run: its series and snapshots up to the checkpoint become part of this one
      rd.carry("series.csv");
      if (std::filesystem::exists(std::filesystem::path(out_dir) / "levels.csv")) rd.carry("levels.csv");
      for (const auto& e : std::filesystem::directory_iterator(out_dir)) {
        const std::string n = e.path().filename().string();
        const std::int64_t s = snap_step(n);
        if (s >= 0 && s <= st.step) rd.carry(n);
      }
    }
    // the checkpoint's bonds (generated or from the file), so that the dt rule and run_info.txt see
    // the bonds the run continues with
    SimConfig cfg = sim_config(sc, st.sp, &info, &st.bonds, restart);
    if (cfg.contacts && kn0 > 0.0 && cfg.contact.kn != kn0) {
      if (sc.given("contact.normal.kn"))
        spdlog::warn("restart: contact.normal.kn = {} differs from the checkpoint's {}; using the "
                     "checkpoint's value so the continuation is exact", cfg.contact.kn, kn0);
      cfg.contact.kn = kn0;
    }
    // the checkpoint's `every` is the length of the gravity block starting at its step
    if (cfg.dt != dt0 || (!cfg.adaptive_gravity && cfg.gravity_every != every0))
      spdlog::warn("restart: dt or gravity.every differ from the checkpoint ({} s, {}); using the "
                   "checkpoint's values so the continuation is exact",
                   dt0, every0);
    cfg.dt = dt0;
    if (!cfg.adaptive_gravity) cfg.gravity_every = every0;
    st.gravity_block = every0;
    energy0 = st.energy0;
    // the storage order the checkpoint's run had (file order if it recorded none; the MPI build
    // continues in file order)
    if (sort) order = SphereOrder::from_file(st, restart);
    else {
      st.sphere_order.clear();
      order = SphereOrder(st.sp.size());
    }
    if (std::isnan(energy0))
      spdlog::warn("restart: {} records no initial energy (older version); the energy error is reported "
                   "from the restart on", restart);
    sim = std::make_unique<Simulation>(std::move(st), cfg);
    info += "restarted from " + restart + " at step " + std::to_string(sim->step_count()) + "\n";
    if (const std::string note = common::other_build_note(restart); !note.empty()) {
      spdlog::warn("restart: {}", note);
      info += note + "\n";
    }
  }
  const SimConfig cfg = sim->config();  // a copy: a renumbering replaces sim
  std::string run_info;
  {
    std::ostringstream os;
    os << info << "spheres: " << sim->spheres().size() << "\ndt = " << cfg.dt
       << " s\nself-gravity: " << (cfg.self_gravity ? (cfg.direct_gravity ? "direct" : "tree") : "off")
       << ", " << cadence_text(cfg) << "\ncontacts: " << (cfg.contacts ? "on" : "off")
       << " (pair kernel in packs of " << ContactSystem::lanes() << ")"
       << "\nk_n = " << cfg.contact.kn << " N/m, parts mask = " << cfg.contact.parts << "\n"
       << "time stepping: "
       << (cfg.multirate ? "multi-rate (levels of 2^l dt, per-pair steps tau_c / " +
                               std::to_string(cfg.pair_steps_per_contact) + ")"
                         : std::string("single rate"))
       << "\nsphere order in memory: "
       << (sort_every > 0      ? "cells of 2 s_max (z, y, x), renumbered every " + std::to_string(sort_every) + " base steps"
           : !order.identity() ? std::string("the checkpoint's order, not renumbered (run.sort_every = 0)")
           : sort              ? std::string("file order (run.sort_every = 0)")
                               : std::string("file order (the MPI build keeps it at every rank count)"))
       << "\n";
    run_info = os.str();
    common::write_text_atomic((std::filesystem::path(dir) / "run_info.txt").string(), run_info);
    spdlog::info("ssdem-grav: {} spheres, dt = {} s, gravity {} ({}), contacts {}",
                 sim->spheres().size(), cfg.dt,
                 cfg.self_gravity ? (cfg.direct_gravity ? "direct" : "tree") : "off",
                 cadence_text(cfg), cfg.contacts ? "on" : "off");
  }
  sim->set_keep_last_good(std::max<std::int64_t>(cfg.gravity_every, 100 / cfg.gravity_every * cfg.gravity_every));

  const auto [t_end, snap_dt, ckpt_wall, series_every, ckpt_every, n_end, times, series_path, ckpt_path] =
      detail::output_plan(sc, cfg, dir);
  sim->set_end_step(n_end);

  // Rows go to series.csv.partial and are renamed onto series.csv when the run ends, stops on a
  // numerical failure (after saving its state) or on a signal (after its checkpoint); a run that
  // fails otherwise leaves an earlier series.csv as it was. A restart continues the series of
  // the run its checkpoint came from, up to the checkpoint's step.
  const BondSystem* bonds = sim->bond_system();  // null without bonds (renewed by a renumbering)
  common::SeriesFile series_file(series_path, series_format(bonds != nullptr),
                                 restart.empty() ? std::nullopt : std::optional(sim->step_count()));

  std::optional<common::SeriesFile> levels_file;
  if (cfg.multirate)
    levels_file.emplace((std::filesystem::path(dir) / "levels.csv").string(), detail::levels_format(),
                        restart.empty() ? std::nullopt : std::optional(sim->step_count()));
  // E_0 of the energy error: the accounted energy of the first row (a restart: the checkpoint's)
  double E0 = energy0, last_level_log = -INFINITY;
  Diagnostics last;
  const double progress_dt = sc.real("output.progress_interval");
  common::Progress progress("ssdem-grav", sim->time(), t_end, sc.real("output.progress_interval"));
  auto write_row = [&]() {
    const Diagnostics d = sim->diagnostics();
    const double e[] = {d.kinetic, d.rotational, d.potential_self, d.potential_uniform, d.elastic, d.total()};
    common::require_finite(e, 6, series_path, "energies at step " + std::to_string(sim->step_count()));
    if (std::isnan(E0)) E0 = d.accounted();
    last = d;
    common::SeriesRow row = series_file.row();
    detail::series_row(row, sim->step_count(), sim->time(), d, E0, progress.elapsed(), bonds != nullptr);
    series_file.write(row);
    progress.update(sim->step_count(), sim->time(), cfg.dt, detail::relative_energy_error(d, E0));
    if (levels_file) {
      const LevelStats& ls = sim->level_stats();
      common::SeriesRow lr = levels_file->row();
      detail::levels_row(lr, sim->step_count(), sim->time(), ls);
      levels_file->write(lr);
      if (progress.elapsed() - last_level_log >= progress_dt) {
        last_level_log = progress.elapsed();
        spdlog::info("levels at t = {:.6g} s (step = 2^l dt): {}", sim->time(), ls.histogram_text());
      }
    }
  };
  auto checkpoint = [&]() {
    SimState st = order.to_file(sim->state());
    st.energy0 = E0;
    write_checkpoint(ckpt_path, st, cfg.dt, st.gravity_block, prov, cfg.contact.kn, ident.text());
    spdlog::info("checkpoint at step {} -> {}", sim->step_count(), ckpt_path);
  };
  double next_snap = snap_dt > 0 ? (std::floor(sim->time() / snap_dt + 1e-9) + 1) * snap_dt : INFINITY;
  std::size_t next_time = 0;
  while (next_time < times.size() && times[next_time] < sim->time() - 1e-12) ++next_time;

  const common::StopSignals stop;  // SIGTERM/SIGINT: checkpoint after the step, exit 128 + signal

  if (restart.empty()) {
    write_row();
    write_snapshot(snap_name(dir, 0), order.to_file(sim->spheres()), sim->time(), 0, prov,
                   bonds ? &bonds->bonds() : nullptr);
  }
  // Renumbering (sphere_order.hpp) at the first block boundary from next_sort on: a restart from
  // the renumbered state, before the boundary's checkpoint (which then records the new order).
  std::int64_t next_sort = sort_every > 0 ? (sim->step_count() / sort_every + 1) * sort_every : 0;
  std::int64_t sorts = 0;
  auto renumber = [&]() {
    const auto t0 = std::chrono::steady_clock::now();
    SimState st = sim->state();
    const std::vector<std::uint32_t> perm = cell_order(st.sp);
    permute_state(st, perm);
    // (the old simulation, its state and the new one are alive together here: ~2x the memory of
    // the spheres' arrays for the length of the construction)
    auto next = std::make_unique<Simulation>(std::move(st), sim->config());
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    next->continue_counters(*sim, wall);
    sim = std::move(next);
    order.renumber(perm);  // only once sim holds the permuted state
    bonds = sim->bond_system();
    ++sorts;
  };
  double last_ckpt_wall = progress.elapsed();
  std::int64_t next_row = (sim->step_count() / series_every + 1) * series_every;
  std::int64_t next_ckpt = ckpt_every > 0 ? (sim->step_count() / ckpt_every + 1) * ckpt_every : 0;
  try {
    while (sim->step_count() < n_end) {
      // a row is due at the first block boundary from next_row on: its gravity evaluation gives
      // the potential too (instead of a second evaluation for the row)
      sim->want_potential(sim->step_count() + 1 >= std::min(next_row, n_end));
      sim->step();
      const std::int64_t s = sim->step_count();
      if (!sim->at_gravity_boundary()) continue;  // velocities are physical at block boundaries only
      if (s >= next_row || s >= n_end) {
        write_row();
        next_row = (s / series_every + 1) * series_every;
      }
      bool snap = false;
      if (sim->time() >= next_snap - 1e-9 * cfg.dt) {
        snap = true;
        while (next_snap <= sim->time() + 1e-9 * cfg.dt) next_snap += snap_dt;
      }
      while (next_time < times.size() && sim->time() >= times[next_time] - 1e-9 * cfg.dt) {
        snap = true;
        ++next_time;
      }
      if (snap || s >= n_end)
        write_snapshot(snap_name(dir, s), order.to_file(sim->spheres()), sim->time(), s, prov,
                       bonds ? &bonds->bonds() : nullptr);
      // (at the last boundary too: the final checkpoint then holds the order that a run
      // extending this one with --restart and a later time.end continues with)
      if (sort_every > 0 && s >= next_sort) {
        renumber();
        next_sort = (s / sort_every + 1) * sort_every;
      }
      const int sig = stop.pending();
      if (sig != 0) {
        checkpoint();
        series_file.commit();
        if (levels_file) levels_file->commit();
        spdlog::warn("interrupted by signal {} at step {}; restart with --restart {}", sig, s, ckpt_path);
        return 128 + sig;
      }
      if ((ckpt_every > 0 && s >= next_ckpt) ||
          (ckpt_wall > 0 && progress.elapsed() - last_ckpt_wall > ckpt_wall)) {
        checkpoint();
        last_ckpt_wall = progress.elapsed();
        if (ckpt_every > 0) next_ckpt = (s / ckpt_every + 1) * ckpt_every;
      }
    }
  } catch (common::NumericalError& e) {
    const std::string failed = (std::filesystem::path(dir) / "failed_state.h5").string();
    if (sim->last_good()) {
      SimState good = order.to_file(*sim->last_good());
      good.energy0 = E0;  // a restart from it reports its energy error against the run's E_0
      write_checkpoint(failed, good, cfg.dt, good.gravity_block, prov, cfg.contact.kn, ident.text());
      spdlog::error("{}; last good state (step {}) saved to {}", e.what(), good.step, failed);
    } else {
      write_snapshot(failed, order.to_file(sim->spheres()), sim->time(), sim->step_count(), prov);
      spdlog::error("{}; failing state saved to {}", e.what(), failed);
    }
    e.set_saved_state(failed);
    series_file.commit();
    if (levels_file) levels_file->commit();
    throw;
  }
  checkpoint();
  series_file.commit();
  if (levels_file) levels_file->commit();
  {
    std::string tail;
    tail += detail::energy_report(last, E0) + "\n";
    if (cfg.self_gravity) tail += cadence_report(*sim) + "\n";
    if (cfg.multirate) tail += levels_report(*sim) + "\n";
    if (const ContactSystem* cs = sim->contact_system())
      tail += "neighbour list: " + std::to_string(cs->rebuild_count()) + " full rebuilds, " +
              std::to_string(cs->local_update_count()) + " merges of new pairs, " +
              std::to_string(cs->reinsert_count()) + " sphere re-insertions (" +
              std::to_string(cs->margin_count()) + " of them isolated: margin taken), " +
              std::to_string(cs->test_count()) + " re-insertion tests; " +
              std::to_string(cs->pair_count()) + " pairs listed at the end\n";
    if (bonds) tail += bond_report(*sim) + "\n";
    if (sort_every > 0) tail += "sphere order: " + std::to_string(sorts) + " renumberings after the start\n";
    tail += "thread teams: " + sim->team_tuner().report() + "\n";
    if (!tail.empty()) {
      spdlog::info("{}", tail.substr(0, tail.size() - 1));
      common::write_text_atomic((std::filesystem::path(dir) / "run_info.txt").string(), run_info + tail);
    }
  }
  rd.publish();
  spdlog::info("run complete: outputs published in {}", out_dir);
  progress.update(sim->step_count(), sim->time(), cfg.dt, std::isnan(E0) ? 0.0 : detail::relative_energy_error(last, E0), true);
  const PhaseTimes& t = sim->times();
  spdlog::info("done: {} steps; wall s: gravity {:.3f} ({} evals), neighbours {:.3f} ({} rebuilds), "
               "contacts {:.3f}, integrate {:.3f} (levels {:.3f})",
               t.steps, t.gravity, t.gravity_evals, t.neighbours, t.neighbour_builds, t.contacts, t.integrate,
               t.levels);
  return 0;
}

}  // namespace ssdem
