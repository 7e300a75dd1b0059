"""Helpers shared by the nbody pipeline scripts: run ssdem-grav, read its outputs."""
import glob
import os
import subprocess
import sys
import time

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, "lib"))
from csvio import read_columns  # noqa: E402
from h5io import read_group  # noqa: E402


def run(exe, scene, outdir, sets, threads=1):
    """Run ssdem-grav with --set overrides; returns wall seconds."""
    args = [exe, "--quiet", "--scene", scene, "--set", f'output.directory="{outdir}"']
    for s in sets:
        args += ["--set", s]
    env = dict(os.environ, OMP_NUM_THREADS=str(threads))
    t0 = time.perf_counter()
    subprocess.run(args, check=True, env=env)
    return time.perf_counter() - t0


def series(outdir):
    """The run's series.csv as {column: array}."""
    return read_columns(os.path.join(outdir, "series.csv"))


def last_snapshot(outdir):
    """ids, positions, radii (sorted by id) and time of the run's last snapshot."""
    path = sorted(glob.glob(os.path.join(outdir, "snap_*.h5")))[-1]
    t, g = read_group(path, "spheres", ("id", "position", "radius"))
    order = np.argsort(g["id"])
    return g["id"][order], g["position"][order], g["radius"][order], t
