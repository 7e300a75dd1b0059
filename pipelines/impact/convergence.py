#!/usr/bin/python3
"""Resolution study of the whole impact chain (target impact-convergence).

    /usr/bin/python3 convergence.py RUN_DIR [RUN_DIR ...] --out DIR

Each RUN_DIR is one run of the impact pipeline at a different MPM cell size h (same physics, same
sphere size). For M_LR/M_PB, beta and the hand-off kinetic-energy loss it tabulates the value
against h and the total wall time of the four stages, and estimates the converged value from the
three finest runs by Richardson extrapolation with an observed order p:

    f(h) = f_0 + C h^p  through (h1, f1), (h2, f2), (h3, f3),  h1 < h2 < h3,
    (f3 - f2) / (f2 - f1) = (h3^p - h2^p) / (h2^p - h1^p)   solved for p > 0,
    f_0 = f1 - C h1^p,  C = (f2 - f1) / (h2^p - h1^p).

When the differences change sign (non-monotone convergence), no p in (0.05, 8) fits, or the p that
fits is outside P_CREDIBLE = [0.5, 4], or the extrapolated value lies outside the quantity's physical
range (PHYSICAL: a mass ratio or a loss fraction in [0, 1], a heat >= 0), there is no asymptotic range:
the table then reports the finest value with the spread of the three finest as its uncertainty, and
says so.

With --ensemble EDIR (ensemble.py's output for several flaw seeds at one of the cells; may be given
once per cell) the seed scatter enters the uncertainty of the estimate: u = sqrt(d^2 + s^2),
d = |finest - f_0| (the discretisation part, or the spread of the three finest where there is no
fit) and s the seeds' sample standard deviation (the largest over the ensembles given). The table also carries the MPM particles, the MPM energy change and the
transfer heat (the numerical heat of the grid-particle transfer, `transfer_heat_J` at the end of
the MPM over the initial energy), and the paper's values (El Mir et al. 2019: 0.85, 1.69).
Writes DIR/convergence.{csv,md,png}.
"""
import csv
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from run_summary import read_run, run_dirs_args, total_wall  # noqa: E402
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, "lib"))
import atomic  # noqa: E402

QUANTITIES = (("M_LR_over_M_PB", "M_LR/M_PB"), ("beta", "beta"), ("ke_loss", "hand-off KE loss"),
              ("mpm_energy_change", "MPM energy change"), ("transfer_heat_frac", "transfer heat / E0"))
# An observed order outside this range (the schemes are first to second order) means the three
# finest runs are not in the asymptotic range; an extrapolation with p -> 0 runs off to anything.
P_CREDIBLE = (0.5, 4.0)
PAPER = {"M_LR_over_M_PB": 0.85, "beta": 1.69}  # El Mir, Ramesh & Richardson (2019), 200 m cells, 4.5 h
# The range each quantity can physically take: an extrapolated value outside it (e.g. a negative
# transfer heat from an order p ~ 1 fit) is not an asymptotic estimate either.
PHYSICAL = {"M_LR_over_M_PB": (0.0, 1.0), "ke_loss": (0.0, 1.0), "transfer_heat_frac": (0.0, math.inf)}


def read_ensemble(edir):
    """{quantity: row of ensemble.csv (n, mean, std, ...)} and the cell of its runs, or ({}, None)."""
    if not edir:
        return {}, None
    with open(os.path.join(edir, "ensemble.csv")) as f:
        table = {r["quantity"]: r for r in csv.DictReader(f)}
    cell = None
    try:
        with open(os.path.join(edir, "ensemble_runs.csv")) as f:
            cell = float(next(csv.DictReader(f))["cell_m"])
    except (OSError, StopIteration, ValueError, KeyError):
        pass
    return table, cell


def richardson(h, f):
    """(f0, p, note) from the three finest points; f0 None when no asymptotic fit exists."""
    pts = sorted((x, y) for x, y in zip(h, f) if x is not None and y is not None and math.isfinite(y))[:3]
    if len(pts) < 3:
        return None, None, "fewer than three runs"
    (h1, f1), (h2, f2), (h3, f3) = pts
    d21, d32 = f2 - f1, f3 - f2
    if d21 == 0.0 or d32 == 0.0 or (d21 > 0) != (d32 > 0):
        return None, None, "non-monotone: no asymptotic range"
    target = d32 / d21

    def g(p):
        return (h3 ** p - h2 ** p) / (h2 ** p - h1 ** p) - target

    lo, hi = 0.05, 8.0
    if g(lo) * g(hi) > 0:
        return None, None, "no order p in (0.05, 8) fits"
    for _ in range(200):  # bisection: g is monotone in p for h1 < h2 < h3
        mid = 0.5 * (lo + hi)
        if g(lo) * g(mid) <= 0:
            hi = mid
        else:
            lo = mid
    p = 0.5 * (lo + hi)
    if not P_CREDIBLE[0] <= p <= P_CREDIBLE[1]:
        return None, None, f"observed order {p:.2f} outside {P_CREDIBLE}: not in the asymptotic range"
    C = d21 / (h2 ** p - h1 ** p)
    return f1 - C * h1 ** p, p, "Richardson"


def estimate(key, h, f):
    """richardson(h, f), refused where the extrapolated value leaves the quantity's PHYSICAL range."""
    f0, p, note = richardson(h, f)
    lo, hi = PHYSICAL.get(key, (-math.inf, math.inf))
    if f0 is not None and not lo <= f0 <= hi:
        return None, None, f"Richardson value {f0:.3g} outside the physical range [{lo:g}, {hi:g}]: no asymptotic range"
    return f0, p, note


def main(argv=None):
    a = run_dirs_args(__doc__, argv, lambda ap: ap.add_argument(
        "--ensemble", action="append", default=[], help="ensemble.py output directory (flaw seeds at one cell); repeatable"))
    ensembles = sorted((read_ensemble(e) for e in a.ensemble), key=lambda e: -(e[1] or 0))
    # per quantity the ensemble with the largest seed std (conservative)
    ens = {}
    for table, cell in ensembles:
        for k, row in table.items():
            if row.get("std") not in (None, "") and (k not in ens or float(row["std"]) > float(ens[k]["std"])):
                ens[k] = dict(row, cell=cell)
    runs = sorted((read_run(d) for d in a.runs), key=lambda r: -(r["cell_m"] or 0))
    bad = [r for r in runs if r["problems"]]
    for r in bad:
        print(f"warning: {r['run']}: {'; '.join(r['problems'])}", file=sys.stderr)
    h = [r["cell_m"] for r in runs]
    with open(os.path.join(a.out, "convergence.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["cell_m", "run", "particles", "M_LR_over_M_PB", "beta", "ke_loss", "mpm_energy_change",
                    "transfer_heat_frac", "spheres",
                    "wall_fragment_s", "wall_handoff_s", "wall_reaccumulate_s", "wall_analyse_s", "wall_total_s"])
        for r in runs:
            w.writerow([r["cell_m"], r["run"], r["particles"], r["M_LR_over_M_PB"], r["beta"], r["ke_loss"],
                        r["mpm_energy_change"], r["transfer_heat_frac"], r["spheres"],
                        r["wall_s"].get("fragment"), r["wall_s"].get("handoff"), r["wall_s"].get("reaccumulate"),
                        r["wall_s"].get("analyse"), f"{total_wall(r):.1f}"])
    md = ["# Impact chain: outcomes against MPM resolution and wall time", "",
          "Same impact and the same N-body settings in every row; only the MPM cell size changes.", "",
          "| cell (m) | particles | M_LR/M_PB | beta | hand-off KE loss | MPM energy change | transfer heat / E0 | spheres | wall: fragment / hand-off / N-body / analyse (s) | total (s) |",
          "|---|---|---|---|---|---|---|---|---|---|"]

    def num(x, f="{:.4f}"):
        return "n/a" if x is None else f.format(x)

    for r in runs:
        ws = r["wall_s"]
        md.append(f"| {num(r['cell_m'], '{:.0f}')} | {r['particles']} | {num(r['M_LR_over_M_PB'])} | {num(r['beta'], '{:.3f}')} | "
                  f"{num(100 * r['ke_loss'] if r['ke_loss'] is not None else None, '{:.2f} %')} | "
                  f"{num(100 * r['mpm_energy_change'] if r['mpm_energy_change'] is not None else None, '{:+.4f} %')} | "
                  f"{num(r['transfer_heat_frac'], '{:.3f}')} | {r['spheres']} | "
                  + " / ".join(num(ws.get(s), "{:.1f}") for s in ("fragment", "handoff", "reaccumulate", "analyse"))
                  + f" | {total_wall(r):.1f} |")
    md += ["", "| quantity | finest run | extrapolated (h -> 0) | observed order p | finest run's distance to it | "
           "seed std (cell) | estimate ± u | paper | note |",
           "|---|---|---|---|---|---|---|---|---|"]
    summary = {}
    for key, label in QUANTITIES:
        vals = [r[key] for r in runs]
        f0, p, note = estimate(key, h, vals)
        finest = next((v for hh, v in sorted(zip(h, vals)) if v is not None), None)
        three = [v for hh, v in sorted(zip(h, vals)) if v is not None][:3]
        spread = (max(three) - min(three)) if len(three) >= 2 else None
        if f0 is not None and finest is not None:
            dist = f"{abs(finest - f0):.3g} ({100 * abs(finest - f0) / abs(f0):.1f} %)" if f0 != 0 else f"{abs(finest - f0):.3g}"
        else:
            dist = f"spread of the three finest: {spread:.3g}" if spread is not None else "n/a"
        summary[key] = (f0, p, note)
        sd = float(ens[key]["std"]) if key in ens and ens[key].get("std") not in (None, "") else None
        est, d = (f0, abs(finest - f0)) if f0 is not None and finest is not None else (finest, spread)
        u = math.hypot(d, sd or 0.0) if d is not None else sd
        sd_cell = f" ({num(ens[key]['cell'], '{:.0f}')} m)" if key in ens else ""
        md.append(f"| {label} | {num(finest, '{:.4g}')} | {num(f0, '{:.4g}')} | {num(p, '{:.2f}')} | {dist} | "
                  f"{num(sd, '{:.3g}')}{sd_cell} | "
                  f"{num(est, '{:.4g}')} ± {num(u, '{:.2g}')} | {PAPER.get(key, '')} | {note} |")
    md += ["", "The demo (`make -C pipelines demo`) runs at 2000 m cells (DEMO_CELL); its row's distance to the "
           "extrapolated value (or to the finest run where no asymptotic range exists) is how far the demo is "
           "from converged. "
           "u = sqrt(d^2 + seed std^2), d = the finest run's distance to the extrapolated value, or the spread "
           "of the three finest runs where there is no asymptotic fit.", ""]
    th = [(r["cell_m"], r["transfer_heat_frac"]) for r in runs if r["cell_m"] and r["transfer_heat_frac"]]
    if len(th) >= 2 and th[0][0] != th[-1][0]:
        q = math.log(th[0][1] / th[-1][1]) / math.log(th[0][0] / th[-1][0])
        md += [f"Transfer heat against cell size: a power law h^q through the coarsest and finest runs has "
               f"q = {q:.2f} (each halving of h multiplies it by {0.5 ** q:.2f}).", ""]
    for table, cell in ensembles:
        md += [f"Flaw seeds at {num(cell, '{:.0f}')} m (n = {table['beta']['n']}): " + ", ".join(
            f"{lab} {float(table[k]['mean']):.4g} ± {float(table[k]['std']):.2g} (min {float(table[k]['min']):.4g}, "
            f"max {float(table[k]['max']):.4g})" for k, lab in (("M_LR_over_M_PB", "M_LR/M_PB"), ("beta", "beta"))
            if k in table and table[k]["mean"] != "") + ".", ""]
    with open(os.path.join(a.out, "convergence.md"), "w") as f:
        f.write("\n".join(md) + "\n")
    print("\n".join(md))
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("matplotlib missing: no plot", file=sys.stderr)
        return 0
    fig, axs = plt.subplots(1, len(QUANTITIES), figsize=(4.2 * len(QUANTITIES), 4))
    wall = [total_wall(r) for r in runs]
    for ax, (key, label) in zip(axs, QUANTITIES):
        vals = [r[key] for r in runs]
        pts = [(t, v, hh) for t, v, hh in zip(wall, vals, h) if v is not None]
        ax.plot([t for t, _, _ in pts], [v for _, v, _ in pts], "o-")
        for t, v, hh in pts:
            ax.annotate(f"{hh:.0f} m", (t, v), textcoords="offset points", xytext=(4, 4), fontsize=8)
        f0 = summary[key][0]
        if f0 is not None:
            ax.axhline(f0, color="k", ls="--", lw=0.8, label=f"Richardson, p = {summary[key][1]:.2f}")
        if key in PAPER:
            ax.axhline(PAPER[key], color="r", ls=":", lw=0.8, label=f"El Mir et al. 2019: {PAPER[key]}")
        if f0 is not None or key in PAPER:
            ax.legend(fontsize=8)
        ax.set_xscale("log")
        ax.set_xlabel("total wall time of the four stages (s)")
        ax.set_title(label)
        ax.grid(alpha=0.3)
    fig.tight_layout()
    atomic.save_png(fig, os.path.join(a.out, "convergence.png"), dpi=110, close=False)
    return 0


if __name__ == "__main__":
    sys.exit(main())
