#!/usr/bin/env python3
"""Plot single-element Tonge-Ramesh strength vs strain rate (output of damage_rate_curve).

Writes <out>/rate_curve.md (median and range over flaw realisations) and <out>/rate_curve.png.
The Grady-Kipp tensile band of validation-data.md section 1.3 ([C], BA99 and Nakamura+07 Weibull
sets) is drawn for orientation only: it is a 1-D model band, not data.
"""
import csv
import sys
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

src, out = sys.argv[1], sys.argv[2]
rows = list(csv.DictReader(open(src)))
data = defaultdict(lambda: defaultdict(list))
for r in rows:
    data[r["mode"]][float(r["rate_per_s"])].append(float(r["peak_stress_Pa"]) / 1e6)

lines = ["# Single-element strength vs strain rate (El Mir 2019 basalt, 1 mm^3 point)", "",
         "| mode | rate (1/s) | median peak (MPa) | min | max | n |", "|---|---|---|---|---|---|"]
fig, ax = plt.subplots(figsize=(6.4, 4.6))
colors = {"tension": "tab:blue", "compression": "tab:red"}
for mode in ("tension", "compression"):
    rates = sorted(data[mode])
    med = [np.median(data[mode][r]) for r in rates]
    lo = [min(data[mode][r]) for r in rates]
    hi = [max(data[mode][r]) for r in rates]
    for r, m, a, b in zip(rates, med, lo, hi):
        lines.append(f"| {mode} | {r:.3g} | {m:.1f} | {a:.1f} | {b:.1f} | {len(data[mode][r])} |")
    ax.fill_between(rates, lo, hi, color=colors[mode], alpha=0.2)
    ax.plot(rates, med, "o-", color=colors[mode], label=f"TR model, {mode} (median, range of 5 flaw sets)")
# Grady-Kipp tensile band [C] from validation-data.md section 1.3
gk_rate = [1, 10, 20, 50, 100, 200, 1e3, 1e4, 1e5]
gk_n07 = [10.8, 15.5, 17.3, 20.0, 22.3, 24.9, 32.1, 46.1, 66.4]
gk_ba99 = [9.1, 16.1, 19.2, 24.1, 28.7, 34.1, 51.0, 90.7, 161]
ax.fill_between(gk_rate, gk_n07, gk_ba99, color="gray", alpha=0.3,
                label="Grady-Kipp tensile band [C] (validation-data 1.3)")
ax.axhline(147, color="k", ls=":", lw=1)
ax.text(12, 155, "gabbro spall 147 MPa @1e4-1e5/s [V]", fontsize=7)
ax.set_xscale("log")
ax.set_yscale("log")
ax.set_xlabel("strain rate (1/s)")
ax.set_ylabel("peak uniaxial stress (MPa)")
ax.set_title("Tonge-Ramesh basalt, one material point, uniaxial stress")
ax.grid(True, which="both", alpha=0.3)
ax.legend(fontsize=7, loc="upper left")
fig.tight_layout()
fig.savefig(f"{out}/rate_curve.png", dpi=150)
open(f"{out}/rate_curve.md", "w").write("\n".join(lines) + "\n")
print("\n".join(lines))
