#!/usr/bin/env bash
# mpm-frag checkpoints on MPI end to end (label mpi): a run on NP ranks stopped at half time, or
# after step 50 between two snapshots (its checkpoint at the end), and continued with --restart on
# NP ranks writes a final snapshot bit-identical to the uninterrupted NP-rank run (h5diff,
# provenance excluded) and the same series;
# continued on each of the rank counts M given (1: the serial driver), the final snapshot agrees
# with it to 1e-6 in every value (h5diff -d; tests/mpm/mpi/test_mpm_mpi_restart.cpp has the tight
# per-field tolerances); a one-rank checkpoint continues on NP ranks likewise.
# Usage: app_mpi_restart.sh <mpm-frag> <scene> <NP> "<M...>" <mpirun...>
set -euo pipefail
exe=$1 scene=$2 np=$3 ms=$4
shift 4
run=("$@")
w=$(mktemp -d "${TMPDIR:-/tmp}/mpm_app_mpi_restart.XXXXXX")
trap 'rm -rf "$w"' EXIT
common=(--scene "$scene" --quiet --set output.snapshot_interval=0.001 --set output.series_every=10)
fail() { echo "FAIL: $*" >&2; exit 1; }
mpm() { local n=$1 dir=$2 end=$3; shift 3; "${run[@]}" -np "$n" "$exe" "${common[@]}" --set "time.end=$end" --set "output.directory=\"$w/$dir\"" "$@"; }
final() { ls "$w/$1"/*_[0-9]*.h5 | sort | tail -1; }
mpm "$np" full 0.002
mpm "$np" half 0.001
ck="$(ls "$w"/half/*_checkpoint.h5)"
h5ls -r "$ck" | grep -q '^/mpm_state/mpi/rank' || fail "no /mpm_state/mpi in the $np-rank checkpoint"
mpm "$np" half 0.002 --restart "$ck"
ref="$(final full)"
[ "$(basename "$ref")" = "$(basename "$(final half)")" ] || fail "final snapshot step differs: $(basename "$ref") vs $(basename "$(final half)")"
h5diff --exclude-path /provenance "$ref" "$(final half)" >/dev/null || fail "restart $np -> $np: final snapshot not bit-identical"
cmp -s "$w"/full/*_series.csv "$w"/half/*_series.csv || fail "restart $np -> $np: series differs"
echo "restart $np -> $np ranks: final snapshot $(basename "$ref") and series bit-identical to the uninterrupted run"
# a checkpoint between snapshots (time.max_steps: the run stops after step 50 with a checkpoint)
mpm "$np" mid 0.002 --set time.max_steps=50
mpm "$np" mid 0.002 --restart "$(ls "$w"/mid/*_checkpoint.h5)"
h5diff --exclude-path /provenance "$ref" "$(final mid)" >/dev/null || fail "restart $np -> $np after step 50: final snapshot not bit-identical"
cmp -s "$w"/full/*_series.csv "$w"/mid/*_series.csv || fail "restart $np -> $np after step 50: series differs"
echo "restart $np -> $np ranks after step 50 (between snapshots): bit-identical"
for m in $ms; do
  mpm "$m" "r$m" 0.002 --restart "$ck"
  [ "$(basename "$ref")" = "$(basename "$(final "r$m")")" ] || fail "restart $np -> $m: final step differs"
  h5diff -d 1e-6 --exclude-path /provenance "$ref" "$(final "r$m")" >/dev/null || fail "restart $np -> $m: final snapshot differs by more than 1e-6"
  echo "restart $np -> $m ranks: final snapshot agrees with the uninterrupted $np-rank run to 1e-6"
done
# a one-rank (serial) checkpoint continued on NP ranks
mpm 1 one 0.001
mpm "$np" one 0.002 --restart "$(ls "$w"/one/*_checkpoint.h5)"
h5diff -d 1e-6 --exclude-path /provenance "$ref" "$(final one)" >/dev/null || fail "restart 1 -> $np: final snapshot differs by more than 1e-6"
echo "restart 1 -> $np ranks: final snapshot agrees with the uninterrupted $np-rank run to 1e-6"
