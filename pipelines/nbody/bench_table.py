#!/usr/bin/env python3
"""Turn bench_nbody's JSON (median aggregates) into a Markdown table and a PNG of the phase split.

usage: bench_table.py <bench.json> <out_dir>  ->  bench.md, bench.png
"""
import os
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, "lib"))
import gbench  # noqa: E402
import mdtable  # noqa: E402

KEYS = ["N", "cpu_us", "cpu_us_gravity", "cpu_us_neighbours", "cpu_us_contacts", "cpu_us_integrate",
        "wall_us_core", "contacts_per_sphere", "bytes_per_sphere"]
PHASES = ["cpu_us_gravity", "cpu_us_neighbours", "cpu_us_contacts", "cpu_us_integrate"]

rows = gbench.aggregates(gbench.load(sys.argv[1]), "median")
out = sys.argv[2]
with open(os.path.join(out, "bench.md"), "w") as f:
    f.write("\n".join(mdtable.header(["benchmark"] + KEYS)) + "\n")
    for b in rows:
        f.write(mdtable.row([b["run_name"]] + [f"{gbench.counter(b, k):.4g}" for k in KEYS]) + "\n")
fig, ax = plt.subplots(figsize=(9, 4))
names = [gbench.args_label(b) for b in rows]  # N/threads/gravity interval
bottom = [0.0] * len(rows)
for k in PHASES:
    vals = [gbench.counter(b, k, 0.0) for b in rows]
    ax.bar(names, vals, bottom=bottom, label=k.replace("cpu_us_", ""))
    bottom = [x + y for x, y in zip(bottom, vals)]
ax.axhline(1.0, color="k", ls="--", lw=0.8)
ax.set_ylabel("CPU us per particle-step")
ax.tick_params(axis="x", labelsize=6, rotation=20)
ax.legend()
fig.tight_layout()
fig.savefig(os.path.join(out, "bench.png"), dpi=120)
print(open(os.path.join(out, "bench.md")).read())
