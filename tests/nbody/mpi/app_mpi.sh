#!/usr/bin/env bash
# The MPI ssdem-grav end to end (label mpi): files written on NP ranks equal those of one rank
# (every dataset of every snapshot and of the checkpoint; series.csv except wall time), a
# checkpoint written on NP ranks restarts on NP2 ranks and reaches the one-rank end state bit for
# bit, each rank reading only its block of the checkpoint's rows (and a fresh start from a
# sphere file likewise, equal to one rank) unless the run has bonds. APP_MPI_SETS adds scene settings to every run (e.g. "--set time.multirate=true": then
# levels.csv must equal one rank's; with bonds.generate = true the snapshots' /bonds, the
# checkpoint's bond state and the four bond columns of series.csv must equal one rank's too).
# Usage: app_mpi.sh <ssdem-grav> <scene> <NP> <NP2> <mpirun...>
set -euo pipefail
exe=$1 scene=$2 np=$3 np2=$4
shift 4
run=("$@")
w=$(mktemp -d "${TMPDIR:-/tmp}/app_mpi.XXXXXX")
trap 'rm -rf "$w"' EXIT
read -r -a extra <<<"${APP_MPI_SETS:-}"
common=(--scene "$scene" --quiet --set output.snapshot_interval=50.0 "${extra[@]}")
fail() { echo "FAIL: $*" >&2; exit 1; }
# from_snapshot NP TAG WHAT [SETS...]: 20 s from the second snapshot of $w/one on one rank and on NP
# ranks ($w/TAG1, $w/TAGn); every HDF5 file and series.csv (but the wall time) must be equal;
# prints the snapshot's name.
from_snapshot() {
  local p=$1 tag=$2 what=$3
  shift 3
  local snap
  snap=$(ls "$w"/one/snap_*.h5 | head -2 | tail -1)
  local sets=(--scene "$scene" --quiet --set time.end=20.0 --set output.snapshot_interval=10.0
    --set initial.source=\"file\" --set "initial.file=\"$snap\"" "$@")
  "${run[@]}" -np 1 "$exe" "${sets[@]}" --set "output.directory=\"$w/${tag}1\"" >&2 || fail "one rank failed ($what)"
  "${run[@]}" -np "$p" "$exe" "${sets[@]}" --set "output.directory=\"$w/${tag}n\"" >&2 || fail "$p ranks failed ($what)"
  for f in "$w/${tag}1"/*.h5; do
    h5diff --exclude-path /provenance "$f" "$w/${tag}n/$(basename "$f")" >/dev/null ||
      fail "$(basename "$f") differs on $p ranks ($what)"
  done
  cmp <(cut -d, -f1-19,21- "$w/${tag}1/series.csv") <(cut -d, -f1-19,21- "$w/${tag}n/series.csv") >&2 ||
    fail "series.csv differs on $p ranks ($what)"
  basename "$snap"
}
# same files as one rank (h5diff: provenance holds the command line and output directory)
"${run[@]}" -np 1 "$exe" "${common[@]}" --set time.end=100.0 --set "output.directory=\"$w/one\""
"${run[@]}" -np "$np" "$exe" "${common[@]}" --set time.end=100.0 --set "output.directory=\"$w/many\""
n=0
for f in "$w"/one/*.h5; do
  h5diff --exclude-path /provenance "$f" "$w/many/$(basename "$f")" >/dev/null || fail "$(basename "$f") differs on $np ranks"
  n=$((n + 1))
done
[ "$n" -ge 3 ] || fail "expected snapshots and a checkpoint, found $n files"
# every column but the wall time (column 20)
cmp <(cut -d, -f1-19,21- "$w/one/series.csv") <(cut -d, -f1-19,21- "$w/many/series.csv") ||
  fail "series.csv differs on $np ranks"
grep -q "MPI ranks: $np" "$w/many/run_info.txt" || fail "run_info.txt lacks the rank count"
if [ -f "$w/one/levels.csv" ]; then  # multi-rate: spheres per level, promotions, evaluations
  cmp "$w/one/levels.csv" "$w/many/levels.csv" || fail "levels.csv differs on $np ranks"
  grep -q "multi-rate levels" "$w/many/run_info.txt" || fail "run_info.txt lacks the level report"
fi
if grep -q "bonds.generate=true" <<<"${APP_MPI_SETS:-}"; then  # bonds: some break, and the last line
  h5ls "$w/many/checkpoint.h5/ssdem_state/bonds" | grep -q released || fail "checkpoint lacks the bond state"
  broken=$(tail -1 "$w/many/series.csv" | awk -F, '{print $NF}')
  [ "$broken" -gt 0 ] || fail "no bond broke: the test needs broken bonds"
  grep "^bonds:" "$w/one/run_info.txt" | cmp - <(grep "^bonds:" "$w/many/run_info.txt") ||
    fail "run_info.txt's bond line differs on $np ranks"
  echo "$np ranks with bonds: $broken bonds broken at the end, as on one rank"
  # the bonds of an input file (bonds.from_file; a snapshot's /bonds with its broken flags)
  first=$(from_snapshot "$np" file "bonds from the input file")
  grep -q "bonds from" "$w/filen/run_info.txt" || fail "the input file's bonds were not used on $np ranks"
  echo "$np ranks with the bonds of $first: files equal to one rank"
fi
echo "$np ranks: $n HDF5 files and series.csv equal to one rank${APP_MPI_SETS:+ ($APP_MPI_SETS)}"
# checkpoint on NP ranks at t = 50 s, restart on NP2 ranks to 100 s: equal to the one-rank run
"${run[@]}" -np "$np" "$exe" "${common[@]}" --set time.end=50.0 --set "output.directory=\"$w/first\""
"${run[@]}" -np "$np2" "$exe" "${common[@]}" --set time.end=100.0 --set "output.directory=\"$w/first\"" \
  --restart "$w/first/checkpoint.h5"
last=$(basename "$(ls "$w"/one/snap_*.h5 | tail -1)")
h5diff --exclude-path /provenance "$w/one/$last" "$w/first/$last" >/dev/null || fail "restart $np -> $np2 ranks differs from one rank"
h5diff --exclude-path /provenance "$w/one/checkpoint.h5" "$w/first/checkpoint.h5" >/dev/null ||
  fail "checkpoint after restart $np -> $np2 differs"
# how the restart read its checkpoint: in blocks (no rank reads all rows) unless it holds bonds
if grep -q "bonds.generate=true" <<<"${APP_MPI_SETS:-}"; then
  grep -q "^input: every rank read all" "$w/first/run_info.txt" || fail "run_info.txt: a checkpoint with bonds is read whole"
else
  grep -q "^input: .* spheres read in blocks, at most" "$w/first/run_info.txt" ||
    fail "run_info.txt: the restart on $np2 ranks did not read the checkpoint in blocks"
  # a fresh start from a sphere file (a snapshot: no bonds), each rank reading its rows only
  snap=$(from_snapshot "$np2" blk "input read in blocks" "${extra[@]}")
  grep -q "^input: .* spheres read in blocks" "$w/blkn/run_info.txt" || fail "the sphere file was not read in blocks"
  echo "$np2 ranks from $snap read in blocks: files equal to one rank"
fi
echo "restart $np -> $np2 ranks: $last and checkpoint equal to one rank"
