#!/usr/bin/env python3
"""Strong scaling of mpm-frag on 1 -> 2 ranks against 1 -> 2 threads (issue 19: the Tonge-Ramesh
impact of ~2e5 particles, and a Tillotson impact of as many).

Cases (scenes of the repository, overrides as below):
  tillotson : mpm/scenes/basalt_impact.toml, grid.cell_size = 0.0055 (203 050 particles)
  tr-z      : pipelines/impact/fragment.toml, grid.cell_size = 700, body[0].ppc = 2,
              time.end = 0.3 (190 764 particles, 17 steps; the impact along z, across the cut axis)
  tr-x      : the same with the impactor along x (the first cut's axis): the shock starts in one box,
              which the boxes by work (mpm/mpi/domain.hpp) must follow
Configurations, run interleaved REPS times: the serial build on 1 and 2 OpenMP threads, the MPI
build on 1 and 2 ranks x 1 thread, and OLD (another MPI mpm-frag, optional) on 2 ranks.
Reported per case and configuration: the median of the `done:` walls (the stepping, without
start-up and output) with its range, its speed-up against the serial one-thread run, and for MPI
runs the halo and migration volumes, the rebalancings and the work imbalance of the last log line;
each run's log beside its directory (<outdir>/<case>-<configuration>-<round>.log).
Usage: mpm_scaling.py <serial mpm-frag> <MPI mpm-frag> <outdir> <reps> <cases,comma-separated|all>
       <old MPI mpm-frag|-> <mpirun...>
"""
import os
import re
import statistics
import subprocess
import sys

serial, mpi, out, reps, which, old = sys.argv[1:7]
reps = int(reps)
mpirun = sys.argv[7:]
root = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
TR = [os.path.join(root, "pipelines/impact/fragment.toml"), "--set", "grid.cell_size=700",
      "--set", "body[0].ppc=2", "--set", "time.end=0.3"]
CASES = {
    "tillotson": [os.path.join(root, "mpm/scenes/basalt_impact.toml"), "--set", "grid.cell_size=0.0055"],
    "tr-z": TR,
    "tr-x": TR + ["--set", "body[1].center=[13105.0,0.0,0.0]", "--set", "body[1].velocity=[-5000.0,0.0,0.0]"],
}
cases = list(CASES) if which == "all" else which.split(",")
configs = [("serial 1 thread", serial, 0, 1), ("serial 2 threads", serial, 0, 2),
           ("MPI 1 rank", mpi, 1, 1), ("MPI 2 ranks x 1 thread", mpi, 2, 1)]
if old != "-":
    configs.append(("OLD MPI 2 ranks x 1 thread", old, 2, 1))
DONE = re.compile(r"done: (\d+) steps to t = \S+ s in ([0-9.]+) s wall")
COMM = re.compile(r"communication: halo ([0-9.e+-]+) MB, migration and gathers ([0-9.e+-]+) MB, (\d+) particle moves, "
                  r"(\d+) rebalancings(?:.*?mean ([0-9.]+), largest ([0-9.]+))?")


def run(case, name, exe, ranks, threads, rep):
    tag = f"{case}-{name.replace(' ', '_')}-{rep}"
    d = os.path.join(out, tag)
    cmd = ([] if ranks == 0 else mpirun + ["-np", str(ranks)]) + [exe, "--scene"] + CASES[case] + \
        ["--set", f'output.directory="{d}"', "--set", "output.snapshot_interval=0.0"]
    env = dict(os.environ, OMP_NUM_THREADS=str(threads), OMP_PROC_BIND="false")
    p = subprocess.run(cmd, env=env, capture_output=True, text=True)
    log = p.stdout + p.stderr
    with open(d + ".log", "w") as f:  # beside the run directory, which mpm-frag owns
        f.write(log)
    if p.returncode != 0:
        sys.exit(f"{' '.join(cmd)}: exit {p.returncode}\n{log[-2000:]}")
    m = DONE.findall(log)
    c = COMM.findall(log)
    return float(m[-1][1]), int(m[-1][0]), (c[-1] if c else None)


res = {}
for r in range(reps):
    for case in cases:
        for name, exe, ranks, threads in configs:
            wall, steps, comm = run(case, name, exe, ranks, threads, r)
            res.setdefault((case, name), []).append((wall, steps, comm))
            print(f"round {r + 1}: {case}, {name}: {wall:.2f} s ({steps} steps)", flush=True)

lines = ["# mpm-frag: 1 -> 2 ranks against 1 -> 2 threads", "",
         f"Medians of {reps} interleaved rounds of the `done:` wall (stepping only); speed-up against the "
         "serial one-thread run; MPI runs: halo / migration volume, rebalancings, work imbalance "
         "(mean / largest over the checks, before rebalancing).", "",
         "| case | configuration | steps | wall s (median; range) | speed-up | halo MB | migration MB | rebalancings | imbalance |",
         "|---|---|---|---|---|---|---|---|---|"]
for case in cases:
    base = statistics.median(w for w, _, _ in res[(case, "serial 1 thread")])
    for name, *_ in configs:
        rows = res[(case, name)]
        wall = statistics.median(w for w, _, _ in rows)
        lo, hi = min(w for w, _, _ in rows), max(w for w, _, _ in rows)
        comm = rows[-1][2]
        extra = "| | | | "
        if comm:
            imb = f"{comm[4]} / {comm[5]}" if comm[4] else ""
            extra = f"| {float(comm[0]):.3g} | {float(comm[1]):.3g} | {comm[3]} | {imb} "
        lines.append(f"| {case} | {name} | {rows[-1][1]} | {wall:.2f}; {lo:.2f}-{hi:.2f} | {base / wall:.2f} {extra}|")
open(os.path.join(out, "scaling.md"), "w").write("\n".join(lines) + "\n")
print("\n".join(lines))
