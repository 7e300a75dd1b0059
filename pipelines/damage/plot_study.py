#!/usr/bin/python3
"""Brazilian-disk (or compression) strength study table: seeds grouped per (sampling, cell,
Courant, nominal rate); log-log slope of strength against the effective rate; strength
interpolated at a reference effective rate.

usage: plot_study.py <outdir> <summary.csv> [<summary.csv> ...] [--ref RATE] [--name study]

Reads summary.csv rows of run_brazilian.sh (test driver) or scene_summary.csv rows of
run_scene.sh (mpm-frag scenes): columns nominal_rate, effective_rate, sigma_t_Pa, cell_m,
seed, sampling, wall_s and, where present, centre_rate and courant. Writes <outdir>/<name>.md
(table: sampling, h, Courant, nominal 2v/D, effective (d sigma_t/dt)/E, centre (d sigma_xx/dt)/E,
strength mean, seed spread (sample standard deviation and min..max), the strength from the platen
load (scenes: sigma_platen_Pa of lab_strength.py), seeds, wall and CPU time) and
<name>.png (strength against the effective rate with the seed spread as error bars).
"""
import os
import sys
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, "lib"))
import atomic  # noqa: E402
import mdtable  # noqa: E402
from csvio import read_rows  # noqa: E402


def main():
    args = sys.argv[1:]
    ref, name = 100.0, "study"
    if "--ref" in args:
        i = args.index("--ref")
        ref = float(args[i + 1])
        del args[i:i + 2]
    if "--name" in args:
        i = args.index("--name")
        name = args[i + 1]
        del args[i:i + 2]
    out, files = args[0], args[1:]
    os.makedirs(out, exist_ok=True)
    groups = defaultdict(list)
    for f in files:
        for r in read_rows(f):
            key = (r.get("sampling", "poisson"), float(r["cell_m"]), float(r.get("courant", 0.3) or 0.3),
                   float(r["nominal_rate"]))
            groups[key].append(r)
    lines = ["# " + name, ""]
    lines += mdtable.header(["sampling", "h (mm)", "Courant", "nominal 2v/D (1/s)", "effective (1/s)",
                             "centre (1/s)", "strength (MPa)", "seed sd (MPa)", "min..max (MPa)",
                             "platen-load strength (MPa)", "seeds", "wall (s)", "CPU (s)"])
    series = defaultdict(list)
    for key in sorted(groups):
        rs = groups[key]
        s = np.array([float(r["sigma_t_Pa"]) for r in rs]) / 1e6
        e = np.array([float(r["effective_rate"]) for r in rs])
        c = np.array([float(r.get("centre_rate") or "nan") for r in rs])
        w = np.array([float(r["wall_s"]) for r in rs])
        cpu = np.array([float(r.get("cpu_s") or "nan") for r in rs])
        sp = np.array([float(r.get("sigma_platen_Pa") or "nan") for r in rs]) / 1e6
        sd = s.std(ddof=1) if len(s) > 1 else float("nan")
        lines.append(mdtable.row([key[0], "%g" % (key[1] * 1e3), "%g" % key[2], "%g" % key[3],
                                  "%.1f" % e.mean(), "%.1f" % np.nanmean(c) if np.isfinite(c).any() else "-",
                                  "%.1f" % s.mean(), "%.1f" % sd if len(s) > 1 else "-",
                                  "%.1f..%.1f" % (s.min(), s.max()),
                                  "%.1f" % np.nanmean(sp) if np.isfinite(sp).any() else "-", len(s),
                                  "%.0f" % w.mean(), "%.0f" % np.nanmean(cpu) if np.isfinite(cpu).any() else "-"]))
        series[key[:3]].append((e.mean(), s.mean(), sd if len(s) > 1 else 0.0))
    lines += ["", "Log-log fit of the mean strength against the effective rate, and the strength "
              "interpolated (log-log) at %g 1/s effective:" % ref, ""]
    lines += mdtable.header(["sampling", "h (mm)", "Courant", "slope", "strength at %g 1/s (MPa)" % ref])
    fig, ax = plt.subplots(figsize=(6.5, 4.5))
    for key, pts in sorted(series.items()):
        pts = np.array(sorted(pts))
        slope = np.polyfit(np.log(pts[:, 0]), np.log(pts[:, 1]), 1)[0] if len(pts) > 1 else float("nan")
        if pts[0, 0] <= ref <= pts[-1, 0]:
            at = "%.1f" % np.exp(np.interp(np.log(ref), np.log(pts[:, 0]), np.log(pts[:, 1])))
        elif len(pts) > 1:  # short extrapolation along the group's own log-log fit
            c = np.polyfit(np.log(pts[:, 0]), np.log(pts[:, 1]), 1)
            at = "%.1f (extrapolated)" % np.exp(np.polyval(c, np.log(ref)))
        else:
            at = "-"
        lines.append(mdtable.row([key[0], "%g" % (key[1] * 1e3), "%g" % key[2],
                                  "%.3f" % slope if len(pts) > 1 else "-", at]))
        ax.errorbar(pts[:, 0], pts[:, 1], yerr=pts[:, 2], marker="o", capsize=3,
                    label="%s, h = %g mm, C = %g" % (key[0], key[1] * 1e3, key[2]))
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("effective strain rate (d sigma_t/dt)/E (1/s)")
    ax.set_ylabel("strength (MPa)")
    ax.legend(fontsize=7)
    ax.grid(True, which="both", alpha=0.3)
    atomic.save_png(fig, os.path.join(out, name + ".png"), 150)
    atomic.write_text(os.path.join(out, name + ".md"), "\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
