"""Multi-rate stepping benchmark (nbody-multirate-bench): issue 15's stiff and extreme cases.

  multirate_bench.py BUILD OUTDIR [--old OLD] [--rounds 2] [--threads 2] [--cases pile,isolated,large]

* pile: every sphere in one dense HCP pile (nbody-dense-pile, 10^4 spheres, 300 steps, gravity every
  16 steps so that both paths integrate the same dynamics): multi-rate may not cost more than 5 %
  over single rate (new binary, time.multirate false/true; OLD too if given), interleaved.
* isolated: 10^4 spheres of 1 m spread over a 2 km ball (no contact in reach), self-gravity with
  the error-controlled cadence: single rate vs multi-rate; the cost should be gravity only.
* large: 10^5 spheres (dense pile, 40 steps, gravity every 16) multi-rate on THREADS threads: the
  phase split, with the serial level bookkeeping (`levels`) as a share of the step.
Cost = wall time x threads / (spheres x base steps) from ssdem-grav's `done:` phases.
Writes OUTDIR/multirate_bench.md and prints it."""
import os
import re
import statistics
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from debris_bench import ROOT, run  # noqa: E402
from gravity_bench import BASE, scene  # noqa: E402

LEVELS = re.compile(r"\(levels ([\d.]+)\)")
RUBBLE = os.path.join(ROOT, "nbody", "scenes", "rubble_pile.toml")


def one(exe, scene_file, sets, rundir, threads):
    os.environ["OMP_NUM_THREADS"] = str(threads)
    r = run(exe, scene_file, sets, rundir)
    ph = r["gravity"] + r["neighbours"] + r["contacts"] + r["integrate"]
    f = threads * 1e6 / (r["steps"] * r["n"])
    lv = LEVELS.search(r["log"])
    r.update(us=ph * f, ph=ph, grav_share=r["gravity"] / ph, levels=float(lv[1]) if lv else 0.0)
    try:
        txt = open(os.path.join(rundir, "run_info.txt")).read()
        r["levels_info"] = next((l for l in txt.splitlines() if l.startswith("multi-rate levels")), "")
    except OSError:
        r["levels_info"] = ""
    return r


def fmt(label, r, extra=""):
    return (f"| {label} | {r['n']} | {r['steps']} | {r['us']:.3f} | {r['gravity']:.2f} | {r['neighbours']:.2f} | "
            f"{r['contacts']:.2f} | {r['integrate']:.2f} | {extra} |")


HEAD = ["| case | spheres | base steps | us/sphere-step | gravity s | neighbours s | contacts s | integrate s | note |",
        "|---|---|---|---|---|---|---|---|---|"]


def main():
    build, outdir = sys.argv[1], sys.argv[2]
    o = dict(zip(sys.argv[3::2], sys.argv[4::2]))
    old, rounds, threads = o.get("--old"), int(o.get("--rounds", 2)), int(o.get("--threads", 2))
    cases = o.get("--cases", "pile,isolated,large").split(",")
    exe = os.path.join(build, "nbody", "ssdem-grav")
    os.makedirs(outdir, exist_ok=True)
    lines = [f"# nbody-multirate-bench ({threads} threads, {rounds} rounds interleaved, medians)", ""]
    if "pile" in cases:
        sets = scene(build, outdir, 10000, 300) + ["gravity.every=16"]
        res = {"old": [], "single": [], "multi": []}
        for k in range(rounds):
            if old:
                res["old"].append(one(old, BASE, sets, os.path.join(outdir, f"pile_old{k}"), threads))
            res["single"].append(one(exe, BASE, sets + ["time.multirate=false"], os.path.join(outdir, f"pile_sr{k}"), threads))
            res["multi"].append(one(exe, BASE, sets + ["time.multirate=true"], os.path.join(outdir, f"pile_mr{k}"), threads))
        lines += ["## All spheres in one pile (10^4 HCP, 300 steps, gravity every 16)", ""] + HEAD
        med = {}
        for key, rs in res.items():
            for k, r in enumerate(rs):
                lines.append(fmt(f"{key} #{k}", r))
            if rs:
                med[key] = statistics.median(r["us"] for r in rs)
        lines += ["", "medians us/sphere-step: " + ", ".join(f"{k} {v:.3f}" for k, v in med.items()),
                  f"multi / single = {med['multi'] / med['single']:.3f}"
                  + (f", multi / old = {med['multi'] / med['old']:.3f}" if "old" in med else ""), ""]
    if "isolated" in cases:
        sets = ['initial.source="random_pile"', "initial.count=10000", "initial.body_radius=2000",
                "initial.sphere_radius=1", "contact.vmax=5", "time.end=0.5", "output.snapshot_interval=0",
                "output.series_every=1000000000", "gravity.theta=0.5", "gravity.every=0"]
        res = {"single": [], "multi": []}
        for k in range(rounds):
            res["single"].append(one(exe, RUBBLE, sets + ["time.multirate=false"], os.path.join(outdir, f"iso_sr{k}"), threads))
            res["multi"].append(one(exe, RUBBLE, sets + ["time.multirate=true"], os.path.join(outdir, f"iso_mr{k}"), threads))
        lines += ["## 10^4 isolated spheres (2 km ball, 0.5 s, error-controlled gravity cadence)", ""] + HEAD
        for key, rs in res.items():
            for k, r in enumerate(rs):
                lines.append(fmt(f"{key} #{k}", r, f"gravity {100 * r['grav_share']:.0f} % of the step"))
        m = {k: statistics.median(r["us"] for r in v) for k, v in res.items()}
        lines += ["", f"medians us/sphere-step: single {m['single']:.3f}, multi {m['multi']:.3f}",
                  res["multi"][-1]["levels_info"], ""]
    if "large" in cases:
        sets = scene(build, outdir, 100000, 40) + ["gravity.every=16", "time.multirate=true"]
        r = one(exe, BASE, sets, os.path.join(outdir, "large_mr"), threads)
        lines += ["## 10^5 spheres, dense pile, multi-rate (40 steps)", ""] + HEAD
        lines.append(fmt("multi", r, f"levels {r['levels']:.2f} s = {100 * r['levels'] / r['ph']:.1f} % of the step"))
        lines += ["", "levels: the level rule (parallel) and the near-pair equalisation (serial fixed point), "
                  "included in integrate", ""]
    text = "\n".join(lines) + "\n"
    open(os.path.join(outdir, "multirate_bench.md"), "w").write(text)
    print(text)


if __name__ == "__main__":
    main()
