#!/usr/bin/python3
"""Flaw-seed ensemble of one impact (target impact-ensemble): mean and spread of the outcomes.

    /usr/bin/python3 ensemble.py RUN_DIR [RUN_DIR ...] --out DIR

Each RUN_DIR is one run of the impact pipeline with the same settings except the flaw seed
(`run.seed` of mpm-frag, read from RUN_DIR/.vars/FRAGMENT). For each outcome x over the n seeds:

    mean  = (1/n) sum x_i
    std   = sqrt( sum (x_i - mean)^2 / (n - 1) )     (sample standard deviation; 0 for n = 1)
    sem   = std / sqrt(n)                             (standard error of the mean)
    min, max

for M_LR/M_PB (largest remnant over parent body), beta (momentum enhancement of the bound
remnant), the hand-off kinetic-energy loss (mpm2spheres audit), the bound-mass fraction, the
MPM energy change and the MPM transfer heat over the initial energy. Writes DIR/ensemble_runs.csv
(one row per seed), DIR/ensemble.csv (one row per quantity: n, mean, std, sem, min, max) and
DIR/ensemble.md. Exit 1 (tables still written, the
problem named) when a run is incomplete, two runs share a seed, or the runs differ in anything but
the seed (cell size or impact speed), so that an ensemble of unlike runs is never averaged silently.
"""
import csv
import io
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from run_summary import read_run, run_dirs_args, total_wall  # noqa: E402
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, "lib"))
import atomic  # noqa: E402
import mdtable  # noqa: E402

QUANTITIES = (("M_LR_over_M_PB", "M_LR/M_PB", 1.0, "{:.4f}"),
              ("beta", "beta", 1.0, "{:.3f}"),
              ("ke_loss", "hand-off KE loss (%)", 100.0, "{:.3f}"),
              ("bound_mass_fraction", "bound mass / M_PB", 1.0, "{:.4f}"),
              ("mpm_energy_change", "MPM energy change (%)", 100.0, "{:+.4f}"),
              ("transfer_heat_frac", "transfer heat / E0", 1.0, "{:.4f}"))


def stats(values):
    """dict n, mean, std (n-1), sem, min, max of the finite values; None entries when there are none."""
    v = [float(x) for x in values if isinstance(x, (int, float)) and math.isfinite(x)]
    n = len(v)
    if n == 0:
        return {"n": 0, "mean": None, "std": None, "sem": None, "min": None, "max": None}
    mean = sum(v) / n
    std = math.sqrt(sum((x - mean) ** 2 for x in v) / (n - 1)) if n > 1 else 0.0
    return {"n": n, "mean": mean, "std": std, "sem": std / math.sqrt(n), "min": min(v), "max": max(v)}


def check_alike(runs):
    """Problems that make the runs not one ensemble (same seed twice, different cell or speed)."""
    out = []
    seeds = [r["seed"] for r in runs]
    dup = sorted({s for s in seeds if s is not None and seeds.count(s) > 1})
    if dup:
        out.append(f"seed(s) {dup} used by more than one run")
    for key in ("cell_m", "speed_m_s"):
        vals = {r[key] for r in runs}
        if len(vals) > 1:
            out.append(f"runs differ in {key}: {sorted(vals, key=str)}")
    return out


def main(argv=None):
    a = run_dirs_args(__doc__, argv)
    runs = sorted((read_run(d) for d in a.runs), key=lambda r: (r["seed"] is None, r["seed"] or 0))
    problems = [f"{r['run']}: {p}" for r in runs for p in r["problems"]] + check_alike(runs)

    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(["seed", "run", "cell_m", "speed_m_s"] + [k for k, _, _, _ in QUANTITIES]
               + ["spheres", "wall_total_s"])
    for r in runs:
        w.writerow([r["seed"], r["run"], r["cell_m"], r["speed_m_s"]] + [repr(r[k]) if r[k] is not None else ""
                                                                         for k, _, _, _ in QUANTITIES]
                   + [r["spheres"], f"{total_wall(r):.2f}"])
    atomic.write_text(os.path.join(a.out, "ensemble_runs.csv"), buf.getvalue())

    table = {k: stats([r[k] for r in runs]) for k, _, _, _ in QUANTITIES}
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(["quantity", "n", "mean", "std", "sem", "min", "max"])
    for k, _, _, _ in QUANTITIES:
        s = table[k]
        w.writerow([k, s["n"]] + [repr(s[c]) if s[c] is not None else "" for c in ("mean", "std", "sem", "min", "max")])
    atomic.write_text(os.path.join(a.out, "ensemble.csv"), buf.getvalue())

    def f(x, scale, fmt):
        return "n/a" if x is None else fmt.format(scale * x)

    r0 = runs[0]
    md = ["# Flaw-seed ensemble", "",
          f"{len(runs)} runs of one impact (MPM cell {f(r0['cell_m'], 1, '{:.0f}')} m, impact speed "
          f"{f(r0['speed_m_s'], 1, '{:.0f}')} m/s) that differ only in the flaw seed `run.seed`: "
          f"{', '.join(str(r['seed']) for r in runs)}. std is the sample standard deviation (n - 1), "
          "sem = std / sqrt(n).", ""]
    md += mdtable.header(["quantity", "n", "mean", "std", "sem", "min", "max"])
    for k, label, scale, fmt in QUANTITIES:
        s = table[k]
        md.append(mdtable.row([label, s["n"]] + [f(s[c], scale, fmt) for c in ("mean", "std", "sem", "min", "max")]))
    md += ["", "Per seed:", ""]
    md += mdtable.header(["seed"] + [label for _, label, _, _ in QUANTITIES] + ["spheres", "wall (s)"])
    for r in runs:
        md.append(mdtable.row([r["seed"]] + [f(r[k], scale, fmt) for k, _, scale, fmt in QUANTITIES]
                              + [r["spheres"], f"{total_wall(r):.1f}"]))
    if problems:
        md += ["", "**Problems** (the table above is not a valid ensemble):", ""] + [f"- {p}" for p in problems]
    atomic.write_text(os.path.join(a.out, "ensemble.md"), "\n".join(md) + "\n")
    print("\n".join(md))
    for p in problems:
        print(f"error: {p}", file=sys.stderr)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
