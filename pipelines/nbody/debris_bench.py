"""Neighbour-list benchmark on debris (nbody-debris-bench): us per sphere-step and the phase split
(neighbours, contacts, gravity, integrate; from ssdem-grav's `done:` line) for the demo's hand-off
debris, a synthetic cloud (10^4 piled + 10^4 flying spheres) and a static rubble pile.

  debris_bench.py compare OLD NEW OUTDIR [--rounds 3] : old and new binaries interleaved
                                                        (old, new, old, new, ...) on every scene
  debris_bench.py sweep EXE OUTDIR [--skins 0.05,0.1,...] : contact.skin = f x max radius
Scenes come from the environment: DEMO_SPHERES (hand-off spheres.h5), CLOUD (nbody-debris-cloud
output), ROOT (repository root), DEMO_TIME, CLOUD_TIME, PILE_TIME (simulated seconds).
Pure standard library (radii read with h5dump). Writes OUTDIR/<mode>.md and prints it."""
import os
import re
import statistics
import subprocess
import sys
import time

ROOT = os.environ.get("ROOT", os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
DONE = re.compile(r"done: (\d+) steps; wall s: gravity ([\d.]+).*?neighbours ([\d.]+)"
                  r"(?: \((\d+) rebuilds\))?, contacts ([\d.]+), integrate ([\d.]+)")

# the reaccumulation scene's settings before the paper's method became its default (multi-rate,
# controlled cadence): what this bench's cases measure (shared with the other nbody benches and the
# bonds study)
SINGLE_RATE = ["time.multirate=false", "gravity.every=10"]


def scenes():
    out = []
    reacc = os.path.join(ROOT, "pipelines", "impact", "reaccumulate.toml")
    if os.environ.get("DEMO_SPHERES"):
        f = os.environ["DEMO_SPHERES"]
        out.append(("demo debris", reacc, f, [f"initial.file=\"{f}\"",
                    f"time.end={os.environ.get('DEMO_TIME') or '600'}", "time.steps_per_contact=4",
                    "time.min_steps_per_contact=4"] + SINGLE_RATE))
    if os.environ.get("CLOUD"):
        f = os.environ["CLOUD"]
        out.append(("cloud 1e4+1e4", reacc, f, [f"initial.file=\"{f}\"",
                    f"time.end={os.environ.get('CLOUD_TIME') or '0.02'}"] + SINGLE_RATE))
    out.append(("static pile", os.path.join(ROOT, "nbody", "scenes", "rubble_pile.toml"), None,
                [f"time.end={os.environ.get('PILE_TIME') or '200'}", "output.snapshot_interval=0"]))
    return out


def max_radius(h5):
    if h5 is None:
        return 1.0  # rubble_pile.toml: sphere_radius = 1 m (jitter only shrinks)
    txt = subprocess.run(["h5dump", "-d", "/spheres/radius", h5], check=True,
                         capture_output=True, text=True).stdout
    data = txt[txt.index("DATA {"):]
    return max(float(v) for v in re.findall(r"(?<![\w(])[-+]?\d+\.?\d*(?:[eE][-+]?\d+)?(?=[,\s])",
                                             data.split(":", 1)[1]) if v)


def run(exe, scene, sets, outdir):
    args = [exe, "--scene", scene, "--set", f'output.directory="{outdir}"',
            "--set", "output.checkpoint_wall=0", "--set", "output.times=[]"]
    for s in sets:
        args += ["--set", s]
    t0 = time.perf_counter()
    p = subprocess.run(args, capture_output=True, text=True)
    wall = time.perf_counter() - t0
    if p.returncode != 0:
        sys.exit(f"{exe} failed ({p.returncode}):\n{p.stdout[-2000:]}\n{p.stderr[-2000:]}")
    m = DONE.search(p.stdout + p.stderr)
    if not m:
        sys.exit(f"no done: line from {exe}:\n{p.stdout[-2000:]}{p.stderr[-2000:]}")
    n = re.search(r"(\d+) spheres", p.stdout + p.stderr)
    return dict(wall=wall, steps=int(m[1]), gravity=float(m[2]), neighbours=float(m[3]),
                rebuilds=int(m[4]) if m[4] else -1, contacts=float(m[5]), integrate=float(m[6]),
                n=int(n[1]) if n else 0, log=(p.stdout + p.stderr)[-4000:])


def row(label, r, n):
    phases = r["gravity"] + r["neighbours"] + r["contacts"] + r["integrate"]
    us = 1e6 * phases / (r["steps"] * n)
    return (f"| {label} | {r['steps']} | {us:.3f} | {r['neighbours']:.2f} ({100 * r['neighbours'] / phases:.0f} %) "
            f"| {r['contacts']:.2f} | {r['gravity']:.2f} | {r['integrate']:.2f} | {r['rebuilds']} | {r['wall']:.2f} |"), us


HEAD = ("| run | steps | us/sphere-step | neighbours s (% of step) | contacts s | gravity s | "
        "integrate s | full rebuilds | process wall s |\n|---|---|---|---|---|---|---|---|---|")


def nspheres(h5):
    if h5 is None:
        return None
    txt = subprocess.run(["h5dump", "-H", "-d", "/spheres/radius", h5], check=True,
                         capture_output=True, text=True).stdout
    return int(re.search(r"SIMPLE \{ \( (\d+)", txt)[1])


def main():
    mode = sys.argv[1]
    opts = dict(zip(sys.argv[2::2], sys.argv[3::2]))
    env_threads = os.environ.get("OMP_NUM_THREADS", "default")
    lines = [f"# nbody-debris-bench: {mode} (OMP_NUM_THREADS={env_threads})", ""]
    if mode == "compare":
        old, new, outdir = sys.argv[2], sys.argv[3], sys.argv[4]
        rounds = int(dict(zip(sys.argv[5::2], sys.argv[6::2])).get("--rounds", 3))
        os.makedirs(outdir, exist_ok=True)
        for name, scene, h5, sets in scenes():
            n = nspheres(h5)
            lines += [f"## {name}", "", HEAD]
            us = {"old": [], "new": []}
            for k in range(rounds):
                for tag, exe in (("old", old), ("new", new)):
                    r = run(exe, scene, sets, os.path.join(outdir, "run"))
                    nn = n or r["n"] or 1
                    txt, u = row(f"{tag} {k + 1}", r, nn)
                    lines.append(txt)
                    us[tag].append(u)
                    print(txt, flush=True)
            mo, mn = statistics.median(us["old"]), statistics.median(us["new"])
            lines += ["", f"median us/sphere-step: old {mo:.3f}, new {mn:.3f}, old/new {mo / mn:.2f}", ""]
    elif mode == "sweep":
        exe, outdir = sys.argv[2], sys.argv[3]
        skins = [float(v) for v in dict(zip(sys.argv[4::2], sys.argv[5::2])).get(
            "--skins", "0.05,0.1,0.25,0.5,1").split(",")]
        os.makedirs(outdir, exist_ok=True)
        for name, scene, h5, sets in scenes():
            n = nspheres(h5)
            smax = max_radius(h5)
            lines += [f"## {name} (max radius {smax:.4g} m)", "", HEAD]
            for f in skins:
                r = run(exe, scene, sets + [f"contact.skin={f * smax!r}"], os.path.join(outdir, "run"))
                txt, _ = row(f"skin {f} x max radius", r, n or r["n"] or 1)
                lines.append(txt)
                print(txt, flush=True)
            lines.append("")
    else:
        sys.exit(__doc__)
    text = "\n".join(lines) + "\n"
    with open(os.path.join(outdir, f"{mode}.md"), "w") as fh:
        fh.write(text)
    print(text)


if __name__ == "__main__":
    main()
