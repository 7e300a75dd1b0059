#!/usr/bin/python3
"""Error vs wall time for the mpm-frag convergence study (mpm_convergence CSV).

usage: plot_convergence.py <convergence.csv> <out_dir>
Writes <out_dir>/convergence.md (table with observed orders) and <out_dir>/convergence.png.
Observed order between successive refinements: p = log2(E_2h / E_h).
"""
import csv
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    src, out = sys.argv[1], sys.argv[2]
    os.makedirs(out, exist_ok=True)
    rows = list(csv.DictReader(open(src)))
    groups = {}
    for r in rows:
        groups.setdefault((r["problem"], r["variant"]), []).append(r)
    lines = ["# mpm-frag: error vs resolution and wall time", "",
             "MMS: axis-aligned manufactured solution (Wallstedt & Guilkey 2008), particle L2 displacement error at T = 0.02, "
             "2^3 particles per cell, CFL 0.2. Shock: planar symmetric Tillotson-basalt impact at 2 x 2.5 km/s, "
             "L1 of the cell-binned pressure profile / P_H against the exact Rankine-Hugoniot step at t = 12 us "
             "(error2 = max relative error of the plateau pressure and of the shock speed).", "",
             "| problem | variant | resolution | particles | steps | wall [s] | error | observed order | error2 |",
             "|---|---|---|---|---|---|---|---|---|"]
    fig, axes = plt.subplots(1, 2, figsize=(12, 5))
    for (prob, var), rs in groups.items():
        rs.sort(key=lambda r: int(r["resolution"]))
        errs = [float(r["error"]) for r in rs]
        walls = [max(float(r["wall_s"]), 1e-3) for r in rs]
        orders = [""] + ["%.2f" % math.log2(errs[i - 1] / errs[i]) for i in range(1, len(errs))]
        for r, o in zip(rs, orders):
            lines.append("| %s | %s | %s | %s | %s | %.2f | %.3e | %s | %.3e |" % (
                prob, var, r["resolution"], r["particles"], r["steps"], float(r["wall_s"]), float(r["error"]),
                o or "-", float(r["error2"])))
        ax = axes[0] if prob == "mms" else axes[1]
        label = "%s (last order %s)" % (var, orders[-1] if len(orders) > 1 else "-")
        ax.loglog(walls, errs, "o-", label=label)
        for w, e, r in zip(walls, errs, rs):
            ax.annotate(r["resolution"], (w, e), textcoords="offset points", xytext=(4, 4), fontsize=7)
    axes[0].set_title("MMS (labels: cells per axis)")
    axes[0].set_xlabel("wall time [s] (1 thread)")
    axes[0].set_ylabel("L2 displacement error [m]")
    axes[1].set_title("Tillotson planar shock (labels: cells per plate)")
    axes[1].set_xlabel("wall time [s] (1 thread)")
    axes[1].set_ylabel("L1 binned pressure error / P_H")
    for ax in axes:
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "convergence.png"), dpi=130)
    open(os.path.join(out, "convergence.md"), "w").write("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
