#!/usr/bin/python3
"""Table + plot of the mpm_bench Google Benchmark JSON (medians of the repetitions).

usage: bench_table.py <bench.json> <out_dir>  ->  bench.md, bench.png
Parallel efficiency = (us/particle-step on 1 thread) / (2 * us/particle-step on 2 threads).
"""
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, "lib"))
import gbench  # noqa: E402
import mdtable  # noqa: E402


def main():
    data = gbench.load(sys.argv[1])
    out = sys.argv[2]
    os.makedirs(out, exist_ok=True)
    med = {}
    for b in gbench.aggregates(data, "median", plain=True):  # a run without repetitions counts as its median
        med[(gbench.family(b).replace("BM_", ""), gbench.args(b)[0])] = b
    cases = sorted({c for c, _ in med})
    lines = ["# mpm-frag benchmark (medians)", "",
             "Wall-clock figures; `cpu` columns are process CPU time per particle-step (the per-core cost,",
             "insensitive to other load on a shared machine). Efficiency = t1 / (2 t2) (wall).", ""]
    lines += mdtable.header(["case", "particles", "bytes/particle", "us/pstep 1 thr", "us/pstep 2 thr", "per core 2 thr",
                             "efficiency 2 thr", "cpu us/pstep/core 1 thr", "cpu us/pstep/core 2 thr"])
    xs, y1, y2 = [], [], []
    for c in cases:
        b1, b2 = med.get((c, 1)), med.get((c, 2))
        if not b1:
            continue
        t1 = b1["us_per_pstep"]
        t2 = b2["us_per_pstep"] if b2 else float("nan")
        eff = t1 / (2 * t2) if b2 else float("nan")
        c1 = gbench.counter(b1, "cpu_us_per_pstep_core")
        c2 = gbench.counter(b2, "cpu_us_per_pstep_core") if b2 else float("nan")
        lines.append("| %s | %d | %.0f | %.3f | %.3f | %.3f | %.0f %% | %.3f | %.3f |" % (
            c, b1["particles"], b1["bytes_per_particle"], t1, t2, 2 * t2, 100 * eff, c1, c2))
        xs.append(c)
        y1.append(t1)
        y2.append(2 * t2)
    fig, ax = plt.subplots(figsize=(9, 4))
    idx = range(len(xs))
    ax.bar([i - 0.2 for i in idx], y1, 0.4, label="1 thread")
    ax.bar([i + 0.2 for i in idx], y2, 0.4, label="2 threads (per core)")
    ax.axhline(0.6, color="k", ls="--", lw=1, label="target 0.6 us (elastic uGIMP)")
    ax.set_xticks(list(idx))
    ax.set_xticklabels(xs, rotation=20, fontsize=8)
    ax.set_ylabel("us per particle-step per core")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "bench.png"), dpi=130)
    open(os.path.join(out, "bench.md"), "w").write("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
