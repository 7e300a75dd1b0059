#!/usr/bin/env bash
# A long stage that is interrupted continues from its checkpoint when the same `make` is run again
# (pipelines/impact/resume.sh). A tiny, slow impact (2 km cells, 10 m/s) is run once uninterrupted
# (the reference), then
#   1. mpm-frag alone gets SIGTERM after its first checkpoint; make again: the fragment stage
#      continues from a step before its last and its snapshots, series and `done` list equal the
#      reference's bit for bit;
#   2. ssdem-grav alone gets SIGKILL; make again: the N-body stage continues from a step before its
#      last; every snapshot and the series (but its wall-time column) and the analysis equal the
#      reference's;
#   3. killed again and its checkpoint damaged (truncated): the tool refuses it, naming it, and the
#      stage runs from the start to the same result;
#   4. killed again, then make with a later NBODY_TIME: the checkpoint is older than the changed
#      settings, so the stage runs from the start, to the new end;
#   5. a fresh run (with a copy of the tools) killed in its N-body stage, every tool then rebuilt
#      (touched) and its checkpoint marked as written by another build: make with
#      RESUME_ACROSS_BUILDS=1 keeps the finished stages, continues the N-body from its
#      checkpoint, says that the checkpoint came from another build (log and run_info.txt), and,
#      the code being the same, gives the reference's result.
# usage: test_make_resume.sh <repo root> <build dir> <work dir>
set -euo pipefail
root=$1; build=$2; work=$3
rm -rf "$work"; mkdir -p "$work"
vars=(BUILD="$build" CELL=2000 IMPACTOR_DIAMETER=4000 IMPACT_SPEED=10 MPM_TIME=60 SNAP_INTERVAL=20 COARSEN=1
      'NBODY_TIMES=[150.0, 300.0]' "MPM_SETS=--set output.checkpoint_every=20")
nb=(NBODY_SETS='--set time.steps_per_contact=10 --set time.min_steps_per_contact=10 --set output.checkpoint_every=400')
fail() { echo "FAIL: $*"; exit 1; }
mk() {  # mk <run> <log> [vars]: make impact, fail with its log on error
  local run=$1 log=$2; shift 2
  make -s -C "$root/pipelines" impact "${vars[@]}" "${nb[@]}" RUN="$run" "$@" > "$log" 2>&1 || { cat "$log"; fail "make failed"; }
}
# interrupt <signal> <run> <stage dir> <checkpoint> <tool> [vars]: start make; once the tool's
# interrupted-run checkpoint exists, send <signal> to the tool alone (not to make, timed.sh or
# resume.sh); make must fail and the stage's `done` must stay as it was.
interrupt() {
  local sig=$1 run=$2 dir=$3 ck=$4 tool=$5; shift 5
  local before; before=$(stat -c '%.9Y' "$run/$dir/done" 2> /dev/null || echo none)
  make -s -C "$root/pipelines" impact "${vars[@]}" "${nb[@]}" RUN="$run" "$@" > "$work/killed.log" 2>&1 &
  local mpid=$! i
  for i in $(seq 1 6000); do
    compgen -G "$run/$dir/.staging-*/$ck" > /dev/null && break
    kill -0 $mpid 2> /dev/null || { cat "$work/killed.log"; fail "make ended before $tool wrote a checkpoint"; }
    sleep 0.01
  done
  pkill "-$sig" -f "^[^ ]*/$tool .*$run/$dir" || fail "no $tool process to signal"
  if wait $mpid; then fail "make succeeded although $tool was interrupted"; fi
  [ "$(stat -c '%.9Y' "$run/$dir/done" 2> /dev/null || echo none)" = "$before" ] || fail "$dir/done written by an interrupted run"
  return 0
}
restart_step() { grep -Eo "restarted from .* at step [0-9]+" "$1" | grep -Eo "[0-9]+$" | tail -n 1; }
same() {  # same <ref dir> <run dir> <done file> <series file> <wall column or ''>: outputs equal
  /usr/bin/python3 - "$@" <<'PY'
import sys, h5py, numpy as np
ref, run, done, series, wall = sys.argv[1:]
a, b = [open(f"{d}/{done}").read().split() for d in (ref, run)]
assert [p.split("/")[-1] for p in a] == [p.split("/")[-1] for p in b], (a, b)
n = 0
for pa, pb in zip(a, b):
    with h5py.File(pa) as fa, h5py.File(pb) as fb:
        names = []
        fa.visititems(lambda k, o: names.append(k) if isinstance(o, h5py.Dataset) and not k.startswith("provenance") else None)
        for k in names:
            assert np.array_equal(fa[k][()], fb[k][()]), (pb, k)
            n += 1
ra, rb = [np.genfromtxt(f"{d}/{series}", delimiter=",", names=True) for d in (ref, run)]
cols = [c for c in ra.dtype.names if c != wall]
assert len(ra) == len(rb) and len(ra) > 2, (len(ra), len(rb))
for c in cols:
    assert np.array_equal(ra[c], rb[c]), (series, c)
print(f"{done}: {len(a)} files, {n} datasets and {len(ra)} series rows equal bit for bit")
PY
}
last_step() {  # last_step <done file> <pattern>: the step in the name of the last matching file
  local f; f=$(basename "$(grep -E "$2" "$1" | tail -n 1)" .h5)
  echo $((10#${f##*_}))
}

ref=$work/ref run=$work/run
mk "$ref" "$work/ref.log" NBODY_TIME=300

interrupt TERM "$run" fragment frag_checkpoint.h5 mpm-frag NBODY_TIME=300
mk "$run" "$work/resume1.log" NBODY_TIME=300
grep -q "resume.sh: continuing the interrupted run from $run/fragment/.staging-" "$work/resume1.log" ||
  { cat "$work/resume1.log"; fail "the fragment stage did not resume"; }
s=$(restart_step "$work/resume1.log"); e=$(last_step "$run/fragment/done" 'frag_[0-9]+\.h5')
[ -n "$s" ] && [ "$s" -gt 0 ] && [ "$s" -lt "$e" ] || fail "mpm-frag restarted at step '$s', not between 0 and its last step $e"
same "$ref" "$run" fragment/done fragment/frag_series.csv '' || fail "the resumed fragment stage differs from the uninterrupted one"
echo "ok: mpm-frag after SIGTERM continued from step $s of $e, bit-identical"

interrupt KILL "$run" nbody checkpoint.h5 ssdem-grav NBODY_TIME=300 NBODY_TIMES='[150.0, 299.0]'
# the same settings as the reference: make reruns the N-body stage for the changed output times
mk "$run" "$work/resume2.log" NBODY_TIME=300 NBODY_TIMES='[150.0, 299.0]'
grep -q "resume.sh: continuing the interrupted run from $run/nbody/.staging-" "$work/resume2.log" ||
  { cat "$work/resume2.log"; fail "the N-body stage did not resume"; }
s=$(restart_step "$run/nbody/run_info.txt"); e=$(last_step "$run/nbody/done" 'snap_[0-9]+\.h5')
[ -n "$s" ] && [ "$s" -gt 0 ] && [ "$s" -lt "$e" ] || fail "ssdem-grav restarted at step '$s', not between 0 and its last step $e"
compgen -G "$run/nbody/.staging-*" > /dev/null && fail "a staging directory is left after the resumed run published"
grep -q "was written by" "$run/nbody/run_info.txt" && fail "a restart by the same build says the checkpoint came from another"
mk "$ref" "$work/ref2.log" NBODY_TIME=300 NBODY_TIMES='[150.0, 299.0]'
same "$ref" "$run" nbody/done nbody/series.csv wall_s || fail "the resumed N-body stage differs from the uninterrupted one"
cmp <(/usr/bin/python3 -c 'import json,sys; j=json.load(open(sys.argv[1]))["final"]; j.pop("file"); print(j)' "$ref/analysis.json") \
    <(/usr/bin/python3 -c 'import json,sys; j=json.load(open(sys.argv[1]))["final"]; j.pop("file"); print(j)' "$run/analysis.json") ||
  fail "the analyses differ"
echo "ok: ssdem-grav after SIGKILL continued from step $s of $e, bit-identical"

interrupt KILL "$run" nbody checkpoint.h5 ssdem-grav NBODY_TIME=300
ck=$(ls -t "$run"/nbody/.staging-*/checkpoint.h5 | head -n 1)
truncate -s 20000 "$ck"
mk "$run" "$work/resume3.log" NBODY_TIME=300
grep -q "resume.sh: the tool refused $ck" "$work/resume3.log" || { cat "$work/resume3.log"; fail "the damaged checkpoint was not refused"; }
grep -q "$ck: corrupt or unreadable" "$work/resume3.log" || fail "no message naming the damaged checkpoint"
compgen -G "$run/nbody/.staging-*" > /dev/null && fail "the refused run's staging directory is left after publishing"
mk "$ref" "$work/ref3.log" NBODY_TIME=300
same "$ref" "$run" nbody/done nbody/series.csv wall_s || fail "the rerun differs from the uninterrupted one"
echo "ok: a damaged checkpoint was refused and the stage ran from the start"

interrupt KILL "$run" nbody checkpoint.h5 ssdem-grav NBODY_TIME=300 NBODY_TIMES='[150.0, 298.0]'
mk "$run" "$work/resume4.log" NBODY_TIME=320 NBODY_TIMES='[150.0, 320.0]'
grep -q "resume.sh: not continuing .*/.vars/NBODY is newer" "$work/resume4.log" || { cat "$work/resume4.log"; fail "a checkpoint older than the settings was continued"; }
grep -q "restarted from" "$run/nbody/run_info.txt" && fail "run_info says restarted"
/usr/bin/python3 -c 'import h5py,sys; t=float(h5py.File(sys.argv[1])["/"].attrs["time"]); assert 320 <= t < 321, t' \
  "$(tail -n 1 "$run/nbody/done")" || fail "the rerun did not reach the new end"
echo "ok: changed settings ran the stage from the start"

tools=$work/tools run5=$work/run5
mkdir -p "$tools/mpm" "$tools/handoff" "$tools/nbody/analysis"
for t in mpm/mpm-frag handoff/mpm2spheres nbody/ssdem-grav nbody/analysis/ssdem-analyse; do cp -p "$build/$t" "$tools/$t"; done
interrupt KILL "$run5" nbody checkpoint.h5 ssdem-grav NBODY_TIME=300 BUILD="$tools"
frag=$(stat -c '%.9Y' "$run5/fragment/done"); handoff=$(stat -c '%.9Y' "$run5/spheres.h5")
ck=$(ls -t "$run5"/nbody/.staging-*/checkpoint.h5 | head -n 1)
/usr/bin/python3 -c 'import h5py,sys; h5py.File(sys.argv[1], "r+")["provenance"].attrs["git_sha"] = "0000000other"' "$ck"
sleep 1; touch "$tools"/mpm/mpm-frag "$tools"/handoff/mpm2spheres "$tools"/nbody/ssdem-grav "$tools"/nbody/analysis/ssdem-analyse
mk "$run5" "$work/resume5.log" NBODY_TIME=300 BUILD="$tools" RESUME_ACROSS_BUILDS=1
grep -q "resume.sh: continuing the interrupted run from $ck" "$work/resume5.log" ||
  { cat "$work/resume5.log"; fail "the N-body stage did not continue across the rebuilt tools"; }
[ "$(stat -c '%.9Y' "$run5/fragment/done")" = "$frag" ] || fail "the finished fragment stage was rerun for a rebuilt tool"
[ "$(stat -c '%.9Y' "$run5/spheres.h5")" = "$handoff" ] || fail "the finished hand-off was rerun for a rebuilt tool"
grep -q "restart: checkpoint $ck was written by ssdem-grav .*(git 0000000other)" "$work/resume5.log" ||
  { cat "$work/resume5.log"; fail "no warning that the checkpoint came from another build"; }
grep -q "was written by ssdem-grav .*(git 0000000other)" "$run5/nbody/run_info.txt" || fail "run_info.txt does not record the other build"
same "$ref" "$run5" nbody/done nbody/series.csv wall_s || fail "the continued N-body stage differs from the uninterrupted one"
echo "ok: RESUME_ACROSS_BUILDS=1 continued across rebuilt tools, recorded the other build, same result"
rm -rf "$work"
