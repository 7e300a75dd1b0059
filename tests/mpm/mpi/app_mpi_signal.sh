#!/usr/bin/env bash
# SIGTERM on MPI ranks end to end (label mpi): one of NP mpm-frag ranks gets SIGTERM early in a
# long run; every rank must checkpoint after the same step and the run exit 143 (128 + SIGTERM).
# The checkpoint (step K) continued with --restart on NP ranks to step K + 30 (time.max_steps)
# must write a final snapshot bit-identical to an uninterrupted NP-rank run to step K + 30. The
# interrupted run's files stay in its staging directory; the continuation adopts it and publishes.
# Usage: app_mpi_signal.sh <mpm-frag> <scene> <NP> <mpirun...>
set -euo pipefail
exe=$1 scene=$2 np=$3
shift 3
run=("$@")
w=$(mktemp -d "${TMPDIR:-/tmp}/mpm_app_mpi_signal.XXXXXX")
trap 'rm -rf "$w"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
. "$(dirname "$0")/../../common/mpi_signal_rank.sh"
common=(--scene "$scene" --quiet --set time.end=0.03 --set output.snapshot_interval=0.01)
"${run[@]}" -np "$np" "$exe" "${common[@]}" --set "output.directory=\"$w/sig\"" &
mpirun_pid=$!
for _ in $(seq 1 600); do  # the initial snapshot: the ranks are stepping
  ls "$w"/sig/.staging-*/*_000000.h5 >/dev/null 2>&1 && break
  sleep 0.05
done
signal_one_rank TERM "$mpirun_pid" || fail "no rank process under mpirun $mpirun_pid"
rc=$mpirun_rc
[ "$rc" -eq 143 ] || fail "exit $rc after SIGTERM, expected 143"
! ls "$w"/sig/*.h5 >/dev/null 2>&1 || fail "the interrupted run published files in its output directory"
ck="$(ls "$w"/sig/.staging-*/*_checkpoint.h5)"  # the interrupted run's files stay in its staging directory
k=$(h5dump -a /mpm_state/step "$ck" | sed -n 's/.*(0): \([0-9]*\).*/\1/p')
[ -n "$k" ] && [ "$k" -gt 0 ] || fail "no step in $ck"
"${run[@]}" -np "$np" "$exe" "${common[@]}" --set "output.directory=\"$w/sig\"" --set "time.max_steps=$((k + 30))" --restart "$ck"
"${run[@]}" -np "$np" "$exe" "${common[@]}" --set "output.directory=\"$w/full\"" --set "time.max_steps=$((k + 30))"
f=$(printf '%s_%06d.h5' "$(basename "$(ls "$w"/full/*_series.csv)" _series.csv)" $((k + 30)))
[ -f "$w/full/$f" ] && [ -f "$w/sig/$f" ] || fail "no snapshot $f"
h5diff --exclude-path /provenance "$w/full/$f" "$w/sig/$f" >/dev/null || fail "restart after SIGTERM: $f not bit-identical"
echo "SIGTERM to one of $np ranks: every rank checkpointed at step $k, exit 143; continued to step $((k + 30)) bit-identically"
