"""Bonds and cohesion in the reaccumulation stage (issue 18 study; target nbody-bonds-study).

From one MPM run (a pipeline run directory with fragment/final.h5) it hands off with and without
bonds (mpm2spheres bonds.*, damage law of handoff/face_bonds.hpp) and integrates the N-body stage
with and without cohesion (contact part `cohesion`), then analyses every variant:
M_LR/M_PB and beta at the end, escaping mass against time (ssdem-analyse on each snapshot), bonds
broken against time and the broken bonds' released energy (series.csv), cost per sphere-step.

Bond stiffness: k_n A of every bond equals the contact stiffness k_n the kinetic rule chose for
the bonds-off run (run_info.txt), k_s = k_n / 2.5, so the bonds leave the time step as it is;
the strengths sigma_c = tau_c are the study's variable (scaled by the damage law).

N-body method (--method): "paper" (default) runs the family's reaccumulation scene as the pipeline
does (reaccumulate.toml: multi-rate block steps, >= 20 steps per contact and per bond mode,
error-controlled gravity cadence; the paper family also drops fragments > 1 km/s at the hand-off
like the pipeline, HANDOFF_MAX_SPEED); "single-rate" the study's former settings (single rate,
gravity every 10 steps, 4 steps per contact; debris_bench.SINGLE_RATE).

usage: bonds_study.py FAMILY RUN_DIR OUT_DIR BUILD_DIR [--variants a,b,...] [--cost-rounds K]
                      [--method paper|single-rate] [--coarsen C]
  FAMILY: paper (the demo impact, pipelines/impact/reaccumulate.toml) or dart (dart/reaccumulate.toml)
  --coarsen: MPM cells per sphere edge at the hand-off (default the family's: paper 3 for the
  1 km-cell run, use 1 for the 2 km-cell demo as the demo's own hand-off)
With SUITE_LOCK set (shared machines), each variant and each cost run holds that lock file (flock).
"""
import argparse
import csv
import glob
import json
import math
import os
import re
import shutil
import subprocess
import sys
import time

import h5py
import numpy as np

from debris_bench import SINGLE_RATE  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.abspath(os.path.join(HERE, os.pardir, os.pardir))

FAMILIES = {
    # scene, coarsen, target radius, N-body end, snapshot times, extra sets (the demo's), handoff sets,
    # cohesion strength used in the "coh" variants
    "paper": dict(scene="pipelines/impact/reaccumulate.toml", coarsen=3, radius=12500.0, end=3600.0,
                  times=[60.0, 150.0, 300.0, 600.0, 1200.0, 1800.0, 2700.0, 3600.0],
                  # --method single-rate: the study's former N-body (single rate, gravity every
                  # 10 steps, 4 steps per contact); --method paper: the scene as it is
                  nbody_sets=["time.steps_per_contact=4", "time.min_steps_per_contact=4", *SINGLE_RATE],
                  handoff_sets=[], paper_handoff_sets=["select.max_speed=1000"], cohesion=1e5, sigma=(1e6, 1e7)),
    "dart": dict(scene="pipelines/impact/dart/reaccumulate.toml", coarsen=2, radius=80.0, end=1800.0,
                 times=[30.0, 60.0, 150.0, 300.0, 900.0, 1800.0],
                 nbody_sets=["time.steps_per_contact=4", "time.min_steps_per_contact=4"],
                 handoff_sets=["select.max_speed=1000"], paper_handoff_sets=["select.max_speed=1000"], cohesion=5.0,
                 sigma=(1e4, 1e5)),
}

# name: (bonds: None or (damage_critical, index of the family's strength sigma_c = tau_c: 0 low, 1 high),
#        cohesion on)
VARIANTS = {
    "base": (None, False),
    "bonds-Dc0.125-hi": ((0.125, 1), False),
    "bonds-Dc1-lo": ((1.0, 0), False),
    "bonds-Dc1-hi": ((1.0, 1), False),
    "coh": (None, True),
    "bonds-Dc1-hi+coh": ((1.0, 1), True),
}
PARTS_COH = "normal,damping,tangential,rolling,twisting,cohesion"


class Lock:
    """flock on $SUITE_LOCK around a block (nothing when it is not set)."""

    def __enter__(self):
        import fcntl
        path = os.environ.get("SUITE_LOCK")
        self.f = open(path, "a") if path else None
        if self.f:
            fcntl.flock(self.f, fcntl.LOCK_EX)
        return self

    def __exit__(self, *exc):
        if self.f:
            self.f.close()


def tool(args, log=None, threads=2):
    cmd = [str(a) for a in args]
    env = dict(os.environ, OMP_NUM_THREADS=str(threads))
    t0 = time.perf_counter()
    r = subprocess.run(cmd, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if log:
        with open(log, "w") as f:
            f.write(r.stdout)
    if r.returncode != 0:
        sys.stderr.write(r.stdout[-3000:])
        raise SystemExit(f"failed ({r.returncode}): {' '.join(cmd)}")
    return time.perf_counter() - t0, r.stdout


def sets(pairs):
    out = []
    for p in pairs:
        out += ["--set", p]
    return out


def handoff(b, fam, frag, vdir, bond):
    out = os.path.join(vdir, "spheres.h5")
    args = [f"{b}/handoff/mpm2spheres", "--quiet", "-i", f"{frag}/final.h5", "-o", out, "--coarsen", fam["coarsen"]]
    if os.path.exists(f"{frag}/frag_outflow.h5"):
        args += ["--outflow", f"{frag}/frag_outflow.h5"]
    args += sets(fam["handoff_sets"])
    if bond:
        dc, sig, kn = bond
        args += sets(["bonds.enabled=true", f"bonds.kn={kn!r}", f"bonds.ks={kn / 2.5!r}", f"bonds.sigma_c={sig!r}",
                      f"bonds.tau_c={sig!r}", f"bonds.damage_critical={dc!r}"])
    tool(args)
    return out


def nbody(b, fam, spheres, vdir, coh, end=None, times=None, threads=2, exe=None):
    """Run ssdem-grav (exe: another binary, e.g. the previous release); returns the output
    directory, wall seconds, steps, the summed phase seconds and the peak resident set [kB]."""
    out = os.path.join(vdir, "nbody")
    shutil.rmtree(out, ignore_errors=True)
    s = [f'initial.file="{spheres}"', f"time.end={end or fam['end']}",
         f"output.times={json.dumps(times if times is not None else fam['times'])}", f'output.directory="{out}"',
         "output.checkpoint_wall=0"] + fam["nbody_sets"]
    if coh:
        s += [f'contact.parts="{PARTS_COH}"', f"contact.cohesion.sigma={fam['cohesion']!r}"]
    rss_file = os.path.join(vdir, "nbody.rss")
    wall, text = tool(["/usr/bin/time", "-f", "%M", "-o", rss_file, exe or f"{b}/nbody/ssdem-grav", "--scene",
                       os.path.join(ROOT, fam["scene"])] + sets(s), log=os.path.join(vdir, "nbody.log"), threads=threads)
    rss = int(open(rss_file).read().split()[-1])
    m = re.search(r"done: (\d+) steps; wall s: gravity ([\d.]+) .*neighbours ([\d.]+) .*contacts ([\d.]+), integrate ([\d.]+)", text)
    steps = int(m.group(1))
    phases = sum(float(m.group(i)) for i in range(2, 6))
    return out, wall, steps, phases, rss


def analyse(b, fam, frag, vdir, spheres, nb):
    snaps = sorted(glob.glob(os.path.join(nb, "snap_*.h5")))
    first = sorted(glob.glob(os.path.join(frag, "frag_[0-9]*.h5")))[0]
    prefix = os.path.join(vdir, "analysis")
    tool([f"{b}/nbody/analysis/ssdem-analyse", "--quiet", spheres] + snaps +
         ["--mpm-initial", first, "--set", f"impact.target_radius={fam['radius']!r}", "-o", prefix])
    with open(prefix + ".json") as f:
        final = json.load(f)["final"]
    rows = list(csv.DictReader(open(prefix + ".timeseries.csv")))
    # the first row is the hand-off file itself (t = 0 again); keep the N-body snapshots
    rows = [r for r in rows if os.path.basename(r["file"]).startswith("snap_")]
    t = np.array([float(r["time"]) for r in rows])
    esc = np.array([float(r["escaping_mass"]) / float(r["total_mass"]) for r in rows])
    return final, t, esc


def read_series(nb):
    rows = list(csv.DictReader(open(os.path.join(nb, "series.csv"))))
    t = np.array([float(r["time_s"]) for r in rows])
    if "bonds_broken" not in rows[0]:
        return t, None, None, None, None
    br = np.array([int(r["bonds_broken"]) for r in rows])
    n = br[0] + int(rows[0]["bonds_intact"])
    rel = np.array([float(r["bond_released_J"]) for r in rows])
    tot = np.array([float(r["total_J"]) for r in rows])
    return t, br, n, rel, tot


def contact_kn(nb):
    text = open(os.path.join(nb, "run_info.txt")).read()
    return float(re.search(r"k_n = ([0-9.eE+-]+) N/m \(kinetic rule", text).group(1))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("family", choices=FAMILIES)
    ap.add_argument("run")
    ap.add_argument("out")
    ap.add_argument("build")
    ap.add_argument("--variants", default=",".join(VARIANTS))
    ap.add_argument("--cost-rounds", type=int, default=2)
    ap.add_argument("--cost-time", type=float, default=600.0)
    ap.add_argument("--old-exe", help="previous ssdem-grav: its bonds-off cost and peak memory beside the new one's")
    ap.add_argument("--method", choices=["paper", "single-rate"], default="paper",
                    help="paper: the family's reaccumulation scene as the pipeline runs it (multi-rate); "
                         "single-rate: the study's former settings")
    ap.add_argument("--coarsen", type=int, help="hand-off coarsening (default: the family's)")
    ap.add_argument("--end", type=float, help="N-body end time [s] (default the family's; snapshots up to it)")
    ap.add_argument("--cost-only", action="store_true",
                    help="only the cost rounds, on the hand-offs and results of an earlier run into OUT_DIR")
    a = ap.parse_args()
    fam = dict(FAMILIES[a.family])
    if a.method == "paper":
        fam["nbody_sets"] = []
        fam["handoff_sets"] = fam["paper_handoff_sets"]
    if a.coarsen:
        fam["coarsen"] = a.coarsen
    if a.end:
        fam["times"] = [t for t in fam["times"] if t < a.end] + [a.end]
        fam["end"] = a.end
    frag = os.path.join(a.run, "fragment")
    os.makedirs(a.out, exist_ok=True)
    res = {}
    kn_bond = None
    names = a.variants.split(",")
    if "base" in names:
        names.remove("base")
    if a.cost_only:
        with open(os.path.join(a.out, "bonds_study.json")) as f:
            res = json.load(f)
        kn_bond = res["_bond_kn"]
    for name in [] if a.cost_only else ["base"] + names:
        bond_cfg, coh = VARIANTS[name]
        vdir = os.path.join(a.out, name)
        os.makedirs(vdir, exist_ok=True)
        bond = None
        if bond_cfg:
            bond = (bond_cfg[0], fam["sigma"][bond_cfg[1]], kn_bond)
        lock = Lock().__enter__()
        sph = handoff(a.build, fam, frag, vdir, bond)
        with h5py.File(sph, "r") as f:
            nsph = f["spheres/id"].shape[0]
            r = float(f["spheres/radius"][0])
            nbonds = f["bonds/id_a"].shape[0] if "bonds" in f else 0
            mean_f = float(np.mean(f["bonds/sigma_c"][:])) / bond[1] if nbonds else float("nan")
        nb, wall, steps, phases, _ = nbody(a.build, fam, sph, vdir, coh)
        if name == "base":
            kn_bond = contact_kn(nb) / (math.pi * r * r)  # k_n A = contact k_n
        final, t, esc = analyse(a.build, fam, frag, vdir, sph, nb)
        lock.__exit__()
        st, br, nb0, rel, tot = read_series(nb)
        res[name] = dict(spheres=nsph, bonds=nbonds, sigma_c=bond[1] if bond else None, mean_factor=mean_f, steps=steps, wall=wall,
                         us_per_sphere_step=1e6 * phases / (steps * nsph),
                         M_LR_over_M_PB=final["M_LR_over_M_PB"], beta=final["beta"],
                         escaping_fraction=final["escaping_mass_fraction"], t_esc=t.tolist(), esc=esc.tolist(),
                         t_series=st.tolist(), broken=None if br is None else br.tolist(),
                         released_J=None if rel is None else float(rel[-1]),
                         total0_J=None if tot is None else float(tot[0]),
                         broken_final=None if br is None else int(br[-1]))
        print(f"{name}: {nsph} spheres, {nbonds} bonds, M_LR/M_PB {final['M_LR_over_M_PB']:.4f}, "
              f"beta {final['beta']:.4f}, escaping {final['escaping_mass_fraction']:.4f}, wall {wall:.1f} s", flush=True)
        res["_bond_kn"] = kn_bond
        done = [n for n in names if n in res]
        with open(os.path.join(a.out, "bonds_study.json"), "w") as f:  # after every variant
            json.dump(res, f, indent=1)
        write_table(a, fam, res, done, quiet=True)
    res["_bond_kn"] = kn_bond

    # Cost per sphere-step, bonds off and on interleaved (one thread, cost_time of N-body each).
    bonded = [n for n in names if VARIANTS[n][0] and res[n]["bonds"] > 0 and not VARIANTS[n][1]]
    cost = {}
    if bonded and a.cost_rounds > 0:
        pick = max(bonded, key=lambda n: (VARIANTS[n][0][1], res[n]["bonds"]))
        runs = [("base", None), (pick, None)] + ([("base-old", a.old_exe)] if a.old_exe else [])
        for rnd in range(a.cost_rounds):
            for name, exe in runs:
                src = "base" if name == "base-old" else name
                vdir = os.path.join(a.out, "cost", name)
                os.makedirs(vdir, exist_ok=True)
                with Lock():
                    nb, wall, steps, phases, rss = nbody(a.build, fam, os.path.join(a.out, src, "spheres.h5"), vdir,
                                                         False, end=a.cost_time, times=[], threads=1, exe=exe)
                cost.setdefault(name, []).append(1e6 * phases / (steps * res[src]["spheres"]))
                res.setdefault("_rss_kB", {}).setdefault(name, []).append(rss)
                _, br, _, _, _ = read_series(nb)
                if br is not None:
                    res[src]["cost_broken_at_end"] = int(br[-1])
        res["_cost"] = {k: dict(rounds=v, median=float(np.median(v))) for k, v in cost.items()}
        res["_cost_pick"] = pick

    with open(os.path.join(a.out, "bonds_study.json"), "w") as f:
        json.dump(res, f, indent=1)
    write_table(a, fam, res, names)
    plot(a, res, ["base"] + names)


def write_table(a, fam, res, names, quiet=False):
    lines = [f"# Bonds and cohesion: {a.family} family ({a.run})", "",
             f"N-body to {fam['end']:g} s, method: {a.method} ({'the scene as the pipeline runs it: multi-rate' if a.method == 'paper' else 'single rate'}; "
             f"sets {' '.join(fam['nbody_sets']) or 'none'}); hand-off coarsen {fam['coarsen']}, sets "
             f"{' '.join(fam['handoff_sets']) or 'none'}.", "",
             f"Bond stiffness k_n = {res['_bond_kn']:.4g} N/m^3 (k_n A = the contact k_n), k_s = k_n / 2.5; "
             f"cohesion {fam['cohesion']:g} Pa where on.", "",
             "| variant | spheres | bonds | sigma_c = tau_c [Pa] | mean damage factor | broken at end | released J (/ E0) | M_LR/M_PB | beta | "
             "escaping mass fraction | steps | wall s |", "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for n in ["base"] + names:
        r = res[n]
        relf = "" if r["released_J"] is None else f"{r['released_J']:.3g} ({r['released_J'] / abs(r['total0_J']):.2g})"
        lines.append(f"| {n} | {r['spheres']} | {r['bonds']} | {'' if r['sigma_c'] is None else format(r['sigma_c'], 'g')} | {'' if r['bonds'] == 0 else format(r['mean_factor'], '.3f')} | "
                     f"{'' if r['broken_final'] is None else r['broken_final']} | {relf} | {r['M_LR_over_M_PB']:.4f} | "
                     f"{r['beta']:.4f} | {r['escaping_fraction']:.4f} | {r['steps']} | {r['wall']:.1f} |")
    lines += ["", "Escaping mass fraction against time:", "",
              "| t [s] | " + " | ".join(["base"] + names) + " |", "|---" * (len(names) + 2) + "|"]
    for k, t in enumerate(res["base"]["t_esc"]):
        lines.append(f"| {t:.0f} | " + " | ".join(f"{res[n]['esc'][k]:.4f}" if k < len(res[n]["esc"]) else ""
                                                   for n in ["base"] + names) + " |")
    if "_cost" in res:
        c = res["_cost"]
        p = res["_cost_pick"]
        lines += ["", f"Cost per sphere-step (one thread, {a.cost_time:g} s of N-body, bonds off and `{p}` "
                      f"interleaved, {len(c['base']['rounds'])} rounds): base {c['base']['median']:.3f} us "
                      f"({', '.join(f'{x:.3f}' for x in c['base']['rounds'])}), with bonds {c[p]['median']:.3f} us "
                      f"({', '.join(f'{x:.3f}' for x in c[p]['rounds'])}); ratio {c[p]['median'] / c['base']['median']:.3f}; "
                      f"{res[p]['bonds']} bonds, {res[p].get('cost_broken_at_end', 0)} broken at the end of the cost run."]
        rss = res["_rss_kB"]
        lines += ["", "Peak resident set (kB, per round): " + "; ".join(f"{k} {v}" for k, v in rss.items())]
        if "base-old" in c:
            lines += ["", f"No bonds, previous binary (`--old-exe`) interleaved: {c['base-old']['median']:.3f} us "
                          f"({', '.join(f'{x:.3f}' for x in c['base-old']['rounds'])}); new/old "
                          f"{c['base']['median'] / c['base-old']['median']:.3f}."]
    with open(os.path.join(a.out, "bonds_study.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    if not quiet:
        print("\n".join(lines))


def plot(a, res, names):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(1, 2, figsize=(11, 4))
    for n in names:
        r = res[n]
        ax[0].plot(r["t_esc"], r["esc"], "o-", label=n)
        if r["broken"] is not None and r["bonds"] > 0:
            ax[1].plot(r["t_series"], np.array(r["broken"]) / r["bonds"], label=n)
    ax[0].set_xlabel("time after hand-off [s]")
    ax[0].set_ylabel("escaping mass / total")
    ax[0].set_xscale("log")
    ax[1].set_xlabel("time after hand-off [s]")
    ax[1].set_ylabel("bonds broken / bonds")
    ax[1].set_xscale("symlog", linthresh=1.0)
    for x in ax:
        x.legend(fontsize=7)
        x.grid(alpha=0.3)
    fig.suptitle(f"bonds and cohesion, {a.family} family")
    fig.tight_layout()
    fig.savefig(os.path.join(a.out, "bonds_study.png"), dpi=110)


if __name__ == "__main__":
    main()
