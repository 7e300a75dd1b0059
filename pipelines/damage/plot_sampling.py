#!/usr/bin/python3
"""Brazilian-disk strength with the two flaw samplings, against strain rate and cell size.

usage: plot_sampling.py <outdir> <label>=<run dir> [<label>=<run dir> ...]

Each run dir holds a summary.csv of run_brazilian.sh (any cell sizes); <label> names its flaw
sampling (poisson, expected). Writes <outdir>/sampling.md and sampling.png: sigma_t = 2F/(pi D t)
against the effective strain rate for every (sampling, cell) with the Grady-Kipp model band of
validation-data.md 1.3, and a table with the band at each run's rate.
"""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, "lib"))
import atomic  # noqa: E402

GK_RATE = np.array([1, 10, 20, 50, 100, 200, 1e3])
GK_LO = np.array([10.8, 15.5, 17.3, 20.0, 22.3, 24.9, 32.1])  # Nakamura+07 (m = 16) [C]
GK_HI = np.array([9.1, 16.1, 19.2, 24.1, 28.7, 34.1, 51.0])   # BA99 (m = 9) [C]


def band(rate):
    lo = np.interp(np.log10(rate), np.log10(GK_RATE), GK_LO)
    hi = np.interp(np.log10(rate), np.log10(GK_RATE), GK_HI)
    return min(lo, hi), max(lo, hi)


def main():
    out = sys.argv[1]
    os.makedirs(out, exist_ok=True)
    runs = []
    for arg in sys.argv[2:]:
        label, d = arg.split("=", 1)
        with open(os.path.join(d, "summary.csv")) as f:
            for r in csv.DictReader(f):
                runs.append((label, float(r["cell_m"]), float(r["courant"]), float(r["nominal_rate"]),
                             float(r["effective_rate"]), float(r["sigma_t_Pa"]) / 1e6, int(r["steps"]),
                             int(r["particles"]), float(r["wall_s"])))
    runs.sort(key=lambda r: (r[0], -r[1], r[3]))
    md = ["# Brazilian disk: flaw sampling (per-particle Poisson vs expected density) and cell size", "",
          "sigma_t = 2 F_peak / (pi D t); effective rate = (d sigma_t/dt)/E over the 20-80 % rise; band: "
          "Grady-Kipp model band [C] of validation-data.md 1.3 (not measured data).", "",
          "| sampling | cell (mm) | nominal 2v/D (1/s) | effective rate (1/s) | sigma_t (MPa) | band (MPa) | sigma_t / band centre | steps | particles | wall (s) |",
          "|---|---|---|---|---|---|---|---|---|---|"]
    for lab, h, c, nom, eff, st, steps, n, wall in runs:
        lo, hi = band(eff)
        md.append(f"| {lab} | {h * 1e3:.2g} | {nom:.0f} | {eff:.1f} | {st:.1f} | {lo:.1f}-{hi:.1f} | "
                  f"{st / (0.5 * (lo + hi)):.2f} | {steps} | {n} | {wall:.0f} |")
    # sigma_t at fixed effective rates (log-log interpolation inside each series; no extrapolation)
    fixed = (30.0, 100.0, 200.0)
    md += ["", "sigma_t (MPa) at fixed effective rates, interpolated log-log within each series "
           "(n/a outside its range):", "",
           "| sampling | cell (mm) | " + " | ".join(f"{r:.0f} 1/s" for r in fixed) + " |",
           "|---|---|" + "---|" * len(fixed)]
    for lab in sorted({r[0] for r in runs}):
        for h in sorted({r[1] for r in runs if r[0] == lab}, reverse=True):
            sel = sorted((r[4], r[5]) for r in runs if r[0] == lab and r[1] == h)
            lr, ls = np.log([e for e, _ in sel]), np.log([v for _, v in sel])
            cells = []
            for rate in fixed:
                x = np.log(rate)
                cells.append(f"{np.exp(np.interp(x, lr, ls)):.1f}" if lr[0] <= x <= lr[-1] else "n/a")
            md.append(f"| {lab} | {h * 1e3:.2g} | " + " | ".join(cells) + " |")
    md.append("| band [C] | | " + " | ".join(f"{band(r)[0]:.1f}-{band(r)[1]:.1f}" for r in fixed) + " |")
    with open(os.path.join(out, "sampling.md"), "w") as f:
        f.write("\n".join(md) + "\n")
    print("\n".join(md))

    fig, ax = plt.subplots(figsize=(6.5, 4.5))
    rr = np.logspace(0.8, 2.8, 50)
    ax.fill_between(rr, [band(r)[0] for r in rr], [band(r)[1] for r in rr], color="0.85",
                    label="Grady-Kipp band [C] (validation-data 1.3)")
    markers = {0.4e-3: "s", 0.2e-3: "^", 0.1e-3: "o"}
    colours = {"poisson": "tab:red", "expected": "tab:blue"}
    for lab in sorted({r[0] for r in runs}):
        for h in sorted({r[1] for r in runs if r[0] == lab}, reverse=True):
            sel = [r for r in runs if r[0] == lab and r[1] == h]
            ax.plot([r[4] for r in sel], [r[5] for r in sel], marker=markers.get(h, "x"),
                    color=colours.get(lab, "k"), ls="-", lw=1,
                    label=f"{lab}, {h * 1e3:.2g} mm")
    ax.set_xscale("log")
    ax.set_xlabel("effective strain rate (1/s)")
    ax.set_ylabel("Brazilian tensile strength 2F/(pi D t) (MPa)")
    ax.set_title("Basalt Brazilian disk, Tonge-Ramesh (El Mir 2019 Table 1)", fontsize=10)
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=7)
    fig.tight_layout()
    atomic.save_png(fig, os.path.join(out, "sampling.png"), dpi=120, close=False)
    return 0


if __name__ == "__main__":
    sys.exit(main())
