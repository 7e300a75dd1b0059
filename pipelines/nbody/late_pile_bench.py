"""Late-reaccumulation benchmark (nbody-late-bench): the cost of a reaccumulated remnant, where the
paper-method run spends most of its wall time (a pile at rest, every sphere in contact on one
level). Starts from a snapshot of a finished run (the demo's last N-body snapshot by default),
runs TIME simulated seconds with the pipeline's scene (reaccumulate.toml), old and new binaries
interleaved (old, new, old, new, ...), and reports medians of wall time, us per sphere
evaluation (wall x threads / force evaluations of spheres), the phase split and the energy error.

  late_pile_bench.py OLD NEW SNAPSHOT OUTDIR [--time 300] [--rounds 3] [--threads 1] [--sets "k=v;k=v"] [--old-sets ...]
OLD may be "-" (new only); --sets (--old-sets) are extra --set overrides of the new (old) binary's runs (e.g.
"gravity.inner_steps=\"impulse\";gravity.max_every=256" against the pipeline's defaults). Keys the old binary does not know (time.level_anchor, if its
--help-params does not list it) are removed from its copy of the scene. Writes OUTDIR/late_pile_bench.md and prints it. Pure standard library."""
import argparse
import os
import re
import statistics
import subprocess
import sys

from bench_run import bench_sets, timed_run

ROOT = os.environ.get("ROOT", os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
DONE = re.compile(r"done: (\d+) steps; wall s: gravity ([\d.]+) \((\d+) evals\).*?neighbours ([\d.]+)"
                  r"(?: \((\d+) rebuilds\))?, contacts ([\d.]+), integrate ([\d.]+) \(levels ([\d.]+)\)")
EVALS = re.compile(r"(\d+) sphere evaluations in (\d+) base steps")
ERR = re.compile(r"error \(sum - E0\) \S+ J = (\S+) of \|E0\|")
NEW_KEYS = ("level_anchor",)


def old_scene(old, outdir):
    """The pipeline's scene without the keys the old binary does not know (--help-params)."""
    src = os.path.join(ROOT, "pipelines", "impact", "reaccumulate.toml")
    known = subprocess.run([old, "--help-params"], capture_output=True, text=True).stdout
    drop = [k for k in NEW_KEYS if k not in known]
    dst = os.path.join(outdir, "reaccumulate_old.toml")
    with open(src) as f, open(dst, "w") as g:
        for line in f:
            if not line.split("=")[0].strip() in drop:
                g.write(line)
    return dst


def run(exe, scene, snap, t_end, threads, outdir, extra=()):
    wall, out = timed_run(exe, scene, bench_sets(snap, t_end, outdir) + ["output.series_every=1000"] + list(extra),
                          threads)
    info = open(os.path.join(outdir, "run_info.txt")).read()
    m, e, err = DONE.search(out), EVALS.search(info), ERR.search(info)
    if not m or not e:
        sys.exit(f"no done:/evaluations line from {exe}:\n{out[-2000:]}")
    r = dict(wall=wall, steps=int(m[1]), gravity=float(m[2]), evals=int(m[3]), neighbours=float(m[4]),
             contacts=float(m[6]), integrate=float(m[7]), levels=float(m[8]), sphere_evals=int(e[1]),
             err=float(err[1]) if err else float("nan"))
    r["us"] = wall * threads / r["sphere_evals"] * 1e6
    return r


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("old")
    ap.add_argument("new")
    ap.add_argument("snapshot")
    ap.add_argument("outdir")
    ap.add_argument("--time", type=float, default=300.0)
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--sets", default="")
    ap.add_argument("--old-sets", default="")
    a = ap.parse_args()
    extra = [s for s in a.sets.split(";") if s]
    old_extra = [s for s in a.old_sets.split(";") if s]
    os.makedirs(a.outdir, exist_ok=True)
    new_scene = os.path.join(ROOT, "pipelines", "impact", "reaccumulate.toml")
    res = {"old": [], "new": []}
    for k in range(a.rounds):
        if a.old != "-":
            res["old"].append(run(a.old, old_scene(a.old, a.outdir), a.snapshot, a.time, a.threads,
                                  os.path.join(a.outdir, f"old{k}"), old_extra))
        res["new"].append(run(a.new, new_scene, a.snapshot, a.time, a.threads, os.path.join(a.outdir, f"new{k}"),
                              extra))
    med = lambda rs, key: statistics.median(r[key] for r in rs)
    lines = [f"# nbody-late-bench: {a.time:g} s from {a.snapshot}, {a.threads} thread(s), {a.rounds} round(s) "
             "interleaved, medians" + (f"; new with --set {'; '.join(extra)}" if extra else "")
             + (f"; old with --set {'; '.join(old_extra)}" if old_extra else ""), "",
             "| binary | base steps | sphere evaluations | wall s | us per sphere evaluation | gravity s [evals] | "
             "contacts s | integrate s (levels) | neighbours s | energy error / abs(E0) |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    for key in ("old", "new"):
        rs = res[key]
        if not rs:
            continue
        lines.append(f"| {key} | {rs[0]['steps']} | {rs[0]['sphere_evals']} | {med(rs, 'wall'):.2f} | "
                     f"{med(rs, 'us'):.3f} | {med(rs, 'gravity'):.2f} [{rs[0]['evals']}] | {med(rs, 'contacts'):.2f} | "
                     f"{med(rs, 'integrate'):.2f} ({med(rs, 'levels'):.2f}) | {med(rs, 'neighbours'):.2f} | "
                     f"{rs[0]['err']:.2e} |")
    if res["old"]:
        pairs = ", ".join("%.2f/%.2f" % (o["wall"], n["wall"]) for o, n in zip(res["old"], res["new"]))
        ratio = med(res["old"], "wall") / med(res["new"], "wall")
        lines += ["", f"old/new wall = {ratio:.2f} (per round, old/new s: {pairs})"]
    text = "\n".join(lines) + "\n"
    open(os.path.join(a.outdir, "late_pile_bench.md"), "w").write(text)
    print(text)


if __name__ == "__main__":
    main()
