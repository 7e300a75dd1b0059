#!/usr/bin/python3
"""Damage field of a Brazilian-disk scene run (issue 16 picture): the disk particles of the layer
next to the symmetry plane, coloured by damage D, in the snapshot at the peak load and in the first
after it whose load is below 70 % of the peak.

usage: plot_damage_field.py <run directory> <out.png>
(the peak is read from <run directory>/strength_history.csv of lab_strength.py)
"""
import glob
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, "lib"))
import atomic  # noqa: E402
from csvio import read_columns  # noqa: E402
from h5io import h5py  # noqa: E402


def layer(path):
    with h5py.File(path, "r") as f:
        p = f["particles"]
        sel = p["material"][...] == 0
        x = p["position"][...][sel]
        d = p["damage"][...][sel].reshape(-1)
        dx = np.median(np.cbrt(p["volume"][...][sel]))
        t = float(f.attrs["time"])
    k = x[:, 2] < x[:, 2].min() + 0.5 * dx  # the particle layer next to the symmetry plane
    return t, x[k], d[k]


def main():
    run, out = sys.argv[1], sys.argv[2]
    files = sorted(f for f in glob.glob(os.path.join(run, "*.h5"))
                   if os.path.basename(f).rsplit("_", 1)[-1][:6].isdigit())
    hist = read_columns(os.path.join(run, "strength_history.csv"))
    ip = int(np.argmax(hist["sigma_Pa"]))
    fig, axes = plt.subplots(1, 2, figsize=(9, 4.4))
    sig = hist["sigma_Pa"]
    after = [i for i in range(ip, len(sig)) if sig[i] < 0.7 * sig[ip]]
    ia = after[0] if after else len(files) - 1
    for ax, path, what in ((axes[0], files[ip], "peak load"), (axes[1], files[ia], "load < 70 % of peak")):
        t, x, d = layer(path)
        sc = ax.scatter(x[:, 0] * 1e3, x[:, 1] * 1e3, c=d, s=4, cmap="inferno", vmin=0, vmax=0.2)
        ax.set_aspect("equal")
        ax.set_title("%s, t = %.1f us" % (what, t * 1e6))
        ax.set_xlabel("x (mm)")
        ax.set_ylabel("y (mm, loading axis)")
    fig.colorbar(sc, ax=axes, label="damage D")
    atomic.save_png(fig, out, 150)


if __name__ == "__main__":
    main()
