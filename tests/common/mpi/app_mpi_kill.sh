#!/usr/bin/env bash
# A killed rank (label mpi), for ssdem-grav and mpm-frag alike: one of NP ranks gets SIGKILL (no
# chance to checkpoint or clean up) in the middle of a run whose output directory holds a
# complete earlier run.
# - mpirun ends the whole job with a non-zero exit;
# - the directory still holds exactly the earlier run, byte for byte (nothing published, nothing
#   half-written; the killed run's files stay in its staging directory, common/run_dir.hpp);
# - the killed run's last periodic checkpoint is a complete file, and its continuation with
#   --restart on NP2 ranks publishes a final snapshot and checkpoint bit-identical to an
#   uninterrupted NP2-rank run, and leaves no staging directory.
# Usage: app_mpi_kill.sh <exe> <scene> <NP> <NP2> <CKPT> <SNAPS> <EARLY> <LONG> <END> "<SETS>" <mpirun...>
#   CKPT, SNAPS: file-name globs of the checkpoint and the snapshots; EARLY, LONG, END: time.end
#   of the earlier run, the killed run and the continuation; SETS: further --set key=value pairs
#   (snapshot interval, checkpoint_every).
set -euo pipefail
exe=$1 scene=$2 np=$3 np2=$4 ckpt=$5 snaps=$6 early=$7 long=$8 end=$9 sets=${10}
shift 10
run=("$@")
w=$(mktemp -d "${TMPDIR:-/tmp}/app_mpi_kill.XXXXXX")
mpirun_pid=
cleanup() {
  [ -n "$mpirun_pid" ] && kill -KILL "$mpirun_pid" 2>/dev/null || true
  rm -rf "$w"
}
trap cleanup EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
. "$(dirname "$0")/../mpi_signal_rank.sh"
common=(--scene "$scene" --quiet)
for kv in $sets; do common+=(--set "$kv"); done
d="$w/d"
tool() { local n=$1 t=$2 dir=$3; shift 3; "${run[@]}" -np "$n" "$exe" "${common[@]}" --set "time.end=$t" --set "output.directory=\"$dir\"" "$@"; }
# a complete earlier run in the directory, and a copy of it to compare with
tool "$np" "$early" "$d"
cp -a "$d" "$w/before"
# a long run into the same directory, killed once its staging directory holds a checkpoint
# (mpirun itself in the background, not a function's subshell: its children are the ranks)
"${run[@]}" -np "$np" "$exe" "${common[@]}" --set "time.end=$long" --set "output.directory=\"$d\"" &
mpirun_pid=$!
kill_rank_after "$d/.staging-*/$ckpt" "$mpirun_pid" || fail "no checkpoint in the staging directory within 60 s, or no rank to kill"
rc=$mpirun_rc
mpirun_pid=
[ "$rc" -ne 0 ] || fail "mpirun exited 0 after a rank was killed"
# the earlier run untouched (the killed run's staging directory and the lock file aside)
diff -r --exclude='.staging-*' --exclude=.lock "$w/before" "$d" >/dev/null || fail "the earlier run's files changed"
# the checkpoint is complete (written to a temporary and renamed) and continues on NP2 ranks
ck=$(ls $d/.staging-*/$ckpt | head -1)
h5dump -H "$ck" >/dev/null || fail "$ck is not a readable HDF5 file"
tool "$np2" "$end" "$d" --restart "$ck"
tool "$np2" "$end" "$w/full"
last=$(basename "$(ls $w/full/$snaps | tail -1)")
[ -f "$d/$last" ] || fail "the continued run did not publish $last"
h5diff --exclude-path /provenance "$w/full/$last" "$d/$last" >/dev/null || fail "continued run: $last differs"
ckn=$(basename "$ck")
h5diff --exclude-path /provenance "$w/full/$ckn" "$d/$ckn" >/dev/null || fail "continued run: the checkpoint differs"
! ls -d "$d"/.staging-* >/dev/null 2>&1 || fail "staging directory left after the continued run published"
echo "SIGKILL to one of $np ranks of $(basename "$exe"): mpirun exit $rc, the earlier run kept byte for byte; the killed run's checkpoint continued on $np2 ranks to $last bit-identical to an uninterrupted run"
