"""Which HDF5 files of a run directory are snapshots: one rule for the report (its MPM and N-body
snapshot lists) and the impact figures (the stages' `done` lists, which name every output)."""
import os


def is_snapshot(path):
    """False for restart checkpoints (mpm-frag's <prefix>_checkpoint.h5, ssdem-grav's checkpoint.h5:
    they repeat a state), mpm-frag's outflow file (<prefix>_outflow.h5: only the material that left
    the grid, stamped with the end time) and failed-state dumps."""
    b = os.path.basename(path)
    return not ("checkpoint" in b or b.endswith("_outflow.h5") or "failed" in b)
