#!/usr/bin/python3
"""Check impact-pipeline runs for clean exits and finite outcomes (target impact-extremes).

    /usr/bin/python3 check_runs.py RUN_DIR [RUN_DIR ...] --out DIR

For each run: every stage's exit code (timing/<stage>.json), the analysis outcomes
(M_LR/M_PB, bound fraction, beta) and the hand-off audit (kinetic-energy loss, mass and
momentum errors) must be present and finite, and the audit's mass and momentum errors below
1e-10. Writes DIR/extremes.md and DIR/extremes.csv; exits 1 if any run fails a check.
"""
import csv
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from run_summary import STAGES, read_run, run_dirs_args, total_wall  # noqa: E402


def main(argv=None):
    a = run_dirs_args(__doc__, argv)
    rows, failed = [], False
    for d in a.runs:
        r = read_run(d)
        for k in ("mass_rel_diff", "momentum_rel_diff"):
            if isinstance(r[k], float) and abs(r[k]) > 1e-10:
                r["problems"].append(f"audit {k} = {r[k]:.3g} > 1e-10")
        failed |= bool(r["problems"])
        rows.append(r)
    cols = ["run", "speed_m_s", "cell_m", "M_LR_over_M_PB", "bound_mass_fraction", "beta", "ke_loss", "mpm_energy_change",
            "mass_rel_diff", "momentum_rel_diff", "outflow_particles", "spheres", "total_wall_s", "status"]
    with open(os.path.join(a.out, "extremes.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(cols)
        for r in rows:
            w.writerow([r["run"], r["speed_m_s"], r["cell_m"], r["M_LR_over_M_PB"], r["bound_mass_fraction"],
                        r["beta"], r["ke_loss"], r["mpm_energy_change"], r["mass_rel_diff"], r["momentum_rel_diff"],
                        r["outflow_particles"], r["spheres"], f"{total_wall(r):.1f}",
                        "ok" if not r["problems"] else "; ".join(r["problems"])])

    def fmt(x, f="{:.4g}"):
        return "n/a" if x is None else (f.format(x) if isinstance(x, float) else str(x))

    md = ["# Impacts at extreme speeds through every stage", "",
          "| speed (m/s) | stage exits | M_LR/M_PB | bound fraction | beta | hand-off KE loss | MPM energy change | "
          "mass / momentum error | outflow particles | spheres | wall (s) | status |",
          "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        exits = " ".join(f"{s[:4]}={r['exit_code'].get(s, '-')}" for s in STAGES)
        md.append(f"| {fmt(r['speed_m_s'], '{:.0f}')} | {exits} | {fmt(r['M_LR_over_M_PB'])} | "
                  f"{fmt(r['bound_mass_fraction'])} | {fmt(r['beta'])} | "
                  f"{fmt(100 * r['ke_loss'] if isinstance(r['ke_loss'], float) else None, '{:.2f} %')} | "
                  f"{fmt(100 * r['mpm_energy_change'] if isinstance(r['mpm_energy_change'], float) else None, '{:+.1f} %')} | "
                  f"{fmt(r['mass_rel_diff'], '{:.1e}')} / {fmt(r['momentum_rel_diff'], '{:.1e}')} | "
                  f"{fmt(r['outflow_particles'])} | {fmt(r['spheres'])} | {total_wall(r):.0f} | "
                  f"{'ok' if not r['problems'] else '; '.join(r['problems'])} |")
    with open(os.path.join(a.out, "extremes.md"), "w") as f:
        f.write("\n".join(md) + "\n")
    print("\n".join(md))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
