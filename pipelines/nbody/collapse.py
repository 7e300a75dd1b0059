#!/usr/bin/env python3
"""nbody-collapse: N spheres (default 1e5) at rest in a random cloud (3.75 % volume fraction, twice
the radius of a 30 % packing), gravel contacts, tree gravity every 20 steps, collapsing into one
region. The run is checked, not only its exit code:

  1. ssdem-grav exits 0 (3 = runaway overlap / NaN, saved as failed_state.h5: a failure);
  2. energy is never created: over the series rows (every 200 steps),
     max_i (E_i - min_{j<=i} E_j) / |W0| <= ENERGY_RISE_MAX (the dashpots only remove energy; a
     rise is integrator or tree error); the total change (E_end - E0)/|W0| is reported;
  3. the half-mass radius about the centre of mass (snapshots every 0.1 t_ff) follows the
     homologous cold collapse of a uniform sphere, r/r0 = cos^2(b) with
     b + sin(b) cos(b) = (pi/2) t/t_ff, to RHALF_TOL while t <= 0.6 t_ff (measured at N = 2000:
     5e-3 at 0.3 t_ff, 1.3e-2 at 0.5, 1.8e-2 at 0.6: the discrete cloud falls in slightly faster),
     and, when the run reaches t_ff, ends below RHALF_END_MAX of its initial value (a compact
     pile: ~0.4 for a 60 % packing; the 500-sphere stability test reaches it at 1.4 t_ff);
  4. the overlap stays below MAX_OVERLAP of the radius (k_n is set for 3 %).
Measured (N = 2000, 0.3 t_ff, 1 thread, 4.7 s): energy rise 1.3e-8 |W0|, E change -3.6e-4 |W0|,
max overlap 1.1e-3 s, r_half 0.9385 (cold collapse 0.9433), all checks pass. N = 1e5, 1.3 t_ff
(100 000 steps, 2 threads, 5560 s): exit 0, energy never rose, E change -1.39 |W0| (dissipated),
max overlap 5.5e-2 s (at 0.84 t_ff, the bounce), r_half within 6.6e-3 of the cold collapse up to
0.6 t_ff, r_half(end)/r_half(0) = 0.419: all checks pass.

Writes collapse.md (checks, half-mass radius, time table), collapse.csv (measured numbers with
their limits), collapse_rhalf.csv, collapse.png; exits 1 if a check fails. At N = 1e5 each of the
~13 snapshots is ~10 MB.

Usage: collapse.py <ssdem-grav> <outdir> [N] [t_end/t_ff]   (defaults 100000 and 1.3)
Smoke test: collapse.py build/nbody/ssdem-grav /tmp/collapse-smoke 2000 0.3   (4 s on 1 thread;
0.6 t_ff: 8 s)
Threads: OMP_NUM_THREADS (default 2).
"""
import csv
import glob
import os
import subprocess
import sys
import time

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

sys.path.insert(0, os.path.dirname(__file__))
from common_runs import series  # noqa: E402
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, "lib"))
from h5io import read_group  # noqa: E402

ENERGY_RISE_MAX = 1e-3   # |W0|
RHALF_TOL = 0.05         # |r/r0 - cos^2 b| while t <= 0.6 t_ff
RHALF_END_MAX = 0.6      # r_half(end) / r_half(0) once t_end >= t_ff
MAX_OVERLAP = 0.10       # of the radius
CHECK_UNTIL = 0.61       # t/t_ff up to which r_half follows the cold collapse (snapshots at 0.1 steps)

EXE, OUT = sys.argv[1], sys.argv[2]
N = int(sys.argv[3]) if len(sys.argv) > 3 else 100000
T_END = float(sys.argv[4]) if len(sys.argv) > 4 else 1.3  # in units of t_ff
s, rho = 1.0, 2000.0
Rc = 2.0 * s * (N / 0.3) ** (1 / 3)  # cloud filling 30 % -> ~2x the packed radius
G = 6.674e-11
M = N * rho * 4 / 3 * np.pi * s**3
tff = np.sqrt(3 * np.pi / (32 * G * M / (4 / 3 * np.pi * Rc**3)))
times = [round(0.1 * k, 10) for k in range(1, int(T_END / 0.1 + 1e-9) + 1)]
os.makedirs(OUT, exist_ok=True)
scene = os.path.join(OUT, "collapse.toml")
with open(scene, "w") as f:
    f.write(f"""
[time]
end = {T_END * tff:.9g}
steps_per_contact = 20
[initial]
source = "random_pile"
count = {N}
body_radius = {Rc:.9g}
sphere_radius = {s}
density = {rho}
[gravity]
every = 20
[contact]
preset = "gravel"
overlap_fraction = 0.03
[output]
series_every = 200
times = [{", ".join(f"{t * tff:.9g}" for t in times)}]
checkpoint_wall = 900.0
progress_interval = 30.0
""")
threads = int(os.environ.get("OMP_NUM_THREADS", "2"))
run_dir = os.path.join(OUT, "run")
t0 = time.perf_counter()
rc = subprocess.run([EXE, "--quiet", "--scene", scene, "--set", f'output.directory="{run_dir}"'],
                    env=dict(os.environ, OMP_NUM_THREADS=str(threads))).returncode
wall = time.perf_counter() - t0


def cold_collapse_radius(t):
    """r/r0 of a uniform cold sphere at t/t_ff (cycloid), for t < t_ff."""
    lo, hi = 0.0, np.pi / 2
    for _ in range(60):
        b = 0.5 * (lo + hi)
        lo, hi = (b, hi) if b + np.sin(b) * np.cos(b) < 0.5 * np.pi * t else (lo, b)
    return np.cos(0.5 * (lo + hi)) ** 2


def half_mass_radius(path):
    t, g = read_group(path, "spheres", ("position", "mass"))
    x, m, t = g["position"], g["mass"], float(t)
    com = (m[:, None] * x).sum(axis=0) / m.sum()
    r = np.linalg.norm(x - com, axis=1)
    order = np.argsort(r)
    cm = np.cumsum(m[order])
    return t, r[order][np.searchsorted(cm, 0.5 * cm[-1])]


checks = []  # (csv key, description, measured, limit, ok)
checks.append(("exit_code", "ssdem-grav exit code", rc, 0, rc == 0))
d = series(run_dir) if os.path.exists(os.path.join(run_dir, "series.csv")) else None
rows = []
if d is not None:
    W0 = abs(d["potential_self_J"][0])
    E = d["total_J"]
    rise = float(np.max(E - np.minimum.accumulate(E)) / W0)
    checks.append(("energy_rise_over_W0", "max energy rise / |W0|", rise, ENERGY_RISE_MAX,
                   rise <= ENERGY_RISE_MAX))
    dE = float((E[-1] - E[0]) / W0)
    checks.append(("energy_change_over_W0", "(E_end - E0) / |W0| (dissipated: <= rise limit)", dE,
                   ENERGY_RISE_MAX, dE <= ENERGY_RISE_MAX))
    max_ov = float(np.max(d["max_overlap_frac"]))
    checks.append(("max_overlap_over_s", "max overlap / radius", max_ov, MAX_OVERLAP, max_ov <= MAX_OVERLAP))
    rh = sorted(half_mass_radius(p) for p in glob.glob(os.path.join(run_dir, "snap_*.h5")))
    r0 = rh[0][1]
    worst = 0.0
    for t, r in rh:
        exp = cold_collapse_radius(t / tff) if t / tff < 1 else float("nan")
        rows.append((t / tff, r / r0, exp))
        if t / tff <= CHECK_UNTIL:  # the snapshot is at the first block boundary after 0.6 t_ff
            worst = max(worst, abs(r / r0 - exp))
    checks.append(("rhalf_vs_cold_collapse", "max |r_half/r0 - cos^2 b| for t <= 0.6 t_ff", worst, RHALF_TOL,
                   worst <= RHALF_TOL))
    end_ratio = rh[-1][1] / r0
    if rh[-1][0] >= tff * (1 - 1e-6):
        checks.append(("rhalf_end_over_rhalf0", "r_half(end) / r_half(0)", end_ratio, RHALF_END_MAX,
                       end_ratio <= RHALF_END_MAX))
    else:
        checks.append(("rhalf_end_over_rhalf0", "r_half(end) / r_half(0) (run ends before t_ff: must shrink)",
                       end_ratio, 1.0, end_ratio < 1.0))
else:
    checks.append(("series_written", "series.csv written", 0, 1, False))

ok = all(c[4] for c in checks)
with open(os.path.join(OUT, "collapse.csv"), "w") as f:
    w = csv.writer(f)
    w.writerow(["quantity", "value", "limit", "pass"])
    for k, v in [("N", N), ("t_ff_s", f"{tff:.6g}"), ("t_end_over_tff", T_END), ("wall_s", f"{wall:.1f}"),
                 ("threads", threads)]:
        w.writerow([k, v, "", ""])
    for key, _, val, lim, good in checks:
        w.writerow([key, f"{val:.4g}", lim, good])
    w.writerow(["all_checks", "", "", ok])
with open(os.path.join(OUT, "collapse_rhalf.csv"), "w") as f:
    f.write("t_over_tff,rhalf_over_r0,cold_collapse_cos2b\n")
    for r in rows:
        f.write(f"{r[0]:.4f},{r[1]:.5f},{r[2]:.5f}\n")
with open(os.path.join(OUT, "collapse.md"), "w") as f:
    f.write(f"N = {N}, t_ff = {tff:.1f} s, t_end = {T_END} t_ff, wall = {wall:.1f} s ({threads} threads), "
            f"exit code {rc}: **{'all checks pass' if ok else 'CHECK FAILED'}**\n\n")
    f.write("| check | measured | limit | |\n|---|---|---|---|\n")
    for _, name, val, lim, good in checks:
        f.write(f"| {name.replace('|', chr(92) + '|')} | {val:.3g} | {lim:.3g} | {'ok' if good else 'FAIL'} |\n")
    if rows:
        f.write("\n| t/t_ff | r_half/r_half(0) | cold collapse cos^2 b |\n|---|---|---|\n")
        for r in rows:
            f.write(f"| {r[0]:.2f} | {r[1]:.4f} | {'' if not np.isfinite(r[2]) else f'{r[2]:.4f}'} |\n")
    if d is not None:
        f.write("\n| t/t_ff | K/\\|W0\\| | W/\\|W0\\| | E/\\|W0\\| | contacts/sphere | max overlap/s |\n"
                "|---|---|---|---|---|---|\n")
        for i in range(0, len(d["time_s"]), max(1, len(d["time_s"]) // 20)):
            f.write(f"| {d['time_s'][i]/tff:.2f} | {d['kinetic_J'][i]/W0:.3e} | {d['potential_self_J'][i]/W0:.4f} | "
                    f"{d['total_J'][i]/W0:.4f} | {2*d['contacts'][i]/N:.2f} | {d['max_overlap_frac'][i]:.3e} |\n")
if d is not None:
    fig, ax = plt.subplots(1, 3, figsize=(14, 4))
    t = d["time_s"] / tff
    for k in ["kinetic_J", "potential_self_J", "elastic_J", "total_J"]:
        ax[0].plot(t, d[k] / W0, label=k)
    ax[0].set_xlabel("t / t_ff"); ax[0].set_ylabel("energy / |W0|"); ax[0].legend()
    ax[1].plot(t, 2 * d["contacts"] / N, label="contacts/sphere")
    ax[1].plot(t, 100 * d["max_overlap_frac"], label="max overlap [% radius]")
    ax[1].set_xlabel("t / t_ff"); ax[1].legend()
    if rows:
        tc = np.linspace(0, min(T_END, 0.999), 200)
        ax[2].plot(tc, [cold_collapse_radius(x) for x in tc], "k-", lw=0.8, label="uniform cold collapse")
        ax[2].plot([r[0] for r in rows], [r[1] for r in rows], "o", label="r_half / r_half(0)")
        ax[2].set_xlabel("t / t_ff"); ax[2].legend()
    fig.tight_layout()
    fig.savefig(os.path.join(OUT, "collapse.png"), dpi=120)
print(open(os.path.join(OUT, "collapse.md")).read())
sys.exit(0 if ok else 1)
