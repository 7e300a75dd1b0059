"""The MPM energy budget of the report: kinetic, EOS, elastic, plastic/granular, damage, shock and
transfer heating and their sum at the start and the end of the fragmentation stage, from
mpm-frag's <prefix>_series.csv (columns and definitions: mpm/include/mpm/energy_budget.hpp)."""
import math

from csvio import read_rows  # pipelines/lib

from .common import fmt

# (column, label); the parts after `total_J` sum to `internal_J`
PARTS = (("kinetic_J", "kinetic"),
         ("eos_J", "internal: EOS (volumetric work)"),
         ("elastic_J", "internal: stored elastic strain (deviatoric)"),
         ("plastic_J", "internal: plastic / granular dissipation"),
         ("damage_J", "internal: damage (crack) energy"),
         ("shock_heat_J", "internal: shock heating (artificial viscosity)"),
         ("transfer_heat_J", "internal: transfer heating (numerical, DeBar fix-up)"))


def budget(path):
    """(first row, last row, relative change of total_J) as floats, or None."""
    try:
        rows = read_rows(path)
        first = {k: float(v) for k, v in rows[0].items() if v not in ("", None)}
        last = {k: float(v) for k, v in rows[-1].items() if v not in ("", None)}
    except (OSError, IndexError, ValueError):
        return None
    e0 = first.get("total_J")
    change = (last["total_J"] - e0) / abs(e0) if e0 else None
    return first, last, change


def energy_section(path):
    md = ["## MPM energy budget\n"]
    b = budget(path) if path else None
    if b is None:
        return md + ["(no mpm-frag series with an energy budget found)\n"]
    first, last, change = b
    e0 = first.get("total_J") or math.nan
    md.append(f"From `{path}`, t = {fmt(first.get('time_s'), 4, 's')} to {fmt(last.get('time_s'), 4, 's')}; "
              "fractions of the initial total.\n")
    md.append("| energy | start | end | end / initial total |\n|---|---|---|---|")
    for col, label in PARTS:
        if col in last:
            md.append(f"| {label} | {fmt(first.get(col), 4, 'J')} | {fmt(last.get(col), 4, 'J')} | "
                      f"{last[col] / e0:.4f} |")
    md.append(f"| **sum (kinetic + internal)** | {fmt(first.get('total_J'), 6, 'J')} | {fmt(last.get('total_J'), 6, 'J')} | "
              f"{last['total_J'] / e0:.6f} |")
    md.append("")
    md.append(f"Change of the sum over the MPM stage: **{100 * change:+.4f} %** (energy that left with particles "
              "removed at the grid edge is kept in the totals).\n" if change is not None else "")
    return md
