#!/usr/bin/env python3
"""nbody-collapse: 1e5 spheres (cold random cloud, gravel contacts, tree gravity every 20 steps)
collapsing into one region. Records energy components, contacts and max overlap over time; the run
must finish with exit 0 (no runaway overlap, no NaN, tree sane). Table + PNG.
Usage: collapse.py <ssdem-grav> <outdir> [count]
"""
import os
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

sys.path.insert(0, os.path.dirname(__file__))
from common_runs import run, series  # noqa: E402

EXE, OUT = sys.argv[1], sys.argv[2]
N = int(sys.argv[3]) if len(sys.argv) > 3 else 100000
s, rho = 1.0, 2000.0
Rc = 2.0 * s * (N / 0.3) ** (1 / 3)  # cloud filling 30 % -> ~2x the packed radius
G = 6.674e-11
M = N * rho * 4 / 3 * np.pi * s**3
tff = np.sqrt(3 * np.pi / (32 * G * M / (4 / 3 * np.pi * Rc**3)))
os.makedirs(OUT, exist_ok=True)
scene = os.path.join(OUT, "collapse.toml")
with open(scene, "w") as f:
    f.write(f"""
[time]
end = {1.3 * tff:.6g}
steps_per_contact = 20
[initial]
source = "random_pile"
count = {N}
body_radius = {Rc:.6g}
sphere_radius = {s}
density = {rho}
[gravity]
every = 20
[contact]
preset = "gravel"
overlap_fraction = 0.03
[output]
series_every = 200
checkpoint_wall = 900.0
progress_interval = 30.0
""")
threads = int(os.environ.get("OMP_NUM_THREADS", "2"))
wall = run(EXE, scene, os.path.join(OUT, "run"), [], threads=threads)
d = series(os.path.join(OUT, "run"))
W0 = abs(d["potential_self_J"][0])
with open(os.path.join(OUT, "collapse.md"), "w") as f:
    f.write(f"N = {N}, t_ff = {tff:.1f} s, wall = {wall:.0f} s ({threads} threads)\n\n")
    f.write(f"max energy rise over the run: {np.max(np.maximum.accumulate(d['total_J']) - d['total_J'][0]) / W0:.2e} |W0|\n\n")
    f.write("| t/t_ff | K/|W0| | W/|W0| | E/|W0| | contacts/sphere | max overlap/s |\n|---|---|---|---|---|---|\n")
    for i in range(0, len(d["time_s"]), max(1, len(d["time_s"]) // 20)):
        f.write(f"| {d['time_s'][i]/tff:.2f} | {d['kinetic_J'][i]/W0:.3e} | {d['potential_self_J'][i]/W0:.4f} | "
                f"{d['total_J'][i]/W0:.4f} | {2*d['contacts'][i]/N:.2f} | {d['max_overlap_frac'][i]:.3e} |\n")
fig, ax = plt.subplots(1, 2, figsize=(10, 4))
t = d["time_s"] / tff
for k in ["kinetic_J", "potential_self_J", "elastic_J", "total_J"]:
    ax[0].plot(t, d[k] / W0, label=k)
ax[0].set_xlabel("t / t_ff"); ax[0].set_ylabel("energy / |W0|"); ax[0].legend()
ax[1].plot(t, 2 * d["contacts"] / N, label="contacts/sphere")
ax[1].plot(t, 100 * d["max_overlap_frac"], label="max overlap [% radius]")
ax[1].set_xlabel("t / t_ff"); ax[1].legend()
fig.tight_layout()
fig.savefig(os.path.join(OUT, "collapse.png"), dpi=120)
print(open(os.path.join(OUT, "collapse.md")).read())
