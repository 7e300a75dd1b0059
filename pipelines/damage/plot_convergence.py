#!/usr/bin/env python3
"""Brazilian strength vs resolution / time-step factor against wall time (damage-brazilian-convergence).
usage: plot_convergence.py <outdir>; writes convergence.md and convergence.png."""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

out = sys.argv[1]
rows = list(csv.DictReader(open(f"{out}/summary.csv")))
ref = min(rows, key=lambda r: (float(r["cell_m"]), float(r["courant"])))
s_ref = float(ref["sigma_t_Pa"])
lines = ["# Brazilian disk: strength vs resolution and Courant number (nominal 2v/D = %s 1/s)" % ref["nominal_rate"], "",
         f"Reference = finest run (h = {float(ref['cell_m'])*1e3:g} mm, C = {ref['courant']}).", "",
         "| cell (mm) | Courant | particles | steps | wall (s) | effective rate (1/s) | sigma_t (MPa) | diff to finest |",
         "|---|---|---|---|---|---|---|---|"]
for r in rows:
    s = float(r["sigma_t_Pa"])
    lines.append(f"| {float(r['cell_m'])*1e3:g} | {r['courant']} | {r['particles']} | {r['steps']} | {float(r['wall_s']):.0f} | "
                 f"{float(r['effective_rate']):.0f} | {s/1e6:.1f} | {100*(s-s_ref)/s_ref:+.1f} % |")
open(f"{out}/convergence.md", "w").write("\n".join(lines) + "\n")
print("\n".join(lines))
fig, ax = plt.subplots(figsize=(5.6, 4))
for r in rows:
    ax.plot(float(r["wall_s"]), float(r["sigma_t_Pa"]) / 1e6, "o", color="tab:blue" if r["courant"] == "0.3" else "tab:orange")
    ax.annotate(f"h={float(r['cell_m'])*1e3:g} mm, C={r['courant']}", (float(r["wall_s"]), float(r["sigma_t_Pa"]) / 1e6), fontsize=7)
ax.set_xscale("log")
ax.set_xlabel("wall time (s, 2 threads)")
ax.set_ylabel("Brazilian strength (MPa)")
ax.grid(True, alpha=0.3)
fig.tight_layout()
fig.savefig(f"{out}/convergence.png", dpi=150)
