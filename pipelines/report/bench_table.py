#!/usr/bin/python3
"""Google Benchmark JSON of bench_analysis -> bench.csv, bench.md and bench.png (medians).

    bench_table.py BENCH_JSON OUT_DIR
"""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, "lib"))
import gbench  # noqa: E402
import mdtable  # noqa: E402


def main(path, out):
    rows = []
    for b in gbench.aggregates(gbench.load(path), "median"):
        n, threads = gbench.args(b)[:2]  # ->Args({spheres, threads})
        t = gbench.seconds(b)
        rows.append({"benchmark": gbench.family(b), "spheres": n, "threads": threads, "wall_s": t,
                     "us_per_sphere": gbench.us_per_item(b, n), "us_per_sphere_per_core": gbench.us_per_item(b, n, threads)})
    os.makedirs(out, exist_ok=True)
    with open(os.path.join(out, "bench.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
    with open(os.path.join(out, "bench.md"), "w") as f:
        f.write("\n".join(mdtable.header(["benchmark", "spheres", "threads", "median wall [s]", "us/sphere",
                                          "us/sphere/core"])) + "\n")
        for r in rows:
            f.write(f"| {r['benchmark']} | {r['spheres']} | {r['threads']} | {r['wall_s']:.3f} | "
                    f"{r['us_per_sphere']:.3f} | {r['us_per_sphere_per_core']:.3f} |\n")
    fig, ax = plt.subplots(figsize=(6, 3.5))
    labels = [f"{r['benchmark'][3:]}\nN={r['spheres']:.0e}, {r['threads']}t" for r in rows]
    ax.bar(range(len(rows)), [r["wall_s"] for r in rows])
    ax.set_xticks(range(len(rows)), labels, fontsize=6)
    ax.set_ylabel("median wall time [s]")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "bench.png"), dpi=110)
    print(open(os.path.join(out, "bench.md")).read())


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
