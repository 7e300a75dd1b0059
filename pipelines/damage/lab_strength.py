#!/usr/bin/python3
"""Strength from an mpm-frag run of pipelines/damage/brazilian.toml or compression.toml (issue 16).

usage: lab_strength.py <run directory> [label]

Reads the snapshots <prefix>_NNNNNN.h5 of the run and the resolved scene in their /provenance:
  F(t)      = 2 x (volume-weighted mean of -sigma_yy over the disk particles with |y| < b) x D t/2,
              b = 1 mm: the force across the central section (x2 for the mirrored half thickness).
              (Until issue 16's exact drive this was sum(-sigma_yy V) / (2 b), which at 0.4 mm cells
              counts 4 rows = 1.6 mm of material against 2 b = 2 mm: 20 % low; the test driver
              tests/damage/brazilian.hpp still measures that way.)
  sigma_t   = 2 F / (pi D t)   (Hondros 1959 / ISRM), D and t of the scene's body (exact bodies,
              the default: the particle volumes sum to its true volume), else of the lattice
  nominal   = 2 v / D          (v = the top platen's drive speed, as experiments report)
  effective = (d sigma_t/dt) / E and (d sigma_xx,centre/dt) / E over the 20-80 % rise to the peak
              (E = 9 K G / (3 K + G) of the basalt), sigma_xx,centre = mean over |r| < 0.5 mm.
Compression (a scene without a body named "disk"): sigma(t) = -(volume-weighted mean sigma_zz of
the specimen particles with z < L/4), i.e. F/A across the lower half of the half-length model;
nominal = v / (L/2); the strength is the peak of sigma; effective = centre rate = (d sigma/dt)/E.
Platen load (the quantity a testing machine measures): from the series CSV <prefix>_series.csv,
  F_platen = |J(t_j) - J(t_{j-1})| / (t_j - t_{j-1}) between consecutive rows, J = the drive's
  impulse on the rest of the system (body<b>_J{y|z}_Ns, mpm/include/mpm/body_drive.hpp), mean
  over the driven platens, x2 for the mirrored half thickness of the disk; sigma_platen =
  2 F_platen / (pi D t) (Brazilian) or F_platen / (pi D^2 / 4) (compression), peak over the run.
Prints one CSV row (COLUMNS without wall_s and cpu_s (user + system), which run_scene.sh appends) and writes
<run directory>/strength_history.csv; `--header` prints the column names.
"""
import glob
import math
import os
import sys
import tomllib

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "lib"))
import numpy as np  # noqa: E402
from h5io import h5py, provenance  # noqa: E402

COLUMNS = ["label", "cell_m", "courant", "seed", "sampling", "nominal_rate", "effective_rate", "centre_rate",
           "peak_F_N", "sigma_t_Pa", "t_peak_s", "snapshots", "platen_F_N", "sigma_platen_Pa", "wall_s", "cpu_s"]


def platen_load(run, scene, axis, mirror):
    """(t_mid, F_platen) from the series CSV: mean over the driven bodies of |dJ/dt| along axis."""
    prefix = scene.get("output", {}).get("prefix", "mpm")
    path = os.path.join(run, prefix + "_series.csv")
    data = np.genfromtxt(path, delimiter=",", names=True)
    t = data["time_s"]
    comp = "xyz"[axis]
    cols = ["body%d_J%s_Ns" % (i, comp) for i, b in enumerate(scene["body"])
            if b.get("drive", {}).get("enabled")]
    J = np.mean([np.abs(data[c]) for c in cols], axis=0)
    keep = np.diff(t) > 0
    F = (np.diff(J) / np.where(keep, np.diff(t), 1.0))[keep]
    return 0.5 * (t[1:] + t[:-1])[keep], mirror * F


def main():
    if sys.argv[1] == "--header":
        print(",".join(COLUMNS))
        return
    run = sys.argv[1]
    files = sorted(f for f in glob.glob(os.path.join(run, "*.h5"))
                   if os.path.basename(f).rsplit("_", 1)[-1][:6].isdigit())
    if not files:
        sys.exit(f"lab_strength.py: no snapshots in {run}")
    with h5py.File(files[0], "r") as f:
        scene = tomllib.loads(provenance(f)["scene"])
    mats = scene["material"]
    basalt = next(i for i, m in enumerate(mats) if m["model"] == "tonge_ramesh")
    m = mats[basalt]
    K, G = m.get("A", 26.7e9), m.get("shear_modulus", 22.7e9)
    E = 9 * K * G / (3 * K + G)
    h = scene["grid"]["cell_size"]
    v = max(max(abs(c) for c in b["drive"]["velocity"]) for b in scene["body"]
            if b.get("drive", {}).get("enabled"))
    brazilian = any(b.get("name") == "disk" for b in scene["body"])
    band = 1e-3
    rows, geo = [], None
    for path in files:
        with h5py.File(path, "r") as f:
            time = float(f.attrs["time"])
            p = f["particles"]
            sel = p["material"][...] == basalt
            x = p["position"][...][sel]
            s = p["stress"][...][sel]
            V = p["volume"][...][sel]
        if geo is None:  # D (or 2R) and the modelled half thickness (or half length) at t = 0
            spec = next(b for b in scene["body"] if b["material"] == m["name"])
            if spec.get("exact", True):  # particle volumes sum to the true volume (issue 17)
                geo = (2 * spec["radius"], spec["length"])
            else:  # the lattice's own extent
                geo = (x[:, 0].max() - x[:, 0].min() + h, x[:, 2].max() + 0.5 * h)
        if brazilian:
            D, t = geo[0], 2 * geo[1]
            mid = np.abs(x[:, 1]) < band
            F = 2 * np.sum(-s[mid, 1] * V[mid]) / np.sum(V[mid]) * D * geo[1]
            cen = x[:, 0] ** 2 + x[:, 1] ** 2 < 0.25e-6
            rows.append((time, F, 2 * F / (math.pi * D * t), s[cen, 0].mean()))
        else:
            low = x[:, 2] < 0.5 * geo[1]
            sig = np.sum(-s[low, 2] * V[low]) / np.sum(V[low])
            rows.append((time, sig * math.pi * geo[0] ** 2 / 4, sig, sig))
    nominal = 2 * v / geo[0] if brazilian else v / geo[1]
    tp, Fp = platen_load(run, scene, 1 if brazilian else 2, 2.0 if brazilian else 1.0)
    Fpk = float(Fp.max())
    sig_p = 2 * Fpk / (math.pi * geo[0] * 2 * geo[1]) if brazilian else Fpk / (math.pi * geo[0] ** 2 / 4)
    a = np.array(rows)
    ip = int(np.argmax(a[:, 2]))
    peak = a[ip, 2]
    rise = a[: ip + 1]
    i20 = int(np.argmax(rise[:, 2] >= 0.2 * peak))
    i80 = int(np.argmax(rise[:, 2] >= 0.8 * peak))
    dt = rise[i80, 0] - rise[i20, 0]
    eff = (rise[i80, 2] - rise[i20, 2]) / (E * dt) if dt > 0 else float("nan")
    cr = (rise[i80, 3] - rise[i20, 3]) / (E * dt) if dt > 0 else float("nan")
    with open(os.path.join(run, "strength_history.csv"), "w") as f:
        f.write("t_s,F_N,sigma_Pa,centre_stress_Pa\n")
        for r in rows:
            f.write("%.6e,%.6e,%.6e,%.6e\n" % r)
    with open(os.path.join(run, "platen_load.csv"), "w") as f:
        f.write("t_s,F_platen_N\n")
        for r in zip(tp, Fp):
            f.write("%.6e,%.6e\n" % r)
    label = sys.argv[2] if len(sys.argv) > 2 else os.path.basename(os.path.normpath(run))
    out = [label, h, scene.get("solver", {}).get("courant", 0.3), scene.get("run", {}).get("seed", 0), m.get("flaw_sampling", "scale_aware"),
           nominal, eff, cr, a[ip, 1], peak, a[ip, 0], len(files), Fpk, sig_p]
    line = ",".join(str(c) if isinstance(c, str) else "%.6g" % c for c in out)
    print(line)
    if ip == len(rows) - 1:
        print("warning: the load was still rising at the last snapshot (raise time.end)", file=sys.stderr)


if __name__ == "__main__":
    main()
