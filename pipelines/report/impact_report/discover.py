"""Finding a run's inputs by content: walk RUN_DIR, classify HDF5 files by their root attributes
(mpm-frag particles, hand-off spheres, N-body snapshots), JSON by their format key, timing files
and scenes by name; explicit command-line options override what was found."""
import json
import os

from h5io import attr as h5_attr, h5py, provenance  # pipelines/lib
from snapshots import is_snapshot  # pipelines/lib


class Run:
    def __init__(self):
        self.mpm = []          # (time, path)
        self.handoff = []      # (time, path)
        self.nbody = []        # (time, path)
        self.audit = None
        self.analysis = None   # path
        self.timings = []      # paths
        self.scenes = []       # paths
        self.notes = []
        self.failed_states = []
        self.mpm_series = None  # mpm-frag <prefix>_series.csv (energy budget)


def classify_h5(path, run):
    try:
        with h5py.File(path, "r") as f:
            fmt_ = h5_attr(f, "format", "")
            t = float(h5_attr(f, "time", 0.0))
            tool = provenance(f).get("tool", "")
    except Exception as e:  # unreadable file: say so, never crash
        run.notes.append(f"could not read {path}: {e}")
        return
    base = os.path.basename(path)
    if base.startswith("failed_state") or "failed" in base:
        run.failed_states.append(path)
        return
    if not is_snapshot(path):  # checkpoints (mpm-frag's too: they were counted) and the outflow file
        return
    if fmt_ == "mpm-frag.particles":
        run.mpm.append((t, path))
    elif fmt_ == "ssdem.spheres":
        # mpm2spheres stamps the MPM end time; ssdem-grav restarts its clock at 0 from that state
        if tool == "mpm2spheres":
            run.handoff.append((0.0, path))
        else:
            run.nbody.append((t, path))


def discover(run_dir, out_dir, args):
    run = Run()
    seen = set()
    skip_out = os.path.abspath(out_dir) != os.path.abspath(run_dir)  # --out may be RUN_DIR itself
    for root, dirs, files in os.walk(run_dir):
        if skip_out and (os.path.abspath(root) + os.sep).startswith(os.path.abspath(out_dir) + os.sep):
            continue
        dirs.sort()
        for name in sorted(files):
            p = os.path.join(root, name)
            real = os.path.realpath(p)
            if real in seen:  # e.g. fragment/final.h5 -> the last snapshot
                continue
            seen.add(real)
            if name.endswith(".h5") and h5py is not None:
                classify_h5(p, run)
            elif name.endswith(".audit.json"):
                run.audit = run.audit or p
            elif name.endswith(".json"):
                try:
                    with open(p) as f:
                        j = json.load(f)
                    if isinstance(j, dict) and j.get("format") == "ssdem-analyse.summary":
                        run.analysis = run.analysis or p
                    elif name.endswith(".timing.json") or (isinstance(j, dict) and "stage" in j and "wall_s" in j):
                        run.timings.append(p)
                except Exception:
                    pass
            elif name in ("timings.csv", "times.csv") or name.endswith(".time"):
                run.timings.append(p)
            elif name.endswith("_series.csv") and run.mpm_series is None:
                try:
                    with open(p) as f:
                        if "internal_J" in f.readline():
                            run.mpm_series = p
                except OSError:
                    pass
            elif name.endswith(".toml"):
                run.scenes.append(p)
    # explicit options win
    if args.mpm:
        run.mpm = [(read_time(p), p) for p in args.mpm]
    if args.spheres:
        run.nbody = [(read_time(p), p) for p in args.spheres]
    if args.handoff:
        run.handoff = [(0.0, args.handoff)]
    if args.audit:
        run.audit = args.audit
    if args.analysis:
        run.analysis = args.analysis
    if args.timings:
        run.timings = list(args.timings)
    if args.scene:
        run.scenes = list(args.scene)
    for lst in (run.mpm, run.handoff, run.nbody):
        lst.sort()
    return run


def read_time(path):
    try:
        with h5py.File(path, "r") as f:
            return float(h5_attr(f, "time", 0.0))
    except Exception:
        return 0.0
