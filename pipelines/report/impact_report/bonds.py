"""Bonds of the reaccumulation stage in the impact report: the bond count, how many broke and when,
the energy stored in intact bonds and the stored energy of the broken ones (released; it has left
ssdem-grav's total_J, so total_J + bond_released_J is the conserved sum of an undamped run), from
the bond columns of ssdem-grav's series.csv (nbody/README.md). No bond columns: no section."""
import os

from csvio import read_rows  # pipelines/lib

from .common import fmt


def bonds_section(nbody_snapshots):
    """Markdown lines for the series.csv beside the N-body snapshots [(time, path)], or []."""
    dirs = sorted({os.path.dirname(p) for _, p in nbody_snapshots})
    for d in dirs:
        path = os.path.join(d, "series.csv")
        try:
            rows = read_rows(path)
        except OSError:
            continue
        if not rows or "bonds_broken" not in rows[0]:
            continue
        first, last = rows[0], rows[-1]
        n = int(first["bonds_intact"]) + int(first["bonds_broken"])
        half = next((float(r["time_s"]) for r in rows if 2 * int(r["bonds_broken"]) >= n and n > 0), None)
        e0 = abs(float(first["total_J"]))
        md = ["## Bonds (ssdem-grav)\n", f"Source: `{path}`.\n", "| quantity | value |\n|---|---|"]
        md.append(f"| bonds at the start (broken) | {n} ({first['bonds_broken']}) |")
        md.append(f"| broken at the end, t = {fmt(float(last['time_s']), 4, 's')} | {last['bonds_broken']} |")
        md.append(f"| half of them broken by | {fmt(half, 4, 's') if half is not None else 'not reached'} |")
        md.append(f"| stored in intact bonds at the end | {fmt(float(last['bond_elastic_J']), 4, 'J')} |")
        rel = float(last["bond_released_J"])
        md.append(f"| stored energy of the broken bonds (released) | {fmt(rel, 4, 'J')} "
                  f"({fmt(rel / e0 if e0 else None, 3)} of the initial total) |")
        md.append("")
        return md
    return []
