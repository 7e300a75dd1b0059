"""Cut-away views of a snapshot: the impact frame (impact direction and two normals), a slab one
item thick through a chosen centre, drawn as discs sized like the particles or spheres and
coloured by damage; a row of such panels for up to four snapshots."""
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from .common import fmt  # noqa: E402
from .files import save_fig  # noqa: E402
from .inputs import read_items  # noqa: E402


def impact_frame(summary, bodies):
    u = None
    if summary:
        u = summary.get("inputs", {}).get("impact_direction")
    if (u is None or not np.any(np.asarray(u, dtype=float))) and bodies:
        v = bodies["impactor"]["velocity"] - bodies["target"]["velocity"]
        if np.linalg.norm(v) > 0:
            u = v / np.linalg.norm(v)
    u = np.asarray(u if u is not None and np.any(np.asarray(u, dtype=float)) else [0.0, 0.0, -1.0], dtype=float)
    u = u / np.linalg.norm(u)
    e = np.eye(3)[int(np.argmin(np.abs(u)))]
    e2 = e - e.dot(u) * u
    e2 /= np.linalg.norm(e2)
    n = np.cross(u, e2)
    return u, e2, n


def weighted_median(x, m):
    out = []
    for k in range(3):
        o = np.argsort(x[:, k])
        c = np.cumsum(m[o])
        out.append(x[o[np.searchsorted(c, 0.5 * c[-1])], k])
    return np.asarray(out)


def cutaway(ax, x, m, d, r, centre, frame, half_width, title, dmax=1.0):
    u, e2, n = frame
    rel = x - centre
    h = rel @ n
    sel = np.abs(h) <= half_width
    if not np.any(sel):
        sel = np.abs(h) <= 3 * half_width
    a = rel[sel] @ e2
    b = -(rel[sel] @ u)  # the impactor arrives from the top
    # view: 1.3 x the radius holding 80 % of the mass (whole set, 3-D), so that escaping ejecta do
    # not shrink the main body to a dot
    dist = np.linalg.norm(rel, axis=1)
    o = np.argsort(dist)
    cm = np.cumsum(m[o])
    r80 = dist[o[min(np.searchsorted(cm, 0.8 * cm[-1]), len(o) - 1)]] if len(o) else 1.0
    lim = max(1.3 * r80, 4 * half_width, 1e-9)
    ax.set_xlim(-lim, lim)
    ax.set_ylim(-lim, lim)
    ax.set_aspect("equal")
    # marker size: item diameter in points
    fig = ax.figure
    width_pt = fig.get_size_inches()[0] * 72 * ax.get_position().width
    scale = width_pt / (2 * lim)
    rr = (r[sel] if r is not None else np.full(a.size, half_width))
    size = np.clip((2 * rr * scale) ** 2, 0.5, 400)
    if d is not None:
        sc = ax.scatter(a, b, s=size, c=d[sel], cmap="inferno", vmin=0, vmax=dmax, marker="o", linewidths=0)
    else:
        ax.scatter(a, b, s=size, color="0.6", marker="o", linewidths=0)
        sc = None
    ax.set_title(title, fontsize=9)
    ax.set_xlabel("across the impact axis [m]", fontsize=8)
    if ax.get_subplotspec().is_first_col():
        ax.set_ylabel("along -impact direction [m]\n(impactor arrives from the top)", fontsize=8)
    ax.tick_params(labelsize=7)
    return sc


def pick(items, k):
    if len(items) <= k:
        return items
    idx = np.unique(np.round(np.linspace(0, len(items) - 1, k)).astype(int))
    return [items[i] for i in idx]


def snapshot_panel_figure(items, kind, frame, path, suptitle, centre_mode):
    chosen = pick(items, 4)
    fig, axes = plt.subplots(1, len(chosen), figsize=(3.4 * len(chosen) + 0.8, 3.8), squeeze=False)
    sc = None
    missing = []
    data = [read_items(p, kind) for _, p in chosen]
    # one colour scale for all panels, up to the largest damage shown (the Tonge-Ramesh model caps
    # D at D_max = 0.2, so a fixed 0..1 scale would leave a fully damaged body dark)
    dmax = max([float(np.max(d)) for _, _, _, d, _ in data if d is not None and d.size] + [0.0])
    dmax = dmax if dmax > 0 else 1.0
    for ax, (_, p), (t, x, m, d, r) in zip(axes[0], chosen, data):
        if d is None:
            missing.append(os.path.basename(p))
        centre = (m[:, None] * x).sum(0) / m.sum() if centre_mode == "com" else weighted_median(x, m)
        # slab of 1.5 item spacings: always at least one lattice layer, whatever the rounding
        hw = 0.75 * float(np.median(2 * r)) if r is not None and r.size else 1.0
        sc = cutaway(ax, x, m, d, r, centre, frame, hw, f"t = {fmt(t, 4)} s" + ("" if d is not None else " (no damage)"),
                     dmax) or sc
    if sc is not None:
        fig.colorbar(sc, ax=axes[0].tolist(), shrink=0.8, label=f"damage (scale 0 to {dmax:.3g})")
    fig.suptitle(suptitle, fontsize=10)
    save_fig(fig, path)
    return [t for t, _ in chosen], missing
