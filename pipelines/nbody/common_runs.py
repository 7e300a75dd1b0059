"""Helpers shared by the nbody pipeline scripts: run ssdem-grav, read its outputs."""
import csv
import glob
import os
import subprocess
import time

import h5py
import numpy as np


def run(exe, scene, outdir, sets, threads=1):
    """Run ssdem-grav with --set overrides; returns wall seconds."""
    args = [exe, "--quiet", "--scene", scene, "--set", f'output.dir="{outdir}"']
    for s in sets:
        args += ["--set", s]
    env = dict(os.environ, OMP_NUM_THREADS=str(threads))
    t0 = time.perf_counter()
    subprocess.run(args, check=True, env=env)
    return time.perf_counter() - t0


def series(outdir):
    with open(os.path.join(outdir, "series.csv")) as f:
        rows = list(csv.DictReader(f))
    return {k: np.array([float(r[k]) for r in rows]) for k in rows[0]}


def last_snapshot(outdir):
    path = sorted(glob.glob(os.path.join(outdir, "snap_*.h5")))[-1]
    with h5py.File(path, "r") as f:
        ids = f["/spheres/id"][:]
        x = f["/spheres/position"][:]
        r = f["/spheres/radius"][:]
        t = f.attrs["time"]
    order = np.argsort(ids)
    return ids[order], x[order], r[order], t
