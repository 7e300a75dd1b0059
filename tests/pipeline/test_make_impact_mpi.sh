#!/usr/bin/env bash
# The impact pipeline on MPI ranks (issue 19: `make -C pipelines impact BUILD=<MPI build> MPI_RANKS=N`,
# pipelines/impact/rules.mk "cluster runs"), on a tiny impact (2 km cells, a 4 km impactor at
# 3 km/s, 1 s of MPM, 30 s of N-body; seconds):
#   1. with MPI_RANKS=2 the fragment and reaccumulate stages run on 2 ranks (timing/<stage>.json
#      records mpi_ranks 2, run_info.txt "MPI ranks: 2") and the run completes (analysis, report);
#   2. against the same impact as one process (MPI_RANKS=0, the same binaries): the hand-off's
#      sphere count equal, M_LR/M_PB and beta within 1e-4 relative (mpm-frag's rank count changes
#      only the round-off of its shared-node sums, which the fracture run amplifies: measured
#      M_LR/M_PB equal, beta 7.7e-6; ssdem-grav's results are the same bits on any rank count);
#   3. MPI_RANKS with a BUILD that is not an MPI build is refused, naming build-mpi.
# usage: test_make_impact_mpi.sh <repo root> <MPI build dir> <work dir> <MPI launch prefix...>
set -euo pipefail
root=$1; build=$2; work=$3; shift 3
launch="$*"
rm -rf "$work"; mkdir -p "$work"
vars=(BUILD="$build" CELL=2000 IMPACTOR_DIAMETER=4000 IMPACT_SPEED=3000 MPM_TIME=1 SNAP_INTERVAL=0.5 COARSEN=1
      NBODY_TIME=30 'NBODY_TIMES=[15.0, 30.0]' NBODY_SETS="--set time.steps_per_contact=10 --set time.min_steps_per_contact=10")
fail() { echo "FAIL: $*"; exit 1; }
make -s -C "$root/pipelines" impact "${vars[@]}" RUN="$work/np2" MPI_RANKS=2 MPI_LAUNCH="$launch" \
  > "$work/np2.log" 2>&1 || { cat "$work/np2.log"; fail "the 2-rank pipeline failed"; }
make -s -C "$root/pipelines" impact "${vars[@]}" RUN="$work/np0" MPI_RANKS=0 > "$work/np0.log" 2>&1 \
  || { cat "$work/np0.log"; fail "the one-process pipeline failed"; }
for f in analysis.json report.md; do [ -f "$work/np2/$f" ] || fail "np2: $f missing"; done
grep -q '"mpi_ranks": 2' "$work/np2/timing/fragment.json" || fail "fragment.json does not record 2 ranks"
grep -q '"mpi_ranks": 2' "$work/np2/timing/reaccumulate.json" || fail "reaccumulate.json does not record 2 ranks"
grep -q '"mpi_ranks": 0' "$work/np2/timing/handoff.json" || fail "the hand-off ran on ranks"
grep -q 'MPI ranks: 2' "$work/np2/nbody/run_info.txt" || fail "ssdem-grav did not run on 2 ranks"
/usr/bin/python3 - "$work" <<'PY'
import json, sys
import h5py
w = sys.argv[1]
def fail(m): print("FAIL:", m); sys.exit(1)
n = [h5py.File(f"{w}/{r}/spheres.h5")["spheres/id"].shape[0] for r in ("np2", "np0")]
if n[0] != n[1]: fail(f"hand-off spheres {n[0]} on 2 ranks, {n[1]} on one")
a, b = (json.load(open(f"{w}/{r}/analysis.json"))["final"] for r in ("np2", "np0"))
for k in ("M_LR_over_M_PB", "beta"):
    d = abs(a[k] - b[k]) / max(abs(b[k]), 1e-300)
    print(f"{k}: 2 ranks {a[k]!r}, one process {b[k]!r}, relative difference {d:.3g}")
    if not d <= 1e-4: fail(f"{k} differs by {d:.3g}")
print(f"ok: {n[0]} spheres; the 2-rank pipeline agrees with one process")
PY
# a BUILD that is not an MPI build
mkdir -p "$work/serial-build" && echo "SUITE_MPI:BOOL=OFF" > "$work/serial-build/CMakeCache.txt"
if make -s -C "$root/pipelines" impact "${vars[@]}" BUILD="$work/serial-build" RUN="$work/bad" MPI_RANKS=2 \
  > "$work/bad.log" 2>&1; then fail "MPI_RANKS with a serial BUILD was accepted"; fi
grep -q "needs an MPI build" "$work/bad.log" || { cat "$work/bad.log"; fail "no message naming the MPI build"; }
echo "ok: MPI_RANKS with a serial BUILD refused"
