#!/usr/bin/python3
"""The paper's figures for one impact run (target impact-figures; El Mir et al. 2019, Figs. 4-6).

    /usr/bin/python3 figures.py RUN_DIR --out DIR [--mpm-times S ...] [--nbody-times S ...]
        [--profile-times S ...] [--pvbatch "xvfb-run -a pvbatch"]

RUN_DIR is a run of the impact pipeline (fragment/done lists the MPM snapshots, nbody/done the
N-body snapshots, spheres.h5 is the hand-off). For each wanted time the snapshot nearest to it is
used, and the captions and DIR/figures.md give the times actually shown:

  fig4_mpm_damage_cutaway.png    ParaView render (render_cutaway.py under pvbatch): MPM particles
                                 coloured by damage, a quarter of the body removed, at --mpm-times
                                 (s after impact);
  fig5_spheres_cutaway.png       the same for the spheres at --nbody-times (s after hand-off);
  fig6_damage_profile.png        mass-weighted mean damage in spherical shells about the
                                 mass-weighted median position (robust to ejecta), against the
                                 shell's radius over the target radius, at --profile-times (s after
                                 hand-off; the paper: 3 s, 30 s and 2 h), with the end of the MPM;
                                 shells of width R_T/12 (R_T from .vars/ANALYSE) out to 1.5 R_T;
  fig_history.png                M_LR/M_PB and beta against time with the paper's 0.85 and 1.69
                                 (the report's figure, from analysis.timeseries.csv).

Exit 2 when RUN_DIR lacks the stage outputs, 3 when pvbatch fails three times (its output is
shown; the retries are for xvfb-run -a, which now and then loses the race for a display number).
"""
import argparse
import json
import os
import re
import shlex
import subprocess
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, os.pardir, "report"))
from impact_report.figures import figure_history  # noqa: E402
from impact_report.inputs import read_items  # noqa: E402
import atomic  # noqa: E402  (pipelines/lib, on the path through impact_report)
from snapshots import is_snapshot  # noqa: E402  (pipelines/lib)
import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def listed(path):
    """The snapshots a stage's `done` file lists (snapshots.is_snapshot: no checkpoint, no outflow file)."""
    with open(path) as f:
        return [n for n in (ln.strip() for ln in f) if n and is_snapshot(n)]


def timed(files, kind):
    """[(time, path)] sorted by time (the file's `time` attribute)."""
    return sorted((read_items(p, kind)[0], p) for p in files)


def nearest(items, wanted):
    """The items nearest to each wanted time, each once, in time order."""
    out = []
    for w in wanted:
        t, p = min(items, key=lambda it: abs(it[0] - w))
        if (t, p) not in out:
            out.append((t, p))
    return sorted(out)


def target_radius(run):
    try:
        m = re.search(r"impact\.target_radius=([0-9.eE+-]+)", open(os.path.join(run, ".vars", "ANALYSE")).read())
        return float(m.group(1))
    except (OSError, AttributeError):
        return None


def render(pvbatch, kind, chosen, out, label):
    xmf = [os.path.splitext(p)[0] + ".xmf" for _, p in chosen]
    cmd = shlex.split(pvbatch) + [os.path.join(HERE, "render_cutaway.py"), "--kind", kind, "--out", out,
                                  "--label", label] + xmf + ["--times"] + [repr(t) for t, _ in chosen]
    for _ in range(3):  # xvfb-run -a occasionally loses the race for a display number: try again
        # pvbatch then aborts without Python's clean-up: the views' directory is removed here
        with tempfile.TemporaryDirectory(dir=os.path.dirname(os.path.abspath(out))) as work:
            r = subprocess.run(cmd + ["--workdir", work], capture_output=True, text=True)
        if r.returncode == 0 and os.path.isfile(out):
            break
    if r.returncode != 0 or not os.path.isfile(out):
        sys.stderr.write(r.stdout + r.stderr)
        print(f"figures: pvbatch failed (exit {r.returncode}) for {out}", file=sys.stderr)
        sys.exit(3)
    print(r.stdout.strip().splitlines()[-1] if r.stdout.strip() else f"wrote {out}")


def shell_profile(x, m, d, r_t, nbins=18):
    """(shell centres / R_T, mass-weighted mean damage, mass fraction in the shell) about the
    mass-weighted median position, shells of width R_T/12 out to 1.5 R_T."""
    c = np.array([np.interp(0.5, np.cumsum(m[np.argsort(x[:, k])]) / m.sum(), np.sort(x[:, k])) for k in range(3)])
    rad = np.linalg.norm(x - c, axis=1) / r_t
    edges = np.linspace(0.0, 1.5, nbins + 1)
    k = np.digitize(rad, edges) - 1
    ok = (k >= 0) & (k < nbins)
    mass = np.bincount(k[ok], weights=m[ok], minlength=nbins)
    md = np.bincount(k[ok], weights=(m * d)[ok], minlength=nbins)
    with np.errstate(invalid="ignore", divide="ignore"):
        mean = np.where(mass > 0, md / mass, np.nan)
    return 0.5 * (edges[1:] + edges[:-1]), mean, mass / m.sum()


def profile_figure(mpm_end, chosen, r_t, out, mpm_time):
    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    rows = []
    for label, kind, (t, p) in [(f"end of MPM, t = {mpm_end[0]:.3g} s after impact", "mpm", mpm_end)] + \
            [(f"{t:.4g} s after hand-off" if t < 7200 else f"{t / 3600:.2f} h after hand-off", "spheres", tp)
             for tp in chosen for t in [tp[0]]]:
        _, x, m, d, _ = read_items(p, kind)
        if d is None:
            continue
        rc, mean, frac = shell_profile(x, m, d, r_t)
        ax.plot(rc, mean, "o-" if kind == "spheres" else "k--", ms=3, label=label)
        rows.append((label, os.path.basename(p), rc, mean))
    ax.set_xlabel("distance from the mass-weighted median position / target radius")
    ax.set_ylabel("mass-weighted mean damage")
    ax.set_xlim(0, 1.5)
    top = max([float(np.nanmax(mean)) for _, _, _, mean in rows if np.any(np.isfinite(mean))] + [0.0])
    ax.set_ylim(0.0, 1.1 * top if top > 0 else 1.0)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    ax.set_title("damage profile (cf. El Mir et al. 2019, Fig. 6)", fontsize=10)
    fig.tight_layout()
    atomic.save_png(fig, out, dpi=110)
    return rows


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("run")
    ap.add_argument("--out", required=True)
    ap.add_argument("--mpm-times", type=float, nargs="+", default=[0.0, 1.0, 3.0, 10.0, 30.0])
    ap.add_argument("--nbody-times", type=float, nargs="+", default=[0.0, 30.0, 1800.0, 16200.0])
    ap.add_argument("--profile-times", type=float, nargs="+", default=[3.0, 30.0, 7200.0])
    ap.add_argument("--pvbatch", default="xvfb-run -a pvbatch")
    a = ap.parse_args(argv)
    need = [os.path.join(a.run, f) for f in ("fragment/done", "nbody/done", "spheres.h5", "analysis.json")]
    missing = [p for p in need if not os.path.isfile(p)]
    if missing:
        print(f"figures: {a.run} is not a complete impact run: missing {', '.join(missing)}", file=sys.stderr)
        return 2
    os.makedirs(a.out, exist_ok=True)
    mpm = timed(listed(need[0]), "mpm")
    # the hand-off file carries the MPM's end time; on the N-body clock it is t = 0 (as ssdem-analyse)
    nbody = [(0.0, need[2])] + timed(listed(need[1]), "spheres")
    nbody = [it for k, it in enumerate(nbody) if k == 0 or it[0] != nbody[k - 1][0]]  # one per time
    r_t = target_radius(a.run) or 1.0
    md = ["# Figures of " + a.run, ""]

    c4 = nearest(mpm, a.mpm_times)
    render(a.pvbatch, "mpm", c4, os.path.join(a.out, "fig4_mpm_damage_cutaway.png"), "MPM, ")
    md += [f"**Fig. 4 (MPM damage, quarter cut away; ParaView)** at t = {', '.join(f'{t:.3g}' for t, _ in c4)} s after "
           f"impact (wanted {', '.join(f'{t:g}' for t in a.mpm_times)} s; the run has "
           f"{', '.join(f'{t:.3g}' for t, _ in mpm)} s).", "", "![Fig. 4](fig4_mpm_damage_cutaway.png)", ""]
    c5 = nearest(nbody, a.nbody_times)
    render(a.pvbatch, "spheres", c5, os.path.join(a.out, "fig5_spheres_cutaway.png"), "after hand-off, ")
    md += [f"**Fig. 5 (spheres by damage, quarter cut away; ParaView)** at t = {', '.join(f'{t:.4g}' for t, _ in c5)} s "
           f"after hand-off (wanted {', '.join(f'{t:g}' for t in a.nbody_times)} s).", "",
           "![Fig. 5](fig5_spheres_cutaway.png)", ""]
    c6 = nearest(nbody, a.profile_times)
    rows = profile_figure(mpm[-1], c6, r_t, os.path.join(a.out, "fig6_damage_profile.png"), mpm[-1][0])
    md += [f"**Fig. 6 (damage against radius)** at {', '.join(f'{t:.4g}' for t, _ in c6)} s after hand-off (wanted "
           f"{', '.join(f'{t:g}' for t in a.profile_times)} s; the run's last N-body snapshot is at {nbody[-1][0]:.4g} s) "
           f"and at the end of the MPM ({mpm[-1][0]:.3g} s after impact); R_T = {r_t:g} m.", "",
           "![Fig. 6](fig6_damage_profile.png)", ""]
    md += ["| profile | file | " + " | ".join(f"{x:.3g}" for x in rows[0][2]) + " |",
           "|---|---|" + "---|" * len(rows[0][2])] if rows else []
    md += [f"| {lab} | {f} | " + " | ".join("" if not np.isfinite(v) else f"{v:.3f}" for v in mean) + " |"
           for lab, f, _, mean in rows]
    notes = []
    summary_path = os.path.join(a.run, "analysis.json")
    with open(summary_path) as f:
        summary = json.load(f)
    md += ["", figure_history(summary, summary_path, a.out, notes)] + [f"- {n}" for n in notes]
    atomic.write_text(os.path.join(a.out, "figures.md"), "\n".join(md) + "\n")
    print(f"figures: {os.path.join(a.out, 'figures.md')}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
