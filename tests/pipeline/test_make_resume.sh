#!/usr/bin/env bash
# A long stage that is killed continues from its checkpoint when the same `make` is run again
# (pipelines/impact/resume.sh): a tiny, slow impact (2 km cells, 10 m/s) is run
#   1. with mpm-frag killed (SIGKILL) after its first checkpoint, then make again: the fragment
#      stage resumes;
#   2. with ssdem-grav killed after its first checkpoint, then make again: the N-body stage
#      resumes, and its final snapshot and the analysis equal those of an uninterrupted run bit
#      for bit;
#   3. a make with a changed N-body setting beside a killed run's checkpoint: the tool refuses the
#      other run's checkpoint and the stage runs from the start.
# usage: test_make_resume.sh <repo root> <build dir> <work dir>
set -euo pipefail
root=$1; build=$2; work=$3
rm -rf "$work"; mkdir -p "$work"
vars=(BUILD="$build" CELL=2000 IMPACTOR_DIAMETER=4000 IMPACT_SPEED=10 MPM_TIME=60 SNAP_INTERVAL=30 COARSEN=1
      NBODY_TIME=300 'NBODY_TIMES=[150.0, 300.0]' "MPM_SETS=--set output.checkpoint_every=20")
nb='--set time.steps_per_contact=10 --set time.min_steps_per_contact=10 --set output.checkpoint_every=400'
fail() { echo "FAIL: $*"; exit 1; }
mk() {  # mk <run> <log> [vars]: make impact, fail with its log on error
  local run=$1 log=$2; shift 2
  make -s -C "$root/pipelines" impact "${vars[@]}" RUN="$run" "$@" > "$log" 2>&1 || { cat "$log"; fail "make failed"; }
}
# kill_after_checkpoint <run> <stage dir> <checkpoint> <tool> [vars]: start make, SIGKILL the tool
# once an interrupted-run checkpoint exists in <stage dir>'s staging directory, wait for make.
kill_after_checkpoint() {
  local run=$1 dir=$2 ck=$3 tool=$4; shift 4
  local before; before=$(stat -c '%.9Y' "$run/$dir/done" 2> /dev/null || echo none)
  make -s -C "$root/pipelines" impact "${vars[@]}" RUN="$run" "$@" > "$work/killed.log" 2>&1 &
  local mpid=$! i
  for i in $(seq 1 6000); do
    compgen -G "$run/$dir/.staging-*/$ck" > /dev/null && break
    kill -0 $mpid 2> /dev/null || { cat "$work/killed.log"; fail "make ended before $tool wrote a checkpoint"; }
    sleep 0.01
  done
  pkill -KILL -f "$tool.*$run/$dir" || fail "no $tool process to kill"
  if wait $mpid; then fail "make succeeded although $tool was killed"; fi
  [ "$(stat -c '%.9Y' "$run/$dir/done" 2> /dev/null || echo none)" = "$before" ] || fail "$dir/done written by a killed run"
  return 0
}

ref=$work/ref
mk "$ref" "$work/ref.log" NBODY_SETS="$nb"

run=$work/run
kill_after_checkpoint "$run" fragment frag_checkpoint.h5 mpm-frag NBODY_SETS="$nb"
mk "$run" "$work/resume1.log" NBODY_SETS="$nb"
grep -q "resume.sh: continuing the interrupted run from $run/fragment/.staging-" "$work/resume1.log" ||
  { cat "$work/resume1.log"; fail "the fragment stage did not resume"; }
grep -Eq "restarted from .* at step [1-9]" "$work/resume1.log" || fail "mpm-frag did not continue from a later step"
echo "ok: a killed fragment stage continued from its checkpoint"

# the N-body stage alone: a changed setting reruns it (and what follows) from the hand-off
nb2="$nb --set gravity.theta=0.5"
mk "$ref" "$work/ref2.log" NBODY_SETS="$nb2"
kill_after_checkpoint "$run" nbody checkpoint.h5 ssdem-grav NBODY_SETS="$nb2"
mk "$run" "$work/resume2.log" NBODY_SETS="$nb2"
grep -q "resume.sh: continuing the interrupted run from $run/nbody/.staging-" "$work/resume2.log" ||
  { cat "$work/resume2.log"; fail "the N-body stage did not resume"; }
grep -Eq "^restarted from .* at step [1-9]" "$run/nbody/run_info.txt" || fail "ssdem-grav did not continue from a later step"
compgen -G "$run/nbody/.staging-*" > /dev/null && fail "a staging directory is left after the resumed run published"
/usr/bin/python3 - "$ref" "$run" <<'PY' || fail "the resumed run differs from the uninterrupted one"
import sys, json, h5py, numpy as np
ref, run = sys.argv[1:]
a, b = [open(d + "/nbody/done").read().split() for d in (ref, run)]
assert [p.split("/")[-1] for p in a] == [p.split("/")[-1] for p in b], (a, b)
with h5py.File(a[-1]) as fa, h5py.File(b[-1]) as fb:
    n = 0
    def cmp(name, obj):
        global n
        if isinstance(obj, h5py.Dataset) and not name.startswith("provenance"):
            assert np.array_equal(obj[()], fb[name][()]), name
            n += 1
    fa.visititems(cmp)
    assert n >= 5, n
ja, jb = [json.load(open(d + "/analysis.json"))["final"] for d in (ref, run)]
for j in (ja, jb): j.pop("file")
assert ja == jb, (ja, jb)
print("final snapshot: %d datasets equal bit for bit" % n)
PY
echo "ok: a killed N-body stage continued from its checkpoint, bit-identical to an uninterrupted run"

kill_after_checkpoint "$run" nbody checkpoint.h5 ssdem-grav NBODY_SETS="$nb --set gravity.theta=0.4"
mk "$run" "$work/resume3.log" NBODY_SETS="$nb --set gravity.theta=0.45"
grep -q "resume.sh: the tool refused" "$work/resume3.log" || { cat "$work/resume3.log"; fail "another run's checkpoint was not refused"; }
grep -q "checkpoint of another run" "$work/resume3.log" || { cat "$work/resume3.log"; fail "no message naming the refused checkpoint"; }
compgen -G "$run/nbody/.staging-*" > /dev/null && fail "the refused run's staging directory is left after publishing"
echo "ok: another run's checkpoint was refused and the stage ran from the start"
rm -rf "$work"
