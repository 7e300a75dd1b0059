"""Gravity benchmark of issue 15 (nbody-gravity-bench): the dense HCP self-gravitating pile
(nbody-dense-pile: radius 100 m, 3500 kg/m^3, spacing (2 - 1e-7) R, gravel preset, k_n from 1 %
overlap at the escape speed, dt = pi sqrt(m / (2 k_n)) / 30) of 10^4 spheres for 300 steps and
5x10^4 spheres for 100 steps, gravity every step and with the error-controlled cadence; optionally
a large debris scene (pile plus as many flying fragments, nbody-debris-cloud, run with the
reaccumulation scene pipelines/impact/reaccumulate.toml for T simulated seconds).

  gravity_bench.py NEW OUTDIR [--old OLD] [--rounds 3] [--threads 1,2] [--sizes 10000:300,50000:100]
                   [--debris H5:T] [--theta X]   (--sizes none: debris only; --theta: the piles'
                   opening angle instead of the default, e.g. the issue's 0.5)

Each case runs old and new interleaved (old, new, old, new, ...) under OMP_NUM_THREADS = 1 and 2;
the cost is wall time x threads / (spheres x steps) from ssdem-grav's `done:` phase times (the
gravity phase includes the initial force and the two energy diagnostics). The relative energy
change |E_end/E_0 - 1| comes from series.csv. Writes OUTDIR/gravity_bench.md and prints it."""
import csv
import os
import re
import statistics
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from debris_bench import ROOT, SINGLE_RATE, run  # noqa: E402

BASE = os.path.join(ROOT, "pipelines", "nbody", "dense_pile.toml")
EVALS = re.compile(r"gravity [\d.]+ \((\d+) evals")


def scene(build, outdir, n, steps):
    h5 = os.path.join(outdir, f"pile_{n}.h5")
    p = subprocess.run([os.path.join(build, "tests", "nbody", "nbody-dense-pile"), h5, str(n)],
                       check=True, capture_output=True, text=True)
    kv = dict(t.split("=") for t in p.stdout.strip().splitlines()[-1].split())
    dt = float(kv["dt"])
    return [f'initial.source="file"', f'initial.file="{h5}"', f"time.dt={dt!r}",
            f"contact.normal.kn={float(kv['kn'])!r}", f"time.end={(steps - 0.5) * dt!r}",
            "output.snapshot_interval=0", "output.series_every=1000000000"]


def energy_error(rundir):
    with open(os.path.join(rundir, "series.csv")) as fh:
        rows = [r for r in csv.DictReader(line for line in fh if not line.startswith("#"))]
    e0, e1 = float(rows[0]["total_J"]), float(rows[-1]["total_J"])
    return abs(e1 / e0 - 1)


def one(exe, sets, rundir, threads, base=BASE):
    os.environ["OMP_NUM_THREADS"] = str(threads)
    r = run(exe, base, sets, rundir)
    phases = r["gravity"] + r["neighbours"] + r["contacts"] + r["integrate"]
    n = r["n"]
    f = threads * 1e6 / (r["steps"] * n)
    return dict(us=phases * f, grav=r["gravity"] * f, nb=r["neighbours"] * f, ct=r["contacts"] * f,
                it=r["integrate"] * f, dE=energy_error(rundir), n=n, steps=r["steps"])


def main():
    new, outdir = sys.argv[1], sys.argv[2]
    o = dict(zip(sys.argv[3::2], sys.argv[4::2]))
    old = o.get("--old")
    rounds = int(o.get("--rounds", 3))
    threads = [int(t) for t in o.get("--threads", "1,2").split(",")]
    sz = o.get("--sizes", "10000:300,50000:100")
    sizes = [] if sz == "none" else [tuple(int(v) for v in s.split(":")) for s in sz.split(",")]
    build = os.path.dirname(os.path.dirname(new))
    os.makedirs(outdir, exist_ok=True)
    rundir = os.path.join(outdir, "run")
    cases = []
    for n, steps in sizes:
        sets = scene(build, outdir, n, steps)
        if o.get("--theta"):
            sets.append(f"gravity.theta={float(o['--theta'])!r}")
        cases.append((f"dense pile {n}, {steps} steps, gravity every step", sets + ["gravity.every=1"], True))
        cases.append((f"dense pile {n}, {steps} steps, error-controlled cadence", sets + ['gravity.every=0'], True))
    if o.get("--debris"):
        h5, t_end = o["--debris"].split(":")
        sets = [f'initial.source="file"', f'initial.file="{h5}"', "output.snapshot_interval=0",
                "output.series_every=1000000000", f"time.end={t_end}",
                *SINGLE_RATE]  # the scene before its paper-method default
        reacc = os.path.join(ROOT, "pipelines", "impact", "reaccumulate.toml")
        cases.append((f"debris {os.path.basename(h5)}, {t_end} s, reaccumulation scene", sets, True, reacc))
    theta = f", theta = {o['--theta']}" if o.get("--theta") else ""
    lines = [f"# nbody-gravity-bench (old = {old or 'none'}, new = {new}{theta})", "",
             "us per sphere-step = wall x threads / (spheres x steps); median of the rounds; "
             "dE = |E_end / E_0 - 1|", "",
             "| case | threads | binary | us/sphere-step | gravity | neighbours | contacts | integrate | dE | old/new |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    for name, sets, with_old, *base in cases:
        for th in threads:
            res = {"old": [], "new": []}
            for _ in range(rounds):
                for tag, exe in (("old", old), ("new", new)):
                    if exe is None or (tag == "old" and not with_old):
                        continue
                    res[tag].append(one(exe, sets, rundir, th, *base))
                    print(name, th, tag, res[tag][-1], flush=True)
            med = {t: {k: statistics.median(r[k] for r in v) for k in v[0]} for t, v in res.items() if v}
            for tag, m in med.items():
                ratio = f"{med['old']['us'] / med['new']['us']:.2f}" if tag == "new" and "old" in med else ""
                lines.append(f"| {name} | {th} | {tag} | {m['us']:.3f} | {m['grav']:.3f} | {m['nb']:.3f} | "
                             f"{m['ct']:.3f} | {m['it']:.3f} | {m['dE']:.2e} | {ratio} |")
    text = "\n".join(lines) + "\n"
    with open(os.path.join(outdir, "gravity_bench.md"), "w") as fh:
        fh.write(text)
    print(text)


if __name__ == "__main__":
    main()
