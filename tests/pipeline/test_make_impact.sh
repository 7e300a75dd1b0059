#!/usr/bin/env bash
# The impact pipeline's Make rules rebuild exactly what depends on a changed setting or a deleted
# intermediate file (issue 7): a tiny, slow impact (2 km cells, 10 m/s, 1 s of MPM, 30 s of N-body) is run
# once, then
#   1. a second `make` runs no stage,
#   2. deleting spheres.h5 reruns hand-off, N-body, analysis and report, not the fragment stage,
#   3. changing NBODY_SETS reruns the N-body stage and after, not the hand-off,
#   4. deleting one N-body snapshot reruns the N-body stage, not the hand-off,
#   5. changing an MPM setting (MPM_SETS) reruns everything.
# usage: test_make_impact.sh <repo root> <build dir> <work dir>
set -euo pipefail
root=$1; build=$2; work=$3
rm -rf "$work"; mkdir -p "$work"
run=$work/run
vars=(BUILD="$build" RUN="$run" CELL=2000 IMPACTOR_DIAMETER=4000 IMPACT_SPEED=10 MPM_TIME=1 SNAP_INTERVAL=0.5 COARSEN=1
      NBODY_TIME=30 'NBODY_TIMES=[15.0, 30.0]')
nb='--set time.steps_per_contact=10 --set time.min_steps_per_contact=10'
mk() { make -s -C "$root/pipelines" impact "${vars[@]}" "$@" > "$work/make.log" 2>&1 || { cat "$work/make.log"; exit 1; }; }
mt() { stat -c '%.9Y' "$1"; }
fail() { echo "FAIL: $*"; exit 1; }
files=(fragment/done spheres.h5 nbody/done analysis.json report.md)
snap() { for f in "${files[@]}"; do echo "$f $(mt "$run/$f")"; done; }
changed() {  # changed <before> <after> <file>: 1 if the mtime of file differs
  [ "$(grep "^$3 " <<< "$1")" != "$(grep "^$3 " <<< "$2")" ]
}
expect() {  # expect <before> <after> <list of files that must change>; all others must not
  local b=$1 a=$2; shift 2
  for f in "${files[@]}"; do
    local want=0; for g in "$@"; do [ "$f" = "$g" ] && want=1; done
    if changed "$b" "$a" "$f"; then [ $want = 1 ] || fail "$f was rebuilt but should not have been";
    else [ $want = 0 ] || fail "$f was not rebuilt"; fi
  done
}

mk NBODY_SETS="$nb"
for f in "${files[@]}"; do [ -f "$run/$f" ] || fail "$f missing after the first run"; done
s0=$(snap)
sleep 1.1
mk NBODY_SETS="$nb"
s1=$(snap); expect "$s0" "$s1"
echo "ok: nothing rebuilt when nothing changed"

rm "$run/spheres.h5"; sleep 1.1
mk NBODY_SETS="$nb"
s2=$(snap); expect "$s1" "$s2" spheres.h5 nbody/done analysis.json report.md
echo "ok: deleting spheres.h5 rebuilt hand-off and after only"

sleep 1.1
mk NBODY_SETS="$nb --set gravity.theta=0.5"
s3=$(snap); expect "$s2" "$s3" nbody/done analysis.json report.md
echo "ok: a changed N-body setting reran the N-body stage and after only"

rm "$(head -n 1 "$run/nbody/done")"; sleep 1.1
mk NBODY_SETS="$nb --set gravity.theta=0.5"
s4=$(snap); expect "$s3" "$s4" nbody/done analysis.json report.md
echo "ok: deleting an N-body snapshot reran the N-body stage and after only"

sleep 1.1
mk NBODY_SETS="$nb --set gravity.theta=0.5" MPM_SETS="--set solver.courant=0.25"
s5=$(snap); expect "$s4" "$s5" fragment/done spheres.h5 nbody/done analysis.json report.md
echo "ok: a changed MPM setting reran every stage"
rm -rf "$work"
