#!/usr/bin/env python3
"""Compare hand-off methods on one particle snapshot: kinetic-energy loss, angular-momentum
error, sphere count and wall time for method in {paper, conserving} x coarsen in {1, 2, 3}.

usage: compare.py MPM2SPHERES SNAPSHOT.h5 OUTDIR
Writes OUTDIR/compare.csv, OUTDIR/compare.md and OUTDIR/compare.png.
"""
import csv
import json
import os
import subprocess
import sys
import time

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    tool, snap, out = sys.argv[1:]
    os.makedirs(out, exist_ok=True)
    rows = []
    for method in ("paper", "conserving"):
        for coarsen in (1, 2, 3):
            stem = os.path.join(out, f"spheres_{method}_c{coarsen}")
            cmd = [tool, "--quiet", "-i", snap, "-o", stem + ".h5", "--method", method, "--coarsen", str(coarsen)]
            t0 = time.perf_counter()
            subprocess.run(cmd, check=True)
            wall = time.perf_counter() - t0
            with open(stem + ".audit.json") as f:
                a = json.load(f)
            rows.append({
                "method": method, "coarsen": coarsen, "spheres": a["after"]["count"],
                "particles": a["before"]["count"], "mass_rel_diff": a["mass_rel_diff"],
                "momentum_rel_diff": a["momentum_rel_diff"], "angular_momentum_rel_diff": a["angular_momentum_rel_diff"],
                "kinetic_rel_loss": a["kinetic_rel_loss"], "rotational_ke_fraction":
                a["after"]["kinetic_rotational"] / max(a["before"]["kinetic"], 1e-300),
                "exact": a["exact"], "wall_s": wall,
            })
    with open(os.path.join(out, "compare.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
    with open(os.path.join(out, "compare.md"), "w") as f:
        f.write(f"Hand-off methods on `{snap}` ({rows[0]['particles']} particles); wall time of the whole tool run "
                "(read, project, audit, write).\n\n")
        f.write("| method | coarsen | spheres | dM/M | |dP|/(M v_rms) | |dL|/L_scale | KE loss | spin KE / KE | exact | wall [s] |\n")
        f.write("|---|---|---|---|---|---|---|---|---|---|\n")
        for r in rows:
            f.write(f"| {r['method']} | {r['coarsen']} | {r['spheres']} | {r['mass_rel_diff']:.1e} | "
                    f"{r['momentum_rel_diff']:.1e} | {r['angular_momentum_rel_diff']:.2e} | "
                    f"{100 * r['kinetic_rel_loss']:.3f} % | {r['rotational_ke_fraction']:.1e} | {r['exact']} | "
                    f"{r['wall_s']:.2f} |\n")
    fig, ax = plt.subplots(1, 2, figsize=(10, 4))
    for method, marker in (("paper", "o"), ("conserving", "s")):
        sel = [r for r in rows if r["method"] == method]
        ax[0].plot([r["spheres"] for r in sel], [max(abs(r["kinetic_rel_loss"]), 1e-16) for r in sel], marker=marker,
                   label=method)
        ax[1].plot([r["wall_s"] for r in sel], [max(abs(r["kinetic_rel_loss"]), 1e-16) for r in sel], marker=marker,
                   label=method)
    for a, xl in ((ax[0], "spheres"), (ax[1], "wall time of the tool [s]")):
        a.set_xscale("log")
        a.set_yscale("log")
        a.set_xlabel(xl)
        a.set_ylabel("|kinetic-energy loss| / KE")
        a.axhline(0.0039, ls=":", c="k", lw=0.8, label="El Mir et al. 2019: 0.39 %")
        a.legend(fontsize=8)
    fig.suptitle("Hand-off: kinetic-energy loss against sphere count and cost")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "compare.png"), dpi=110)
    print(open(os.path.join(out, "compare.md")).read())


if __name__ == "__main__":
    main()
