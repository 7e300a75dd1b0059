#!/usr/bin/env python3
"""Turn bench_nbody's JSON (median aggregates) into a Markdown table and a PNG of the phase split."""
import json
import os
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt

data = json.load(open(sys.argv[1]))
out = sys.argv[2]
rows = [b for b in data["benchmarks"] if b.get("aggregate_name") == "median"]
keys = ["N", "cpu_us", "cpu_us_gravity", "cpu_us_neighbours", "cpu_us_contacts", "cpu_us_integrate",
        "wall_us_core", "contacts_per_sphere", "bytes_per_sphere"]
with open(os.path.join(out, "bench.md"), "w") as f:
    f.write("| benchmark | " + " | ".join(keys) + " |\n|---|" + "---|" * len(keys) + "\n")
    for b in rows:
        f.write(f"| {b['run_name']} | " + " | ".join(f"{b.get(k, float('nan')):.4g}" for k in keys) + " |\n")
fig, ax = plt.subplots(figsize=(9, 4))
names = [b["run_name"].replace("BM_RubblePile/", "").replace("/iterations:3/real_time", "") for b in rows]
bottom = [0.0] * len(rows)
for k in ["cpu_us_gravity", "cpu_us_neighbours", "cpu_us_contacts", "cpu_us_integrate"]:
    vals = [b.get(k, 0.0) for b in rows]
    ax.bar(names, vals, bottom=bottom, label=k.replace("cpu_us_", ""))
    bottom = [x + y for x, y in zip(bottom, vals)]
ax.axhline(1.0, color="k", ls="--", lw=0.8)
ax.set_ylabel("CPU us per particle-step")
ax.tick_params(axis="x", labelsize=6, rotation=20)
ax.legend()
fig.tight_layout()
fig.savefig(os.path.join(out, "bench.png"), dpi=120)
print(open(os.path.join(out, "bench.md")).read())
