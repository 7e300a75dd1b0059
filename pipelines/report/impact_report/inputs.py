"""Reading the run's files once found: JSON and CSV tables, particle/sphere arrays of a snapshot,
stage timings (CSV, timed.sh JSON, `time` output) and the target and impactor bodies of the
mpm-frag scene (a TOML file or the scene recorded in /provenance)."""
import json
import math
import os
import re
import tomllib

import numpy as np
from csvio import read_rows as load_csv  # pipelines/lib (on sys.path via __init__)
from h5io import h5py, provenance, read_group


def load_json(path, notes, what):
    if not path:
        return None
    try:
        with open(path) as f:
            return json.load(f)
    except Exception as e:
        notes.append(f"{what} {path} could not be read: {e}")
        return None


def num(row, key):
    try:
        v = row.get(key, "")
        return float(v) if v not in ("", None) else float("nan")
    except ValueError:
        return float("nan")


def analysis_csv(summary, summary_path, key, suffix):
    """Locate an output CSV named in the summary (absolute, relative to cwd, or beside the JSON)."""
    cands = []
    if summary and summary.get("outputs", {}).get(key):
        p = summary["outputs"][key]
        cands += [p, os.path.join(os.path.dirname(summary_path), os.path.basename(p))]
    if summary_path:
        stem = summary_path[:-5] if summary_path.endswith(".json") else summary_path
        cands.append(stem + suffix)
    for c in cands:
        if c and os.path.isfile(c):
            return c
    return None


def read_items(path, kind):
    """Positions, masses, damage (or None), sizes (radius or half particle edge) of a file."""
    if kind == "mpm":
        t, g = read_group(path, "particles", ("position", "mass"), ("damage", "size"))
    else:
        t, g = read_group(path, "spheres", ("position", "mass", "radius"), ("damage",))
    x = np.asarray(g["position"], dtype=float).reshape(-1, 3)
    m = np.asarray(g["mass"], dtype=float).reshape(-1)
    d = np.asarray(g["damage"], dtype=float).reshape(-1) if "damage" in g else None
    if kind == "mpm":
        r = 0.5 * np.asarray(g["size"], dtype=float).reshape(-1, 3)[:, 0] if "size" in g else None
    else:
        r = np.asarray(g["radius"], dtype=float).reshape(-1)
    return float(t), x, m, d, r


def parse_timing_file(path):
    """List of (stage, wall seconds)."""
    out = []
    name = os.path.basename(path)
    try:
        if name.endswith(".csv"):
            for row in load_csv(path):
                stage = row.get("stage") or row.get("name")
                w = row.get("wall_s") or row.get("seconds") or row.get("wall")
                if stage and w:
                    out.append((stage, float(w)))
        elif name.endswith(".json"):  # {"stage", "wall_s"[, "exit_code", "threads"]} or a list of them
            with open(path) as f:
                j = json.load(f)
            items = j if isinstance(j, list) else [j]
            for it in items:
                stage = str(it.get("stage", name.split(".")[0]))
                extra = []
                if it.get("exit_code") not in (None, 0):
                    extra.append(f"exit code {it['exit_code']}")
                if it.get("threads") not in (None, ""):
                    extra.append(f"{it['threads']} threads")
                out.append((stage + (f" ({', '.join(extra)})" if extra else ""), float(it["wall_s"])))
        else:  # *.time
            text = open(path).read()
            stage = name[:-5]
            m = re.search(r"Elapsed \(wall clock\) time.*?:\s*(?:(\d+):)?(\d+):([\d.]+)", text)
            if m:
                h = float(m.group(1) or 0)
                out.append((stage, 3600 * h + 60 * float(m.group(2)) + float(m.group(3))))
            else:
                m = re.search(r"^real\s+([\d.]+)", text, re.M) or re.search(r"wall_s\s*=\s*([\d.eE+-]+)", text) \
                    or re.search(r"^\s*([\d.]+(?:[eE][+-]?\d+)?)\s*$", text, re.M)  # `time -f %e -o FILE`: a number
                if m:
                    out.append((stage, float(m.group(1))))
    except Exception:
        return []
    return out


def scene_bodies(run):
    """Target and impactor (mass [kg], radius [m], velocity) from an mpm-frag scene, or None."""
    texts = []
    for p in run.scenes:
        try:
            texts.append((p, open(p).read()))
        except Exception:
            pass
    for _, p in run.mpm[:1]:
        try:
            with h5py.File(p, "r") as f:
                s = provenance(f).get("scene", "")
                if s:
                    texts.append((p + " (/provenance/scene)", s))
        except Exception:
            pass
    for src, text in texts:
        try:
            sc = tomllib.loads(text)
        except Exception:
            continue
        bodies, mats = sc.get("body"), sc.get("material")
        if not isinstance(bodies, list) or not bodies:
            continue
        dens = {}
        for i, m in enumerate(mats or []):
            if "density" in m:
                dens[m.get("name", str(i))] = float(m["density"])
                dens[str(i)] = float(m["density"])
        out = []
        for b in bodies:
            if b.get("shape", "sphere") != "sphere" or "radius" not in b:
                continue
            rho = dens.get(str(b.get("material", "0")), None) or b.get("density")
            if rho is None:
                continue
            r = float(b["radius"])
            v = np.asarray(b.get("velocity", [0.0, 0.0, 0.0]), dtype=float)
            out.append({"name": b.get("name", "?"), "mass": float(rho) * 4.0 / 3.0 * math.pi * r ** 3,
                        "radius": r, "density": float(rho), "velocity": v})
        if len(out) >= 2:
            out.sort(key=lambda b: -b["mass"])
            return {"source": src, "target": out[0], "impactor": out[1]}
    return None
