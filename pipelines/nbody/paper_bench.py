"""Impact debris, the paper's method (nbody-paper-bench): the demo impact handed off with one sphere
per MPM cell (COARSEN=1: 8 225 spheres of 1 km), every contacting pair resolved by >= 20 steps
(time.steps_per_contact = time.min_steps_per_contact = 20), the reaccumulation scene of the impact
pipeline. Runs an old (single-rate) and a new (multi-rate) ssdem-grav interleaved for TIME simulated
seconds on THREADS threads and reports wall time, the phase split (ssdem-grav's `done:` line),
us per sphere-step = wall x threads / (spheres x base steps) and the multi-rate level histogram over
time (levels.csv). The wall time for the paper's 4.5 h is extrapolated linearly from TIME (stated as
such: the debris evolves, so this is an estimate, not a measurement).

  paper_bench.py OLD NEW SPHERES OUTDIR [--time 60] [--rounds 1] [--threads 2] [--max-every 4096]
OLD may be '-' (new only). Pure standard library. Writes OUTDIR/paper_bench.md and prints it."""
import argparse
import csv
import os
import re
import statistics
import sys

# reaccumulate.toml is multi-rate with the controlled cadence since the paper's method became the
# pipeline default; the old binary runs the single-rate setting this bench compares against
from bench_run import bench_sets, timed_run  # noqa: E402
from debris_bench import SINGLE_RATE as OLD_SETS  # noqa: E402

ROOT = os.environ.get("ROOT", os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
DONE = re.compile(r"done: (\d+) steps; wall s: gravity ([\d.]+) \((\d+) evals\).*?neighbours ([\d.]+)"
                  r"(?: \((\d+) rebuilds\))?, contacts ([\d.]+), integrate ([\d.]+)")
SPHERES = re.compile(r"spheres: (\d+)")
PAPER_T = 16200.0


def run(exe, spheres, t_end, threads, outdir, extra):
    scene = os.path.join(ROOT, "pipelines", "impact", "reaccumulate.toml")
    sets = bench_sets(spheres, t_end, outdir) + ["time.steps_per_contact=20", "time.min_steps_per_contact=20",
                                                 "output.series_every=1000"] + list(extra)
    wall, out = timed_run(exe, scene, sets, threads)
    m = DONE.search(out)
    n = SPHERES.search(open(os.path.join(outdir, "run_info.txt")).read())
    if not m or not n:
        sys.exit(f"no done:/spheres line from {exe}:\n{out[-2000:]}")
    r = dict(wall=wall, steps=int(m[1]), gravity=float(m[2]), evals=int(m[3]), neighbours=float(m[4]),
             contacts=float(m[6]), integrate=float(m[7]), n=int(n[1]))
    r["us"] = wall * threads / (r["n"] * r["steps"]) * 1e6
    r["paper_min"] = wall * PAPER_T / t_end / 60.0
    info = open(os.path.join(outdir, "run_info.txt")).read()
    r["levels"] = next((l for l in info.splitlines() if l.startswith("multi-rate levels")), "")
    lv = os.path.join(outdir, "levels.csv")
    r["hist"] = list(csv.reader(open(lv))) if os.path.exists(lv) else []
    return r


def row(label, r):
    ph = r["gravity"] + r["neighbours"] + r["contacts"] + r["integrate"]
    pc = lambda x: f"{x:.1f} ({100 * x / ph:.0f} %)"
    return (f"| {label} | {r['n']} | {r['steps']} | {r['wall']:.1f} | {r['us']:.3f} | {pc(r['gravity'])} "
            f"[{r['evals']}] | {pc(r['neighbours'])} | {pc(r['contacts'])} | {pc(r['integrate'])} | "
            f"{r['paper_min']:.1f} |")


def histogram(rows, every):
    if not rows:
        return []
    head, data = rows[0], rows[1:]
    lev = [k for k, h in enumerate(head) if h.startswith("n_level")]
    used = [k for k in lev if any(int(d[k]) > 0 for d in data)]
    out = ["| t [s] | " + " | ".join(head[k].replace("n_level", "l") for k in used) + " | promotions |",
           "|---|" + "---|" * (len(used) + 1)]
    step = max(1, len(data) // every)
    for d in data[::step] + ([data[-1]] if len(data) % step != 1 else []):
        out.append(f"| {float(d[1]):.1f} | " + " | ".join(d[k] for k in used) + f" | {d[head.index('promotions')]} |")
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("old")
    ap.add_argument("new")
    ap.add_argument("spheres")
    ap.add_argument("outdir")
    ap.add_argument("--time", type=float, default=60.0)
    ap.add_argument("--rounds", type=int, default=1)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--max-every", type=int, default=4096)
    a = ap.parse_args()
    os.makedirs(a.outdir, exist_ok=True)
    new_sets = ["time.multirate=true", "gravity.every=0", f"gravity.max_every={a.max_every}"]
    res = {"old": [], "new": []}
    for k in range(a.rounds):
        if a.old != "-":
            res["old"].append(run(a.old, a.spheres, a.time, a.threads, os.path.join(a.outdir, f"old{k}"), OLD_SETS))
        res["new"].append(run(a.new, a.spheres, a.time, a.threads, os.path.join(a.outdir, f"new{k}"), new_sets))
    lines = [f"# nbody-paper-bench: {a.time:g} s of the paper-method debris, {a.threads} threads, "
             f"{a.rounds} round(s) interleaved (old, new)", "",
             "old = single rate, gravity every 10 steps (reaccumulate.toml); new = multi-rate "
             f"(time.multirate = true), error-controlled gravity cadence up to {a.max_every} steps. "
             "us/sphere-step = wall x threads / (spheres x base steps). The last column extrapolates "
             f"the wall time linearly to 4.5 h ({PAPER_T:g} s): an estimate.", "",
             "| run | spheres | base steps | wall s | us/sphere-step | gravity s [evals] | neighbours s | "
             "contacts s | integrate s | est. 4.5 h [min] |", "|---|---|---|---|---|---|---|---|---|---|"]
    for key in ("old", "new"):
        for k, r in enumerate(res[key]):
            lines.append(row(f"{key} #{k}", r))
    if res["old"] and res["new"]:
        o = statistics.median(r["wall"] for r in res["old"])
        n = statistics.median(r["wall"] for r in res["new"])
        lines += ["", f"median wall old {o:.1f} s, new {n:.1f} s: old/new = {o / n:.2f}"]
    if res["new"]:
        lines += ["", res["new"][-1]["levels"], "", "Spheres per level (step 2^l dt) at series rows:", ""]
        lines += histogram(res["new"][-1]["hist"], 12)
    text = "\n".join(lines) + "\n"
    open(os.path.join(a.outdir, "paper_bench.md"), "w").write(text)
    print(text)


if __name__ == "__main__":
    main()
