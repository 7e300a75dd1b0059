"""Read the outcome of one impact-pipeline run directory (shared by convergence.py and check_runs.py).

A run directory (pipelines/impact/rules.mk) holds analysis.json (ssdem-analyse summary),
spheres.audit.json (mpm2spheres audit), fragment/frag_series.csv (MPM energy history),
timing/<stage>.json ({"stage", "wall_s", "exit_code"})
and .vars/FRAGMENT (the fragment stage's resolved settings, from which the cell size, impact speed
and flaw seed `run.seed` are read).
"""
import json
import math
import os
import re
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, "lib"))
from csvio import read_rows  # noqa: E402

STAGES = ("fragment", "handoff", "reaccumulate", "analyse")


def _load(path):
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError):
        return None


def _finite(x):
    return isinstance(x, (int, float)) and math.isfinite(x)


def _particle_count(run_dir):
    """MPM particles at t = 0 (the first snapshot listed in fragment/done), or None."""
    try:
        import h5py
        with open(os.path.join(run_dir, "fragment", "done")) as f:
            first = f.readline().strip()
        with h5py.File(first, "r") as h:
            return int(h["particles/mass"].shape[0])
    except (ImportError, OSError, KeyError, ValueError):
        return None


def read_run(run_dir):
    """Dict of the run's settings, outcomes, stage times and exit codes; missing pieces are None."""
    r = {"run": run_dir, "cell_m": None, "speed_m_s": None, "seed": None, "M_LR_over_M_PB": None, "beta": None,
         "bound_mass_fraction": None, "ke_loss": None, "mass_rel_diff": None, "momentum_rel_diff": None,
         "outflow_particles": None, "spheres": None, "mpm_energy_change": None,
         "transfer_heat_frac": None, "particles": None, "wall_s": {}, "exit_code": {},
         "problems": []}
    vars_path = os.path.join(run_dir, ".vars", "FRAGMENT")
    try:
        text = open(vars_path).read()
        m = re.search(r"grid\.cell_size=([0-9.eE+-]+)", text)
        r["cell_m"] = float(m.group(1)) if m else None
        m = re.search(r"body\[1\]\.velocity=\[0,0,-([0-9.eE+-]+)\]", text)
        r["speed_m_s"] = float(m.group(1)) if m else None
        m = re.search(r"run\.seed=([0-9]+)", text)
        r["seed"] = int(m.group(1)) if m else None
    except OSError:
        r["problems"].append(f"{vars_path} missing")
    for st in STAGES:
        t = _load(os.path.join(run_dir, "timing", st + ".json"))
        if t is None:
            r["problems"].append(f"stage {st}: no timing record (not run?)")
            continue
        r["wall_s"][st] = t.get("wall_s")
        r["exit_code"][st] = t.get("exit_code")
        if t.get("exit_code") != 0:
            r["problems"].append(f"stage {st}: exit code {t.get('exit_code')}")
    an = _load(os.path.join(run_dir, "analysis.json"))
    if an is None:
        r["problems"].append("analysis.json missing or unreadable")
    else:
        fin = an.get("final", {})
        for k in ("M_LR_over_M_PB", "beta", "bound_mass_fraction"):
            r[k] = fin.get(k)
        for k in ("M_LR_over_M_PB", "bound_mass_fraction"):
            if not _finite(r[k]):
                r["problems"].append(f"analysis final.{k} = {r[k]!r} (not finite)")
        if r["beta"] is not None and not _finite(r["beta"]):
            r["problems"].append(f"analysis final.beta = {r['beta']!r} (not finite)")
    # MPM energy conservation: (E_end - E_0)/E_0 of kinetic + internal (removed particles included)
    try:
        rows = read_rows(os.path.join(run_dir, "fragment", "frag_series.csv"))
        e0, e1 = float(rows[0]["total_J"]), float(rows[-1]["total_J"])
        r["mpm_energy_change"] = (e1 - e0) / e0 if e0 else None
        # numerical heat of the grid-particle transfer (DeBar fix-up, PIC blend), per initial energy
        r["transfer_heat_frac"] = float(rows[-1]["transfer_heat_J"]) / e0 if e0 else None
    except (OSError, ValueError, IndexError, KeyError, TypeError):
        r["problems"].append("fragment/frag_series.csv missing or unreadable")
    r["particles"] = _particle_count(run_dir)
    au = _load(os.path.join(run_dir, "spheres.audit.json"))
    if au is None:
        r["problems"].append("spheres.audit.json missing or unreadable")
    else:
        r["ke_loss"] = au.get("kinetic_rel_loss")
        r["mass_rel_diff"] = au.get("mass_rel_diff")
        r["momentum_rel_diff"] = au.get("momentum_rel_diff")
        r["outflow_particles"] = au.get("outflow_particles", 0)
        r["spheres"] = (au.get("after") or {}).get("count")
        for k in ("ke_loss", "mass_rel_diff", "momentum_rel_diff"):
            if not _finite(r[k]):
                r["problems"].append(f"audit {k} = {r[k]!r} (not finite)")
    return r


def run_dirs_args(doc, argv=None, extra=None):
    """Command line of the study scripts: RUN_DIR ... --out DIR (created); `extra(parser)` adds options."""
    import argparse
    ap = argparse.ArgumentParser(description=doc.split("\n")[0])
    ap.add_argument("runs", nargs="+")
    ap.add_argument("--out", required=True)
    if extra:
        extra(ap)
    a = ap.parse_args(argv)
    os.makedirs(a.out, exist_ok=True)
    return a


def total_wall(r):
    return sum(v for v in r["wall_s"].values() if _finite(v))
