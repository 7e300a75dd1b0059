#!/usr/bin/env bash
# mpm-frag checkpoints on MPI end to end (label mpi): a run on NP ranks stopped at half time, or
# after step 50 between two snapshots (its checkpoint at the end), and continued with --restart on
# NP ranks writes a final snapshot bit-identical to the uninterrupted NP-rank run (h5diff,
# provenance excluded) and the same series;
# with outflow removal the outflow file too; continued on each of the rank counts M given (1: the
# serial driver), the final snapshot agrees with it to DELTA in every value (h5diff -d;
# tests/mpm/mpi/test_mpm_mpi_restart.cpp has the tight per-field tolerances); a one-rank
# checkpoint continues on NP ranks likewise. HALF, END, SNAP: times [s] (stop, end, snapshots).
# Usage: app_mpi_restart.sh <mpm-frag> <scene> <NP> "<M...>" <HALF> <END> <SNAP> <DELTA> <mpirun...>
set -euo pipefail
exe=$1 scene=$2 np=$3 ms=$4 half=$5 end=$6 snap=$7 delta=$8
shift 8
run=("$@")
w=$(mktemp -d "${TMPDIR:-/tmp}/mpm_app_mpi_restart.XXXXXX")
trap 'rm -rf "$w"' EXIT
common=(--scene "$scene" --quiet --set output.snapshot_interval=$snap --set output.series_every=10)
fail() { echo "FAIL: $*" >&2; exit 1; }
mpm() { local n=$1 dir=$2 end=$3; shift 3; "${run[@]}" -np "$n" "$exe" "${common[@]}" --set "time.end=$end" --set "output.directory=\"$w/$dir\"" "$@"; }
final() { ls "$w/$1"/*_[0-9]*.h5 | sort | tail -1; }
mpm "$np" full "$end"
mpm "$np" half "$half"
ck="$(ls "$w"/half/*_checkpoint.h5)"
h5ls -r "$ck" | grep -q '^/mpm_state/mpi/rank' || fail "no /mpm_state/mpi in the $np-rank checkpoint"
mpm "$np" half "$end" --restart "$ck"
ref="$(final full)"
[ "$(basename "$ref")" = "$(basename "$(final half)")" ] || fail "final snapshot step differs: $(basename "$ref") vs $(basename "$(final half)")"
h5diff --exclude-path /provenance "$ref" "$(final half)" >/dev/null || fail "restart $np -> $np: final snapshot not bit-identical"
cmp -s "$w"/full/*_series.csv "$w"/half/*_series.csv || fail "restart $np -> $np: series differs"
echo "restart $np -> $np ranks: final snapshot $(basename "$ref") and series bit-identical to the uninterrupted run"
for f in "$w"/full/*_outflow.h5; do
  [ -f "$f" ] || continue
  h5diff --exclude-path /provenance "$f" "$w/half/$(basename "$f")" >/dev/null || fail "restart $np -> $np: outflow file not bit-identical"
  echo "restart $np -> $np ranks: outflow file bit-identical ($(h5ls "$f/particles/id" | sed 's/.*{\([0-9]*\).*/\1/') particles)"
done
# a checkpoint between snapshots (time.max_steps: the run stops after step 50 with a checkpoint)
mpm "$np" mid "$end" --set time.max_steps=50
mpm "$np" mid "$end" --restart "$(ls "$w"/mid/*_checkpoint.h5)"
h5diff --exclude-path /provenance "$ref" "$(final mid)" >/dev/null || fail "restart $np -> $np after step 50: final snapshot not bit-identical"
cmp -s "$w"/full/*_series.csv "$w"/mid/*_series.csv || fail "restart $np -> $np after step 50: series differs"
echo "restart $np -> $np ranks after step 50 (between snapshots): bit-identical"
for m in $ms; do
  mpm "$m" "r$m" "$end" --restart "$ck"
  [ "$(basename "$ref")" = "$(basename "$(final "r$m")")" ] || fail "restart $np -> $m: final step differs"
  h5diff -d "$delta" --exclude-path /provenance "$ref" "$(final "r$m")" >/dev/null || fail "restart $np -> $m: final snapshot differs by more than $delta"
  echo "restart $np -> $m ranks: final snapshot agrees with the uninterrupted $np-rank run to $delta"
done
# a one-rank (serial) checkpoint continued on NP ranks
mpm 1 one "$half"
mpm "$np" one "$end" --restart "$(ls "$w"/one/*_checkpoint.h5)"
h5diff -d "$delta" --exclude-path /provenance "$ref" "$(final one)" >/dev/null || fail "restart 1 -> $np: final snapshot differs by more than $delta"
echo "restart 1 -> $np ranks: final snapshot agrees with the uninterrupted $np-rank run to $delta"
