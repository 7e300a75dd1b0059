"""The report's four figures (MPM damage, spheres during reaccumulation, M_LR/M_PB and beta against
time, damage profiles), each returned as its Markdown paragraph; a figure whose inputs are
missing or fail is replaced by a "not available" sentence (and a note)."""
import math
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from .common import NA, fmt  # noqa: E402
from .cutaway import snapshot_panel_figure  # noqa: E402
from .files import save_fig  # noqa: E402
from .inputs import analysis_csv, load_csv, num  # noqa: E402
from .physics import PAPER  # noqa: E402


def figures_section(run, summary, frame, out, notes):
    """The "Figures" section: heading and one paragraph per figure."""
    return ["## Figures\n",
            figure_mpm(run, frame, out, notes),
            figure_nbody(run, frame, out, notes),
            figure_history(summary, run.analysis, out, notes),
            figure_profile(summary, run.analysis, out, notes)]


def figure_mpm(run, frame, out, notes):
    if not run.mpm:
        return f"**Damage in the MPM stage (cf. paper Fig. 4):** {NA} (no mpm-frag snapshots).\n"
    try:
        times, missing = snapshot_panel_figure(run.mpm, "mpm", frame, os.path.join(out, "fig_mpm_damage.png"),
                                               "MPM damage, slice through the impact axis", "com")
        extra = f" No damage field in {', '.join(missing)}." if missing else ""
        return (f"**Damage in the MPM stage (cf. paper Fig. 4)**, a slice one particle thick through the impact axis at "
                f"t = {', '.join(fmt(t, 3) for t in times)} s.{extra}\n\n![MPM damage](fig_mpm_damage.png)\n")
    except Exception as e:
        notes.append(f"MPM figure failed: {e}")
        return f"**Damage in the MPM stage:** {NA} ({e}).\n"


def figure_nbody(run, frame, out, notes):
    # the first ssdem-grav snapshot usually repeats the hand-off state: keep one per time
    items, seen = [], set()
    for t, p in run.handoff + run.nbody:
        if t not in seen:
            seen.add(t)
            items.append((t, p))
    items.sort()
    if not items:
        return f"**Spheres during reaccumulation (cf. paper Fig. 5):** {NA} (no sphere files).\n"
    try:
        times, missing = snapshot_panel_figure(items, "spheres", frame, os.path.join(out, "fig_nbody_spheres.png"),
                                               "spheres coloured by damage, slice through the main body", "median")
        extra = f" No damage field in {', '.join(missing)}." if missing else ""
        return (f"**Spheres during reaccumulation (cf. paper Fig. 5)**, a slice one sphere thick through the mass-weighted "
                f"median position at t = {', '.join(fmt(t, 3) for t in times)} s.{extra}\n\n"
                "![spheres](fig_nbody_spheres.png)\n")
    except Exception as e:
        notes.append(f"N-body figure failed: {e}")
        return f"**Spheres during reaccumulation:** {NA} ({e}).\n"


def figure_history(summary, summary_path, out, notes):
    p = analysis_csv(summary, summary_path, "timeseries_csv", ".timeseries.csv")
    if not p:
        return f"**M_LR/M_PB and beta against time:** {NA} (no analysis time series).\n"
    try:
        rows = load_csv(p)
        t = np.array([num(r, "time") for r in rows])
        scale, unit = (3600.0, "h") if t.size and np.nanmax(t) > 7200 else (1.0, "s")
        fig, (a1, a2) = plt.subplots(1, 2, figsize=(10, 3.8))
        a1.plot(t / scale, [num(r, "M_LR_over_M_PB") for r in rows], "o-", ms=3, label="largest remnant M_LR/M_PB")
        a1.plot(t / scale, [num(r, "bound_mass_fraction") for r in rows], "s--", ms=3, label="bound remnant / M_PB")
        a1.axhline(PAPER["M_LR_over_M_PB"], color="k", lw=0.8, ls=":", label="El Mir et al. 2019: 0.85")
        a1.set_xlabel(f"time [{unit}]")
        a1.set_ylabel("mass fraction")
        a1.legend(fontsize=7)
        b = np.array([num(r, "beta") for r in rows])
        if np.any(np.isfinite(b)):
            a2.plot(t / scale, b, "o-", ms=3, label="beta (bound remnant)")
            a2.plot(t / scale, [num(r, "beta_lr") for r in rows], "s--", ms=3, label="beta (largest remnant)")
            bs = np.array([num(r, "beta_escape_speed") for r in rows])
            if np.any(np.isfinite(bs)):
                a2.plot(t / scale, bs, "^:", ms=3, label="beta (sphere escape speed)")
            a2.axhline(PAPER["beta"], color="k", lw=0.8, ls=":", label="El Mir et al. 2019: 1.69")
            a2.legend(fontsize=7)
        else:
            a2.text(0.5, 0.5, "beta not available\n(no impactor mass/velocity given)", ha="center", transform=a2.transAxes)
        a2.set_xlabel(f"time [{unit}]")
        a2.set_ylabel("beta")
        fig.tight_layout()
        save_fig(fig, os.path.join(out, "fig_history.png"))
        return "**M_LR/M_PB and beta against time** (from `" + os.path.basename(p) + "`).\n\n![history](fig_history.png)\n"
    except Exception as e:
        notes.append(f"history figure failed: {e}")
        return f"**M_LR/M_PB and beta against time:** {NA} ({e}).\n"


def figure_profile(summary, summary_path, out, notes):
    p = analysis_csv(summary, summary_path, "damage_csv", ".damage.csv")
    if not p:
        return f"**Damage profile (cf. paper Fig. 6):** {NA} (no analysis damage profile).\n"
    try:
        rows = load_csv(p)
        if not rows:
            return f"**Damage profile (cf. paper Fig. 6):** {NA} (the analysis found no damage field).\n"
        groups = {}
        for r in rows:
            groups.setdefault((r["kind"], r["stage"], r["set"]), []).append(r)
        labels = {"mpm_end": "end of MPM", "handoff": "hand-off spheres", "nbody_end": "end of N-body"}
        span = max((abs(num(r, "hi")) for r in rows if math.isfinite(num(r, "hi"))), default=1.0)
        scale, unit = (1e3, "km") if span > 5e3 else (1.0, "m")
        fig, axes = plt.subplots(1, 2, figsize=(10, 3.8))
        for ax, kind in zip(axes, ("axial", "radial")):
            for (k, stage, st), rs in sorted(groups.items()):
                if k != kind:
                    continue
                x = np.array([num(r, "centre") for r in rs])
                y = np.array([num(r, "mean_damage") for r in rs])
                ok = np.isfinite(x) & np.isfinite(y)  # empty bins have no mean
                x, y = x[ok], y[ok]
                ax.plot(x / scale, y, "o-" if st == "all" else "s--", ms=3,
                        label=f"{labels.get(stage, stage)} ({'bound remnant' if st == 'bound' else 'all'})")
            ax.set_ylim(-0.02, 1.02)
            ax.set_ylabel("mass-weighted mean damage")
            ax.set_xlabel(f"position along the impact direction [{unit}] (impact site < 0)" if kind == "axial"
                          else f"distance from the centre of mass [{unit}]")
            ax.legend(fontsize=7)
        fig.tight_layout()
        save_fig(fig, os.path.join(out, "fig_damage_profile.png"))
        return ("**Damage profile (cf. paper Fig. 6)**: along the impact axis and in radial shells, at the end of MPM "
                "and of the N-body run.\n\n![damage profile](fig_damage_profile.png)\n")
    except Exception as e:
        notes.append(f"damage-profile figure failed: {e}")
        return f"**Damage profile:** {NA} ({e}).\n"
