#!/usr/bin/env python3
"""First strong-scaling measurement of the MPI ssdem-grav (issue 19).

Scene: nbody/scenes/two_bodies.toml scaled to ~1e5 spheres (bodies of 50 m and 15 m radius, 1 m
spheres, gravity every 10 steps as in the scene). Configurations, run interleaved REPS times:
  1 rank x 2 OpenMP threads (mpirun -np 1: the serial driver, the reference)
  2 ranks x 1 thread        (the domain decomposition)
Reported per configuration (medians): process wall time for STEPS steps (start-up and the final
snapshot + checkpoint included), wall per sphere-step, cost per sphere-step per core (wall x 2 cores
/ (N steps)), and for MPI the bytes each rank sent per step (halo, exchanges, gravity gathers) and its
seconds in communication, from run_info.txt.
Usage: mpi_scaling.py <ssdem-grav (MPI build)> <outdir> <steps> <reps> <mpirun...>
"""
import csv
import os
import re
import statistics
import subprocess
import sys
import time

exe, out, steps, reps = sys.argv[1], sys.argv[2], int(sys.argv[3]), int(sys.argv[4])
mpirun = sys.argv[5:]
root = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
scene = ["--scene", os.path.join(root, "nbody/scenes/two_bodies.toml"), "--quiet",
         "--set", "initial.body_radius=50.0", "--set", "initial.body2_radius=15.0",
         "--set", "initial.body2_offset=[66.0, 2.0, 0.0]", "--set", "initial.body2_velocity=[-1.0, 0.0, 0.0]",
         "--set", "output.snapshot_interval=0.0", "--set", "output.series_every=1000000",
         "--set", "output.checkpoint_wall=0.0"]


def run(np, threads, tend, tag):
    d = os.path.join(out, tag)
    env = dict(os.environ, OMP_NUM_THREADS=str(threads), OMP_PROC_BIND="false")
    cmd = mpirun + ["-np", str(np), exe] + scene + ["--set", f"time.end={tend!r}", "--set", f'output.directory="{d}"']
    t0 = time.perf_counter()
    subprocess.run(cmd, check=True, env=env, stdout=subprocess.DEVNULL)
    return time.perf_counter() - t0, open(os.path.join(d, "run_info.txt")).read()


# dt and sphere count from a one-step probe
_, info = run(1, 2, 1e-9, "probe")
dt = float(re.search(r"dt = ([0-9.eE+-]+) s", info).group(1))
n = int(re.search(r"spheres: (\d+)", info).group(1))
tend = steps * dt * (1 - 1e-6)
configs = [(1, 2), (2, 1)]
res = {c: [] for c in configs}
comm = {}
for r in range(reps):
    for np, th in configs:
        wall, info = run(np, th, tend, f"np{np}_t{th}")
        res[(np, th)].append(wall)
        if np > 1:
            rows = re.findall(r"rank (\d+): (\d+) own spheres, (\d+) ghosts; (\d+) exchanges, (\d+) decompositions.*?"
                              r"halo ([0-9.e+-]+) B, exchanges ([0-9.e+-]+) B, gravity ([0-9.e+-]+) B; communication "
                              r"([0-9.e+-]+) s; bytes per own sphere ([0-9.e+-]+)", info)
            comm.setdefault((np, th), []).append(rows)
        print(f"rep {r}: {np} rank(s) x {th} thread(s): {wall:.2f} s", flush=True)

lines = ["# ssdem-grav on MPI: 1 rank x 2 threads vs 2 ranks x 1 thread", "",
         f"{n} spheres (two-body reaccumulation, 1 m spheres), {steps} steps of {dt:.4g} s, gravity every 10 steps "
         f"(tree, theta 0.25); 2-core machine; medians of {reps} interleaved runs; wall includes start-up and the "
         "final snapshot + checkpoint.", "",
         "| ranks x threads | wall s (median) | runs | us per sphere-step (wall) | us per sphere-step per core |",
         "|---|---|---|---|---|"]
rows_csv = []
base = statistics.median(res[configs[0]])
for np, th in configs:
    w = statistics.median(res[(np, th)])
    per = w / (n * steps) * 1e6
    lines.append(f"| {np} x {th} | {w:.2f} | {', '.join(f'{x:.2f}' for x in res[(np, th)])} | {per:.3f} | {per * 2:.3f} |")
    rows_csv.append([np, th, n, steps, w, per, per * 2, base / w])
lines += ["", f"2 ranks x 1 thread / 1 rank x 2 threads wall ratio: "
          f"{statistics.median(res[(2, 1)]) / base:.3f}", ""]
if (2, 1) in comm:
    last = comm[(2, 1)][-1]
    lines += ["Per rank (last run): own spheres, ghosts, exchanges, decompositions, bytes sent per step (halo / "
              "exchanges / gravity gathers), seconds in communication, bytes held per own sphere", "",
              "| rank | own | ghosts | exchanges | ORB | halo B/step | exchange B/step | gravity B/step | comm s | B per own sphere |",
              "|---|---|---|---|---|---|---|---|---|---|"]
    for r in last:
        lines.append("| " + " | ".join(r) + " |")
    tot = sum(float(r[5]) + float(r[6]) + float(r[7]) for r in last)
    lines += ["", f"Total sent per step by both ranks: {tot / 1e6:.3f} MB ({tot / n:.1f} B per sphere per step)."]
open(os.path.join(out, "scaling.md"), "w").write("\n".join(lines) + "\n")
with open(os.path.join(out, "scaling.csv"), "w", newline="") as f:
    wr = csv.writer(f)
    wr.writerow(["ranks", "threads", "spheres", "steps", "wall_s", "us_per_sphere_step", "us_per_sphere_step_core",
                 "speedup_vs_1x2"])
    wr.writerows(rows_csv)
print("\n".join(lines))
