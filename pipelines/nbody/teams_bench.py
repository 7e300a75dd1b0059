"""Team-rule benchmark (nbody-teams-bench): the wall time of ssdem-grav under each run.teams rule
(size, one-thread, every-pass, and auto, the rule measured while the run goes; team_tuner.hpp) on
several scenes, with THREADS threads, against one thread and, optionally, an older binary. Every
variant of a scene runs once per round, in turn (interleaved), so that the machine's drift hits
them alike; the table gives medians and auto's share of base steps under each rule.

  teams_bench.py NEW OUTDIR CASE... [--old OLD] [--rounds 3] [--threads 2]
CASE is NAME=SNAPSHOT:SECONDS (a hand-off or an N-body snapshot, run for SECONDS under the
pipeline's scene). Writes OUTDIR/teams_bench.md and prints it. Pure standard library."""
import argparse
import os
import re
import statistics

from late_pile_bench import ROOT, old_scene, run

SHARES = re.compile(r"thread teams: (.*)")
RULES = ("size", "one-thread", "every-pass", "auto")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("new")
    ap.add_argument("outdir")
    ap.add_argument("cases", nargs="+")
    ap.add_argument("--old", default="")
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--threads", type=int, default=2)
    a = ap.parse_args()
    os.makedirs(a.outdir, exist_ok=True)
    scene = os.path.join(ROOT, "pipelines", "impact", "reaccumulate.toml")
    # (label, binary, scene, threads, extra --set)
    variants = [(f"{r}, {a.threads} threads", a.new, scene, a.threads, [f'run.teams="{r}"']) for r in RULES]
    variants.append(("auto, 1 thread", a.new, scene, 1, []))
    if a.old:
        variants.insert(0, (f"old, {a.threads} threads", a.old, old_scene(a.old, a.outdir), a.threads, []))
    cases = []
    for c in a.cases:
        name, rest = c.split("=", 1)
        snap, secs = rest.rsplit(":", 1)
        cases.append((name, snap, float(secs)))
    res = {(c[0], v[0]): [] for c in cases for v in variants}
    shares = {}
    for k in range(a.rounds):
        for name, snap, secs in cases:
            for label, exe, sc, threads, extra in variants:
                out = os.path.join(a.outdir, f"{name}-{len(res[(name, label)])}-{label.split(',')[0]}-t{threads}")
                res[(name, label)].append(run(exe, sc, snap, secs, threads, out, extra))
                m = SHARES.search(open(os.path.join(out, "run_info.txt")).read())
                if m and label.startswith("auto, ") and threads > 1:
                    shares.setdefault(name, []).append(m[1])
    med = lambda rs, key: statistics.median(r[key] for r in rs)
    lines = [f"# nbody-teams-bench: {a.rounds} round(s) interleaved, medians (wall s: the process; phases: "
             "the done: line)", ""]
    for name, snap, secs in cases:
        base = med(res[(name, f"size, {a.threads} threads")], "wall")
        lines += [f"## {name}: {secs:g} s from {snap}", "",
                  "| variant | wall s (rounds) | size / variant | contacts s | integrate s (levels) | gravity s | neighbours s |",
                  "|---|---|---|---|---|---|---|"]
        for label, *_ in variants:
            rs = res[(name, label)]
            walls = " / ".join(f"{r['wall']:.2f}" for r in rs)
            lines.append(f"| {label} | {med(rs, 'wall'):.2f} ({walls}) | {base / med(rs, 'wall'):.2f} | "
                         f"{med(rs, 'contacts'):.2f} | {med(rs, 'integrate'):.2f} ({med(rs, 'levels'):.2f}) | "
                         f"{med(rs, 'gravity'):.2f} | {med(rs, 'neighbours'):.2f} |")
        lines += [""] + [f"auto, round {i + 1}: {s}" for i, s in enumerate(shares.get(name, []))] + [""]
    text = "\n".join(lines)
    open(os.path.join(a.outdir, "teams_bench.md"), "w").write(text)
    print(text)


if __name__ == "__main__":
    main()
