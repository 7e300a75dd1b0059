#!/usr/bin/python3
"""Damage field of a Brazilian-disk scene run (issue 16 picture): the disk particles of the layer
next to the symmetry plane, coloured by damage D, at crack onset, at the peak load and in the first
snapshot after the peak whose load is below 70 % of it.

Crack onset = the first snapshot in which at least ONSET_COUNT particles of the layer have reached
D >= D_CRACK that had not at t = 0 (flaws that start at D >= D_c are pre-broken, not a crack).
Printed (one line per panel): time, load / peak, the number of such particles, their centroid
(x, y) in mm and the rms distance of them from the disk centre and from the loaded diameter x = 0,
so "starts near the centre and runs along the loaded diameter" is a number, not only a picture.

usage: plot_damage_field.py <run directory> <out.png>
(the load history is read from <run directory>/strength_history.csv of lab_strength.py)
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

D_CRACK = 0.125
ONSET_COUNT = 5


def layer(path):
    """(time, positions, damage, ids, particle size) of the disk particles next to the symmetry plane z = min."""
    with h5py.File(path, "r") as f:
        p = f["particles"]
        sel = p["material"][...] == 0
        x = p["position"][...][sel]
        d = p["damage"][...][sel].reshape(-1)
        ids = p["id"][...][sel] if "id" in p else np.nonzero(sel)[0]
        dx = np.median(np.cbrt(p["volume"][...][sel]))
        t = float(f.attrs["time"])
    k = x[:, 2] < x[:, 2].min() + 0.5 * dx
    return t, x[k], d[k], ids[k], dx


def main():
    run, out = sys.argv[1], sys.argv[2]
    files = sorted(f for f in glob.glob(os.path.join(run, "*.h5"))
                   if os.path.basename(f).rsplit("_", 1)[-1][:6].isdigit())
    sig = read_columns(os.path.join(run, "strength_history.csv"))["sigma_Pa"]
    ip = int(np.argmax(sig))
    after = [i for i in range(ip, len(sig)) if sig[i] < 0.7 * sig[ip]]
    ia = after[0] if after else len(files) - 1
    _, x0, d0, id0, dx = layer(files[0])
    c0 = 0.5 * (x0.min(axis=0) + x0.max(axis=0))  # disk centre (in the layer plane)
    pre = set(id0[d0 >= D_CRACK].tolist())
    io = ip
    for i in range(1, ip + 1):
        _, _, d, ids, _ = layer(files[i])
        if sum(1 for j in ids[d >= D_CRACK] if j not in pre) >= ONSET_COUNT:
            io = i
            break
    fig, axes = plt.subplots(1, 3, figsize=(9.6, 3.4))
    for ax, i, what in ((axes[0], io, "crack onset"), (axes[1], ip, "peak load"),
                        (axes[2], ia, "load < 70 % of peak")):
        t, x, d, ids, _ = layer(files[i])
        new = (d >= D_CRACK) & np.array([j not in pre for j in ids])
        r = (x[new, :2] - c0[:2]) * 1e3
        print("%s: t = %.2f us, load/peak = %.2f, %d cracked particles (D >= %g, not pre-broken), centroid "
              "(%.2f, %.2f) mm, rms distance from centre %.2f mm, from the loaded diameter %.2f mm"
              % (what, t * 1e6, sig[i] / sig[ip], new.sum(), D_CRACK, *(r.mean(axis=0) if len(r) else (np.nan,) * 2),
                 np.sqrt((r ** 2).sum(axis=1).mean()) if len(r) else np.nan,
                 np.sqrt((r[:, 0] ** 2).mean()) if len(r) else np.nan))
        sc = ax.scatter((x[:, 0] - c0[0]) * 1e3, (x[:, 1] - c0[1]) * 1e3, c=d, s=(15.0 * dx * 1e3) ** 2, cmap="inferno",
                        vmin=0, vmax=0.2, rasterized=True)
        ax.set_aspect("equal")
        ax.set_title("%s, t = %.1f us" % (what, t * 1e6), fontsize=9)
        ax.set_xlabel("x (mm)")
    axes[0].set_ylabel("y (mm, loading axis)")
    fig.colorbar(sc, ax=axes, label="damage D", shrink=0.8)
    atomic.save_png(fig, out, 110)


if __name__ == "__main__":
    main()
