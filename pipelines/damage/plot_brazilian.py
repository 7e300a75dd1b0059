#!/usr/bin/env python3
"""Brazilian-disk strength vs strain rate + damage field at failure (pipeline damage-brazilian).

usage: plot_brazilian.py <outdir> [cell_m] [courant]
Reads <outdir>/summary.csv, history_*.csv, damage_*.csv; writes brazilian.md, brazilian.png,
damage_field.png (highest- and lowest-rate runs at the given cell size).
Experimental band: the Ramesh/Stickle/Kimberley basalt Brazilian data were not available
(validation-data.md section 1.4); the band drawn is the Grady-Kipp model band [C] of
validation-data.md section 1.3 (Nakamura+07 m=16 to BA99 m=9), ~15-35 MPa at 20-200 1/s.
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

out = sys.argv[1]
cell = float(sys.argv[2]) if len(sys.argv) > 2 else None
cfl = float(sys.argv[3]) if len(sys.argv) > 3 else 0.3
rows = [r for r in csv.DictReader(open(f"{out}/summary.csv"))]
if cell is not None:
    rows = [r for r in rows if abs(float(r["cell_m"]) - cell) < 1e-9 and abs(float(r["courant"]) - cfl) < 1e-9]
rows.sort(key=lambda r: float(r["nominal_rate"]))


def centre_stress(r):
    """Largest mean sigma_xx within 0.5 mm of the centre over the run (NaN if not recorded)."""
    tag = f"{float(r['nominal_rate']):g}_h{float(r['cell_m']):g}_c{float(r['courant']):g}_s{int(float(r.get('seed', 1)))}"
    try:
        h = np.genfromtxt(f"{out}/history_{tag}.csv", delimiter=",", names=True)
        if "sxx_center_Pa" not in h.dtype.names:
            return float("nan")
        return float(np.max(h["sxx_center_Pa"]))
    except OSError:
        return float("nan")


gk_rate = np.array([1, 10, 20, 50, 100, 200, 1e3])
gk_lo = np.array([10.8, 15.5, 17.3, 20.0, 22.3, 24.9, 32.1])
gk_hi = np.array([9.1, 16.1, 19.2, 24.1, 28.7, 34.1, 51.0])
lines = ["# Dynamic Brazilian disk, El Mir (2019) basalt, Tonge-Ramesh in mpm-frag", "",
         "sigma_t = 2 F_peak/(pi D t), D = 10 mm, t = 2 mm; effective rate = (d sigma_t/dt)/E (20-80 % rise).",
         "Band: Grady-Kipp model band [C] (validation-data.md 1.3), not measured data.", "",
         "Centre sigma_xx = largest mean sigma_xx within 0.5 mm of the centre during the run (the local tensile",
         "strength at the centre; the flat sticking platens spread the load over an arc of several cells, so the",
         "centre stress is ~0.5-0.6 x 2F/(pi D t) even in an elastic disk; n/a = not recorded).", "",
         "| cell (mm) | Courant | nominal 2v/D (1/s) | effective rate (1/s) | F_peak (kN) | sigma_t (MPa) | centre sigma_xx (MPa) | band at rate (MPa) | steps | particles | wall (s) |",
         "|---|---|---|---|---|---|---|---|---|---|---|"]
for r in rows:
    er = float(r["effective_rate"])
    lo = np.interp(np.log10(er), np.log10(gk_rate), gk_lo)
    hi = np.interp(np.log10(er), np.log10(gk_rate), gk_hi)
    lines.append(f"| {float(r['cell_m'])*1e3:.2g} | {float(r['courant']):.2g} | {float(r['nominal_rate']):.0f} | {er:.1f} | "
                 f"{float(r['peak_F_N'])/1e3:.3f} | {float(r['sigma_t_Pa'])/1e6:.1f} | "
                 f"{(f'{centre_stress(r)/1e6:.1f}' if np.isfinite(centre_stress(r)) else 'n/a')} | {min(lo,hi):.1f}-{max(lo,hi):.1f} | "
                 f"{r['steps']} | {r['particles']} | {float(r['wall_s']):.0f} |")
open(f"{out}/brazilian.md", "w").write("\n".join(lines) + "\n")
print("\n".join(lines))

fig, ax = plt.subplots(figsize=(6.2, 4.4))
ax.fill_between(gk_rate, np.minimum(gk_lo, gk_hi), np.maximum(gk_lo, gk_hi), color="gray", alpha=0.35,
                label="Grady-Kipp band [C] (validation-data 1.3)")
ax.axvspan(20, 200, color="tab:green", alpha=0.08, label="target rates 20-200 1/s")
if rows:
    ax.plot([float(r["effective_rate"]) for r in rows], [float(r["sigma_t_Pa"]) / 1e6 for r in rows], "o-",
            color="tab:blue", label=f"TR model, mpm-frag, h = {float(rows[0]['cell_m'])*1e3:.2g} mm")
ax.set_xscale("log")
ax.set_xlabel("effective strain rate (d sigma_t/dt)/E (1/s)")
ax.set_ylabel("Brazilian tensile strength 2F/(pi D t) (MPa)")
ax.set_xlim(5, 1000)
ax.set_ylim(0, 80)
ax.grid(True, which="both", alpha=0.3)
ax.legend(fontsize=7)
ax.set_title("Dynamic Brazilian disk, basalt (El Mir 2019 parameters)")
fig.tight_layout()
fig.savefig(f"{out}/brazilian.png", dpi=150)

if rows:
    sel = [rows[0], rows[-1]] if len(rows) > 1 else rows
    fig, axs = plt.subplots(1, len(sel), figsize=(5.2 * len(sel), 4.8), constrained_layout=True)
    axs = np.atleast_1d(axs)
    for a, r in zip(axs, sel):
        tag = f"{float(r['nominal_rate']):g}_h{float(r['cell_m']):g}_c{float(r['courant']):g}_s{int(float(r.get('seed', 1)))}"
        d = np.loadtxt(f"{out}/damage_{tag}.csv", delimiter=",", skiprows=1)
        z = d[:, 2]
        m = z < float(r["cell_m"])  # first layer above the mid-plane (z ~ h/2)
        sc = a.scatter(d[m, 0] * 1e3, d[m, 1] * 1e3, c=d[m, 3], s=4, cmap="inferno", vmin=0, vmax=0.2)
        a.set_aspect("equal")
        a.set_title(f"damage at failure, eff. rate {float(r['effective_rate']):.0f} 1/s")
        a.set_xlabel("x (mm)")
        a.set_ylabel("y (mm), load axis")
    fig.colorbar(sc, ax=axs.tolist(), label="damage D")
    fig.savefig(f"{out}/damage_field.png", dpi=150)
