"""Command line of the impact report (make_report.py): options, then the report assembled from
the sections and figures and written to OUT/report.md."""
import argparse
import os
import sys

from h5io import h5py  # pipelines/lib
from .bonds import bonds_section
from .cutaway import impact_frame
from .discover import discover
from .energy import energy_section
from .figures import figures_section
from .files import write_text
from .inputs import load_json, scene_bodies
from .physics import impact_energy
from . import sections

DESCRIPTION = "Impact report: one Markdown page + PNG figures for a run directory of the impact pipeline."


def parse_args(argv=None):
    ap = argparse.ArgumentParser(description=DESCRIPTION)
    ap.add_argument("run_dir")
    ap.add_argument("--out", help="output directory (default RUN_DIR/report)")
    ap.add_argument("--mpm", nargs="*", help="mpm-frag snapshots (default: discovered)")
    ap.add_argument("--spheres", nargs="*", help="ssdem-grav snapshots (default: discovered)")
    ap.add_argument("--handoff", help="mpm2spheres sphere file (default: discovered)")
    ap.add_argument("--audit", help="hand-off audit JSON (default: *.audit.json)")
    ap.add_argument("--analysis", help="ssdem-analyse summary JSON (default: discovered)")
    ap.add_argument("--timings", nargs="*", help="timing files (default: discovered)")
    ap.add_argument("--scene", nargs="*", help="scene TOML files (default: *.toml in RUN_DIR)")
    ap.add_argument("--title", default=None)
    return ap.parse_args(argv)


def build_report(run, out, title):
    """The report's Markdown lines; writes the figures into `out`."""
    notes = run.notes
    summary = load_json(run.analysis, notes, "analysis summary")
    audit = load_json(run.audit, notes, "hand-off audit")
    bodies = scene_bodies(run)
    frame = impact_frame(summary, bodies)
    energy = impact_energy(summary, bodies)
    md = sections.title_section(title)
    md += sections.inputs_section(energy, summary, bodies)
    md += sections.outcome_section(summary)
    md += sections.comparison_section(energy, summary, audit)
    md += energy_section(run.mpm_series)
    md += sections.audit_section(run, audit)
    md += bonds_section(run.nbody)
    md += sections.timings_section(run)
    md += figures_section(run, summary, frame, out, notes)
    md += sections.files_section(run, summary, notes)
    md.append("")
    return md


def main(argv=None):
    args = parse_args(argv)
    if not os.path.isdir(args.run_dir):
        print(f"make_report.py: {args.run_dir}: run directory does not exist", file=sys.stderr)
        return 2
    out = args.out or os.path.join(args.run_dir, "report")
    os.makedirs(out, exist_ok=True)
    if h5py is None:
        print("make_report.py: h5py is not installed; HDF5 inputs are not available", file=sys.stderr)
    run = discover(args.run_dir, out, args)
    title = args.title or f"Impact report: {os.path.basename(os.path.abspath(args.run_dir))}"
    md = build_report(run, out, title)
    write_text(os.path.join(out, "report.md"), "\n".join(md))
    print(f"make_report.py: wrote {os.path.join(out, 'report.md')}")
    return 0
