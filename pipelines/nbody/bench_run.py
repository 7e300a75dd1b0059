"""One timed ssdem-grav run for the nbody benchmarks and studies (paper_bench, late_pile_bench,
chaos_floor): the scene plus --set overrides on OMP_NUM_THREADS threads, its output captured;
a failure ends the script naming the binary, its exit code and the end of its output.
Pure standard library."""
import os
import subprocess
import sys
import time


def timed_run(exe, scene, sets, threads, quiet=False):
    """Run `exe --scene scene --set s ...`; returns (wall seconds, stdout + stderr)."""
    args = [exe, "--scene", scene] + (["-q"] if quiet else [])
    for s in sets:
        args += ["--set", s]
    env = dict(os.environ, OMP_NUM_THREADS=str(threads))
    t0 = time.perf_counter()
    p = subprocess.run(args, capture_output=True, text=True, env=env)
    wall = time.perf_counter() - t0
    out = p.stdout + p.stderr
    if p.returncode != 0:
        sys.exit(f"{exe} failed ({p.returncode}):\n{out[-3000:]}")
    return wall, out


def bench_sets(spheres, t_end, outdir):
    """Overrides every benchmark run shares: input, end time, output directory, no snapshots or
    wall-clock checkpoints in the timed region."""
    return [f'initial.file="{spheres}"', f"time.end={t_end}", f'output.directory="{outdir}"',
            "output.checkpoint_wall=0", "output.times=[]", "output.snapshot_interval=0"]
