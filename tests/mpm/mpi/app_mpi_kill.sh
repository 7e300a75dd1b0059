#!/usr/bin/env bash
# A killed rank (label mpi): one of NP mpm-frag ranks gets SIGKILL (no chance to checkpoint or
# clean up) in the middle of a run whose output directory holds a complete earlier run.
# - mpirun ends the whole job with a non-zero exit;
# - the directory still holds exactly the earlier run, byte for byte (nothing published, nothing
#   half-written; the killed run's files stay in its staging directory, mpm/run_directory.hpp);
# - the killed run's last periodic checkpoint is a complete file, and its continuation with
#   --restart on NP ranks publishes a final snapshot and checkpoint bit-identical to an
#   uninterrupted NP-rank run, and leaves no staging directory.
# Usage: app_mpi_kill.sh <mpm-frag> <scene> <NP> <mpirun...>
set -euo pipefail
exe=$1 scene=$2 np=$3
shift 3
run=("$@")
w=$(mktemp -d "${TMPDIR:-/tmp}/mpm_app_mpi_kill.XXXXXX")
mpirun_pid=
cleanup() {
  [ -n "$mpirun_pid" ] && kill -KILL "$mpirun_pid" 2>/dev/null || true
  rm -rf "$w"
}
trap cleanup EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
. "$(dirname "$0")/../../common/mpi_signal_rank.sh"
common=(--scene "$scene" --quiet --set output.snapshot_interval=0.001 --set output.checkpoint_every=100)
d="$w/d"
# a complete earlier run in the directory, and a copy of it to compare with
"${run[@]}" -np "$np" "$exe" "${common[@]}" --set time.end=0.002 --set "output.directory=\"$d\""
cp -a "$d" "$w/before"
# a long run into the same directory, killed once its staging directory holds a checkpoint
"${run[@]}" -np "$np" "$exe" "${common[@]}" --set time.end=1.0 --set "output.directory=\"$d\"" &
mpirun_pid=$!
ck=
for _ in $(seq 1 1200); do
  ck=$(ls "$d"/.staging-*/*_checkpoint.h5 2>/dev/null | head -1 || true)
  [ -n "$ck" ] && break
  kill -0 "$mpirun_pid" 2>/dev/null || fail "the long run ended before its first checkpoint"
  sleep 0.05
done
[ -n "$ck" ] || fail "no checkpoint in the staging directory after 60 s"
signal_one_rank KILL "$mpirun_pid" || fail "no rank process under mpirun $mpirun_pid"
rc=$mpirun_rc
mpirun_pid=
[ "$rc" -ne 0 ] || fail "mpirun exited 0 after a rank was killed"
# the earlier run untouched (the killed run's staging directory and the lock file aside)
diff -r --exclude='.staging-*' --exclude=.lock "$w/before" "$d" >/dev/null || fail "the earlier run's files changed"
# the checkpoint is complete (written to a temporary and renamed) and continues on NP ranks
ck=$(ls "$d"/.staging-*/*_checkpoint.h5 | head -1)
h5dump -H "$ck" >/dev/null || fail "$ck is not a readable HDF5 file"
k=$(h5dump -a /mpm_state/step "$ck" | sed -n 's/.*(0): \([0-9]*\).*/\1/p')
"${run[@]}" -np "$np" "$exe" "${common[@]}" --set time.end=0.006 --set "output.directory=\"$d\"" --restart "$ck"
"${run[@]}" -np "$np" "$exe" "${common[@]}" --set time.end=0.006 --set "output.directory=\"$w/full\""
last=$(basename "$(ls "$w"/full/*_[0-9]*.h5 | tail -1)")
[ -f "$d/$last" ] || fail "the continued run did not publish $last"
h5diff --exclude-path /provenance "$w/full/$last" "$d/$last" >/dev/null || fail "continued run: $last differs"
ckn=$(basename "$ck")
h5diff --exclude-path /provenance "$w/full/$ckn" "$d/$ckn" >/dev/null || fail "continued run: the checkpoint differs"
! ls -d "$d"/.staging-* >/dev/null 2>&1 || fail "staging directory left after the continued run published"
echo "SIGKILL to one of $np ranks: mpirun exit $rc, the earlier run kept byte for byte; the killed run's checkpoint (step $k) continued to $last bit-identical to an uninterrupted run"
