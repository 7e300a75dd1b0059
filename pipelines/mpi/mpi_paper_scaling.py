#!/usr/bin/env python3
"""The MPI ssdem-grav on the paper-method debris with multi-rate block steps (issue 19 with issue 15's
steps): the demo impact handed off with one sphere per MPM cell, the impact pipeline's reaccumulation
scene (pipelines/impact/reaccumulate.toml: multi-rate, >= 20 steps per contact, error-controlled
gravity cadence) for TIME simulated seconds.

Configurations, run interleaved REPS times: 1 rank x 2 OpenMP threads (mpirun -np 1: the serial
driver, the reference) and 2 ranks x 1 thread (the domain decomposition). Reported per configuration
(medians): process wall (start-up and the final checkpoint included), the phase split of rank 0's
`done:` line, wall per base step, and for 2 ranks the per-rank decomposition, bytes sent per base step
(halo / exchanges / gravity gathers), seconds in communication and equalisation rounds per base step
(run_info.txt). The final checkpoints of the two configurations are compared with h5diff (provenance
excluded): the domain decomposition is bit-identical to one rank.

Usage: mpi_paper_scaling.py <ssdem-grav (MPI build)> <spheres.h5> <outdir> <time s> <reps> <mpirun...>
Pure standard library (h5diff from the HDF5 tools)."""
import os
import re
import statistics
import subprocess
import sys
import time

exe, spheres, out, t_end, reps = sys.argv[1], sys.argv[2], sys.argv[3], float(sys.argv[4]), int(sys.argv[5])
mpirun = sys.argv[6:]
root = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
scene = os.path.join(root, "pipelines", "impact", "reaccumulate.toml")
DONE = re.compile(r"done: (\d+) steps; wall s: gravity ([\d.]+) \((\d+) evals\).*?neighbours ([\d.]+)"
                  r"(?: \((\d+) rebuilds\))?, contacts ([\d.]+), integrate ([\d.]+)(?:, communication ([\d.]+))?")
RANK = re.compile(r"rank (\d+): (\d+) own spheres, (\d+) ghosts; (\d+) exchanges, (\d+) decompositions.*?"
                  r"halo ([0-9.e+-]+) B, exchanges ([0-9.e+-]+) B, gravity ([0-9.e+-]+) B; communication "
                  r"([0-9.e+-]+) s; bytes per own sphere ([0-9.e+-]+); multi-rate equalisation rounds (\d+) in (\d+) base steps; "
                  r"steps with a mover check (\d+)")


def run(np, threads, tag):
    d = os.path.join(out, tag)
    env = dict(os.environ, OMP_NUM_THREADS=str(threads), OMP_PROC_BIND="false")
    sets = [f'initial.file="{spheres}"', f"time.end={t_end!r}", f'output.directory="{d}"',
            "output.checkpoint_wall=0", "output.times=[]", "output.snapshot_interval=0",
            "output.series_every=1000"]
    cmd = mpirun + ["-np", str(np), exe, "--scene", scene]
    for s in sets:
        cmd += ["--set", s]
    t0 = time.perf_counter()
    p = subprocess.run(cmd, capture_output=True, text=True, env=env)
    wall = time.perf_counter() - t0
    if p.returncode != 0:
        sys.exit(f"{' '.join(cmd)} failed ({p.returncode}):\n{(p.stdout + p.stderr)[-3000:]}")
    m = DONE.search(p.stdout + p.stderr)
    info = open(os.path.join(d, "run_info.txt")).read()
    n = int(re.search(r"spheres: (\d+)", info).group(1))
    if not m:
        sys.exit(f"no done: line from {exe}")
    r = dict(wall=wall, steps=int(m[1]), gravity=float(m[2]), evals=int(m[3]), neighbours=float(m[4]),
             contacts=float(m[6]), integrate=float(m[7]), comm=float(m[8] or 0.0), n=n,
             ranks=RANK.findall(info), dir=d)
    r["levels"] = next((l for l in info.splitlines() if l.startswith("multi-rate levels")), "")
    return r


os.makedirs(out, exist_ok=True)
configs = [(1, 2), (2, 1)]
res = {c: [] for c in configs}
for k in range(reps):
    for np, th in configs:
        r = run(np, th, f"np{np}_t{th}")
        res[(np, th)].append(r)
        print(f"round {k}: {np} rank(s) x {th} thread(s): {r['wall']:.1f} s", flush=True)

same = subprocess.run(["h5diff", "--exclude-path", "/provenance", os.path.join(out, "np1_t2", "checkpoint.h5"),
                       os.path.join(out, "np2_t1", "checkpoint.h5")], capture_output=True).returncode == 0
first = res[configs[0]][0]
lines = ["# ssdem-grav on MPI with multi-rate steps: the paper-method debris", "",
         f"{first['n']} spheres ({os.path.basename(spheres)}), {t_end:g} s simulated, the impact pipeline's "
         f"reaccumulation scene (multi-rate, >= 20 steps per contact, controlled gravity cadence); "
         f"{first['steps']} base steps; 2-core machine; medians of {reps} interleaved rounds; wall includes "
         "start-up and the final checkpoint.", "",
         f"Final checkpoint of 2 ranks x 1 thread against 1 rank x 2 threads (h5diff, provenance excluded): "
         f"{'identical' if same else 'DIFFERENT'}.", "",
         "| ranks x threads | wall s (median; rounds) | us per sphere-step (wall x cores) | gravity s [evals] | "
         "neighbours s | contacts s | integrate s | communication s |",
         "|---|---|---|---|---|---|---|---|"]
med = lambda c, key: statistics.median(r[key] for r in res[c])
for c in configs:
    np, th = c
    w = med(c, "wall")
    walls = ", ".join(f"{r['wall']:.1f}" for r in res[c])
    lines.append(f"| {np} x {th} | {w:.1f} ({walls}) | "
                 f"{w * 2 / (first['n'] * first['steps']) * 1e6:.3f} | {med(c, 'gravity'):.1f} [{res[c][0]['evals']}] | "
                 f"{med(c, 'neighbours'):.1f} | {med(c, 'contacts'):.1f} | {med(c, 'integrate'):.1f} | "
                 f"{med(c, 'comm'):.1f} |")
lines += ["", f"wall(2 x 1) / wall(1 x 2) = {med((2, 1), 'wall') / med((1, 2), 'wall'):.3f}", ""]
last = res[(2, 1)][-1]["ranks"]
if last:
    lines += ["Per rank (last 2-rank run): own spheres, ghosts, exchanges, decompositions, bytes sent per base "
              "step, seconds in communication, bytes held per own sphere, equalisation rounds per base step", "",
              "| rank | own | ghosts | exchanges | ORB | halo B/step | exchange B/step | gravity B/step | comm s | "
              "B per own sphere | rounds per base step | steps with a mover check |",
              "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in last:
        lines.append("| " + " | ".join(r[:10]) + f" | {int(r[10]) / max(int(r[11]), 1):.3f} | {r[12]} |")
lines += ["", "Levels (1 x 2): " + first["levels"]]
open(os.path.join(out, "scaling.md"), "w").write("\n".join(lines) + "\n")
print("\n".join(lines))
