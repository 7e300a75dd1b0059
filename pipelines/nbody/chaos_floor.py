"""Multi-rate accuracy against the chaos floor (nbody-chaos-floor): the paper-method reaccumulation
of one hand-off (RUN/spheres.h5, e.g. the demo's) run four ways with the pipeline's scene
(reaccumulate.toml): multi-rate (the default: self-gravity held through blocks of up to 4096 base
steps), single-rate at the base step (time.multirate = false, RESPA impulses with blocks of up to
256 steps, the longest that keeps a resting pile bound), and each again with one sphere's position
perturbed by 1e-12 relative, and multi-rate with the impulses (gravity.inner_steps = "impulse")
in blocks of at most 256 (the pipeline before the held field) and 32 base steps (no breathing of
a resting pile, nbody/README.md). ssdem-analyse gives M_LR/M_PB and beta at 1 h and at the end; the multi-rate vs
single-rate difference is compared with the chaos floor (each method against its own perturbed run).

  chaos_floor.py NBODY ANALYSE RUN OUTDIR [--end 16200] [--threads 2] [--target-radius R]
Writes OUTDIR/chaos_floor.md (+ .csv) and prints it. Needs Debian's python3-h5py (perturbed copy)."""
import argparse
import csv
import json
import os
import shutil
import subprocess
import sys

import h5py

from bench_run import timed_run

ROOT = os.environ.get("ROOT", os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))


def perturbed_copy(src, dst, rel=1e-12):
    shutil.copyfile(src, dst)
    with h5py.File(dst, "r+") as f:
        x = f["spheres/position"]
        k = int(x.shape[0] // 2)  # a sphere inside the body, not at the origin (a lattice hand-off
        while not x[k, :].any():  # can put one there, where a relative change is no change)
            k = (k + 1) % x.shape[0]
        p = x[k, :]
        c = int(abs(p).argmax())
        p[c] *= 1.0 + rel
        x[k, :] = p
    return dst


def reaccumulate(exe, spheres, outdir, end, threads, extra):
    scene = os.path.join(ROOT, "pipelines", "impact", "reaccumulate.toml")
    sets = [f'initial.file="{spheres}"', f"time.end={end}", f"output.times=[3600.0, {end}]",
            f'output.directory="{outdir}"', "output.snapshot_interval=0", "output.checkpoint_wall=0"] + extra
    return timed_run(exe, scene, sets, threads, quiet=True)[0]


def analyse(exe, run, outdir, target_radius):
    snaps = sorted(os.path.join(outdir, f) for f in os.listdir(outdir) if f.startswith("snap_") and f.endswith(".h5"))
    frag = open(os.path.join(run, "fragment", "done")).read().split()
    args = [exe, os.path.join(run, "spheres.h5")] + snaps + ["--mpm", os.path.join(run, "fragment", "final.h5"),
                                                           "--mpm-initial", frag[0], "--set",
                                                           f"impact.target_radius={target_radius}",
                                                           "-o", os.path.join(outdir, "analysis")]
    p = subprocess.run(args, capture_output=True, text=True)
    if p.returncode != 0:
        sys.exit(f"{exe} failed ({p.returncode}):\n{(p.stdout + p.stderr)[-3000:]}")
    rows = list(csv.DictReader(open(os.path.join(outdir, "analysis.timeseries.csv"))))
    return rows


def at(rows, t):
    r = min(rows, key=lambda r: abs(float(r["time"]) - t))
    return float(r["M_LR_over_M_PB"]), float(r["beta"])


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("nbody")
    ap.add_argument("analyse")
    ap.add_argument("run")
    ap.add_argument("outdir")
    ap.add_argument("--end", type=float, default=16200.0)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--target-radius", type=float, default=12500.0)
    ap.add_argument("--cases", default="all",
                    help="'all', or 'core': the four runs of the comparison and its floor (no impulse variants)")
    a = ap.parse_args()
    os.makedirs(a.outdir, exist_ok=True)
    base = os.path.join(a.run, "spheres.h5")
    pert = perturbed_copy(base, os.path.join(a.outdir, "spheres_perturbed.h5"))
    single = ["time.multirate=false", "gravity.max_every=256"]
    impulse = ['gravity.inner_steps="impulse"']
    cases = [("multi-rate", base, []), ("multi-rate, perturbed", pert, []),
             ("single rate", base, single), ("single rate, perturbed", pert, single),
             ("multi-rate, impulses, gravity blocks <= 256 dt", base, impulse + ["gravity.max_every=256"]),
             ("multi-rate, impulses, gravity blocks <= 32 dt", base, impulse + ["gravity.max_every=32"])]
    if a.cases == "core":  # the paper-method hand-off: the impulse variants double an hour-long study
        cases = cases[:4]
    elif a.cases != "all":
        sys.exit(f"--cases must be 'all' or 'core', not '{a.cases}'")
    res = {}
    for name, sph, extra in cases:
        d = os.path.join(a.outdir, name.replace(", ", "_").replace(" ", "_"))
        shutil.rmtree(d, ignore_errors=True)
        wall = reaccumulate(a.nbody, sph, d, a.end, a.threads, extra)
        rows = analyse(a.analyse, a.run, d, a.target_radius)
        res[name] = dict(wall=wall, h1=at(rows, 3600.0), end=at(rows, a.end))
        print(name, res[name], flush=True)
    lines = [f"# nbody-chaos-floor: {a.run}/spheres.h5, {a.end:g} s, {a.threads} threads", "",
             "| run | wall s | M_LR/M_PB at 1 h | beta at 1 h | M_LR/M_PB at end | beta at end |",
             "|---|---|---|---|---|---|"]
    for name, _, _ in cases:
        r = res[name]
        lines.append(f"| {name} | {r['wall']:.0f} | {r['h1'][0]:.5f} | {r['h1'][1]:.4f} | {r['end'][0]:.5f} | "
                     f"{r['end'][1]:.4f} |")
    d = lambda x, y, k, i: abs(res[x][k][i] - res[y][k][i])
    lines += ["", "| difference | M_LR/M_PB 1 h | beta 1 h | M_LR/M_PB end | beta end |", "|---|---|---|---|---|"]
    for label, x, y in (("multi-rate vs single rate", "multi-rate", "single rate"),
                        ("chaos floor, multi-rate", "multi-rate", "multi-rate, perturbed"),
                        ("chaos floor, single rate", "single rate", "single rate, perturbed"),
                        ("held vs impulses <= 32 dt", "multi-rate", "multi-rate, impulses, gravity blocks <= 32 dt"),
                        ("held vs impulses <= 256 dt", "multi-rate", "multi-rate, impulses, gravity blocks <= 256 dt")):
        if x not in res or y not in res:
            continue
        lines.append(f"| {label} | {d(x, y, 'h1', 0):.5f} | {d(x, y, 'h1', 1):.4f} | {d(x, y, 'end', 0):.5f} | "
                     f"{d(x, y, 'end', 1):.4f} |")
    text = "\n".join(lines) + "\n"
    open(os.path.join(a.outdir, "chaos_floor.md"), "w").write(text)
    json.dump(res, open(os.path.join(a.outdir, "chaos_floor.json"), "w"), indent=1)
    print(text)


if __name__ == "__main__":
    main()
