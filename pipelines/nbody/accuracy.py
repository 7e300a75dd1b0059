#!/usr/bin/env python3
"""nbody-accuracy: error against wall time for a self-gravitating rubble pile and a two-body
reaccumulation, across dt (steps per contact), opening angle theta and the gravity update
interval k (RESPA outer step k*dt; k = 0: the error-controlled cadence, gravity.tolerance and
gravity.max_every), single-rate and multi-rate steps (time.multirate, with the pipeline's
median anchor). Reference: 60 steps per contact, theta = 0.2, k = 1, single rate.

Errors: |E_end - E_ref,end| / |W_0| (energy, incl. elastic and dissipation history) and the rms
final-position difference / sphere radius. Granular flows are chaotic, so position differences
of unrelated perturbations grow; compare variants against each other at equal simulated time.

Usage: accuracy.py <ssdem-grav> <outdir>
"""
import os
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

sys.path.insert(0, os.path.dirname(__file__))
from common_runs import last_snapshot, run, series  # noqa: E402

EXE, OUT = sys.argv[1], sys.argv[2]
SCENES = {
    "rubble_pile": ("""
[time]
end = 300.0
[initial]
source = "lattice_pile"
body_radius = 8.0
sphere_radius = 1.0
density = 2000.0
jitter = 0.05
[contact]
preset = "gravel"
[output]
series_every = 50
checkpoint_wall = 0.0
progress_interval = 1000.0
""", []),
    "two_body": ("""
[time]
end = 600.0
[initial]
source = "two_bodies"
body_radius = 6.0
body2_radius = 4.0
sphere_radius = 1.0
density = 2000.0
jitter = 0.05
body2_offset = [12.0, 1.5, 0.0]
body2_velocity = [-0.015, 0.0, 0.0]
[contact]
preset = "gravel"
vmax = 0.05
[output]
series_every = 50
checkpoint_wall = 0.0
progress_interval = 1000.0
""", []),
}
REF = {"spc": 60, "theta": 0.2, "every": 1}
VARIANTS = [dict(spc=s, theta=0.3, every=1) for s in (20, 30, 45)]
VARIANTS += [dict(spc=30, theta=t, every=1) for t in (0.5, 0.7)]
VARIANTS += [dict(spc=30, theta=0.3, every=k) for k in (10, 50, 200)]
VARIANTS += [dict(spc=30, theta=0.5, every=50)]
# The error-controlled gravity cadence (the default, gravity.every = 0) at two tolerances and with
# the reaccumulation pipeline's longest block, single rate; then multi-rate steps with it, the
# last at the pipeline's settings (20 steps per contact, blocks up to 4096 steps, default theta).
VARIANTS += [dict(spc=30, theta=0.3, every=0, tol=t) for t in (1e-3, 1e-4)]
VARIANTS += [dict(spc=30, theta=0.3, every=0, tol=1e-3, max_every=4096)]
VARIANTS += [dict(spc=30, theta=0.3, every=0, tol=1e-3, mr=True)]
VARIANTS += [dict(spc=20, theta=0.25, every=0, tol=1e-3, max_every=4096, mr=True)]
# Chaos floor: the reference settings with a round-off-level change (tree leaf size 8 instead of
# 16 changes only the summation order of the gravity sums). Errors at this level are not
# systematic but the chaotic divergence of granular dynamics.
VARIANTS += [dict(spc=60, theta=0.2, every=1, bucket=8)]


def sets(v):
    out = [f"time.steps_per_contact={v['spc']}", f"gravity.theta={v['theta']}",
           f"gravity.every={v['every']}", f"gravity.bucket={v.get('bucket', 16)}"]
    if v["every"] == 0:
        out += [f"gravity.tolerance={v['tol']}", f"gravity.max_every={v.get('max_every', 64)}"]
    if v.get("mr"):
        out += ["time.multirate=true", 'time.level_anchor="median"']
    return out


def cadence(v):
    """The gravity column: k, or auto(tolerance, longest block)."""
    return str(v["every"]) if v["every"] else f"auto({v['tol']:g}, {v.get('max_every', 64)})"


def tag(v):
    t = f"spc{v['spc']}_th{v['theta']}_k{v['every']}_b{v.get('bucket', 16)}"
    if v["every"] == 0:
        t += f"_tol{v['tol']:g}_max{v.get('max_every', 64)}"
    return t + ("_mr" if v.get("mr") else "")


rows = []
os.makedirs(OUT, exist_ok=True)
for name, (text, extra) in SCENES.items():
    scene = os.path.join(OUT, f"{name}.toml")
    with open(scene, "w") as f:
        f.write(text)
    ref_dir = os.path.join(OUT, name, "ref")
    wall_ref = run(EXE, scene, ref_dir, sets(REF) + extra)
    sref = series(ref_dir)
    ids_r, x_r, rad, t_r = last_snapshot(ref_dir)
    W0 = abs(sref["potential_self_J"][0])
    for v in VARIANTS:
        d = os.path.join(OUT, name, tag(v))
        wall = run(EXE, scene, d, sets(v) + extra)
        s = series(d)
        ids, x, _, t = last_snapshot(d)
        assert np.array_equal(ids, ids_r)
        dE = abs(s["total_J"][-1] - sref["total_J"][-1]) / W0
        drift = abs(s["total_J"][-1] - s["total_J"][0]) / W0
        dx = np.sqrt(np.mean(np.sum((x - x_r) ** 2, axis=1))) / np.mean(rad)
        rows.append(dict(scene=name, bucket=v.get("bucket", 16), **{k: v[k] for k in ("spc", "theta", "every")},
                         gravity=cadence(v), multirate=bool(v.get("mr")), wall_s=wall, dE_vs_ref=dE,
                         dx_rms_over_r=dx, E_change_over_W0=drift, t_end=t, t_ref=t_r, wall_ref_s=wall_ref))
        print(rows[-1], flush=True)

keys = ["scene", "spc", "theta", "every", "gravity", "multirate", "bucket", "wall_s", "wall_ref_s", "dE_vs_ref",
        "dx_rms_over_r", "E_change_over_W0", "t_end"]
with open(os.path.join(OUT, "accuracy.csv"), "w") as f:
    f.write(",".join(keys) + "\n")
    for r in rows:
        f.write(",".join(f'"{r[k]}"' if k == "gravity" else str(r[k]) for k in keys) + "\n")
with open(os.path.join(OUT, "accuracy.md"), "w") as f:
    f.write("| scene | steps/contact | theta | gravity every | steps | leaf | wall s | t_end s | \\|E-E_ref\\|/\\|W0\\| "
            "| \\|E_end-E_0\\|/\\|W0\\| | rms dx / r |\n")
    f.write("|---|---|---|---|---|---|---|---|---|---|---|\n")
    for r in rows:
        f.write(f"| {r['scene']} | {r['spc']} | {r['theta']} | {r['gravity']} | "
                f"{'multi-rate' if r['multirate'] else 'single'} | {r['bucket']} | {r['wall_s']:.2f} | "
                f"{r['t_end']:.1f} | {r['dE_vs_ref']:.2e} | {r['E_change_over_W0']:.2e} | {r['dx_rms_over_r']:.2e} |\n")
    f.write("\nReference: 60 steps/contact, theta 0.2, gravity every step, leaf 16 "
            f"(rubble pile {rows[0]['wall_ref_s']:.1f} s wall). The leaf-8 row is the chaos floor "
            "(same physics, round-off-level change). auto(tol, max) is the error-controlled gravity cadence "
            "(gravity.every = 0, gravity.tolerance, gravity.max_every); multi-rate rows use time.multirate with "
            "the median anchor. |E_end-E_0|/|W0| is the run's own energy change "
            "(dissipation plus drift; E_change_over_W0 in the CSV). Runs end at the first gravity-block boundary "
            "after t_end, so large k ends slightly later.\n")

fig, axes = plt.subplots(1, 2, figsize=(11, 4.5))
for ax, key, lab in [(axes[0], "dE_vs_ref", "|E - E_ref| / |W0| at t_end"),
                     (axes[1], "dx_rms_over_r", "rms |x - x_ref| / radius at t_end")]:
    for name, mk in [("rubble_pile", "o"), ("two_body", "s")]:
        for r in rows:
            if r["scene"] != name:
                continue
            col = ("C2" if r["bucket"] != 16 else "C4" if r["multirate"] else "C3" if r["every"] == 0
                   else "C0" if r["every"] == 1 else "C1")
            ax.loglog(r["wall_s"], max(r[key], 1e-16), mk, color=col)
            ax.annotate(f"{r['spc']}/{r['theta']}/{r['gravity']}", (r["wall_s"], max(r[key], 1e-16)),
                        fontsize=6)
    ax.set_xlabel("wall time [s] (1 thread)")
    ax.set_ylabel(lab)
    ax.grid(True, which="both", alpha=0.3)
axes[0].set_title("o pile, s two-body; blue k=1, orange k>1, red auto cadence, purple multi-rate, "
                  "green chaos floor", fontsize=8)
fig.tight_layout()
fig.savefig(os.path.join(OUT, "accuracy.png"), dpi=120)
print("wrote", os.path.join(OUT, "accuracy.csv"), os.path.join(OUT, "accuracy.png"))
