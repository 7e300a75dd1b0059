#!/usr/bin/env bash
# The MPI mpm-frag end to end (label mpi): on NP ranks the snapshots have the layout of a one-rank
# run (the same groups, datasets and shapes, `h5ls -r`), the series the same header and rows, a
# second NP-rank run writes bit-identical snapshots (h5diff, provenance excluded: it holds the
# command line and directory), --restart of a missing file exits 2, and with outflow removal
# (tests/common/data/tiny_impact.toml) the outflow file has the layout of one rank's and as many
# particles, and the Brazilian disk's driven platens give one rank's loads, and bit-identical
# series and final snapshot after a restart on NP ranks.
# Usage: app_mpi.sh <mpm-frag> <scene> <NP> <mpirun...>
set -euo pipefail
exe=$1 scene=$2 np=$3
shift 3
run=("$@")
w=$(mktemp -d "${TMPDIR:-/tmp}/mpm_app_mpi.XXXXXX")
trap 'rm -rf "$w"' EXIT
common=(--scene "$scene" --quiet --set time.end=0.002 --set output.snapshot_interval=0.001 --set output.series_every=10)
fail() { echo "FAIL: $*" >&2; exit 1; }
"${run[@]}" -np 1 "$exe" "${common[@]}" --set "output.directory=\"$w/one\""
"${run[@]}" -np "$np" "$exe" "${common[@]}" --set "output.directory=\"$w/a\""
"${run[@]}" -np "$np" "$exe" "${common[@]}" --set "output.directory=\"$w/b\""
layout() { h5ls -r "$1" | grep -v '^/provenance' | sed 's/  */ /g'; }
n=0
for f in "$w"/one/*_[0-9]*.h5; do
  g="$w/a/$(basename "$f")"
  [ -f "$g" ] || fail "$(basename "$f") not written on $np ranks"
  cmp <(layout "$f") <(layout "$g") || fail "$(basename "$f"): layout on $np ranks differs from one rank"
  h5diff --exclude-path /provenance "$g" "$w/b/$(basename "$f")" >/dev/null || fail "$(basename "$f") differs between two $np-rank runs"
  n=$((n + 1))
done
[ "$n" -ge 3 ] || fail "expected 3 snapshots, found $n"
s1=$(ls "$w"/one/*_series.csv) s2=$(ls "$w"/a/*_series.csv)
[ "$(head -1 "$s1")" = "$(head -1 "$s2")" ] || fail "series header differs"
[ "$(wc -l <"$s1")" = "$(wc -l <"$s2")" ] || fail "series rows differ: $(wc -l <"$s1") vs $(wc -l <"$s2")"
echo "$np ranks: $n snapshots with the one-rank layout, bit-identical on a repeated run; series as one rank"
set +e
"${run[@]}" -np "$np" "$exe" "${common[@]}" --set "output.directory=\"$w/c\"" --restart "$w/one/nothing.h5" >/dev/null 2>&1
rc=$?
set -e
[ "$rc" -eq 2 ] || fail "--restart of a missing file on $np ranks: exit $rc, expected 2"
echo "--restart of a missing file on $np ranks refused (exit 2)"
tiny="$(dirname "$0")/../../common/data/tiny_impact.toml"
"${run[@]}" -np 1 "$exe" --scene "$tiny" --quiet --set "output.directory=\"$w/o1\""
"${run[@]}" -np "$np" "$exe" --scene "$tiny" --quiet --set "output.directory=\"$w/on\""
[ -f "$w/on/ck_outflow.h5" ] || fail "no outflow file on $np ranks"
cmp <(layout "$w/o1/ck_outflow.h5") <(layout "$w/on/ck_outflow.h5") || fail "outflow file on $np ranks differs in layout or count from one rank"
echo "outflow removal on $np ranks: $(h5ls "$w/on/ck_outflow.h5/particles/id" | sed 's/.*{\([0-9]*\).*/\1/') particles in the outflow file, layout of one rank"
# velocity-driven platens (pipelines/damage/brazilian.toml at 0.4 mm, the first half of the
# loading): the platen loads in the series on NP ranks equal one rank's to 1e-9 of the largest
# component of that platen's force (or impulse) over the run (the reactions summed over the nodes
# each rank owns, then over the ranks)
bz="$(dirname "$0")/../../../pipelines/damage/brazilian.toml"
bzc=(--scene "$bz" --quiet --set grid.cell_size=4e-4 --set output.snapshot_interval=4e-6)
for n in 1 "$np"; do
  "${run[@]}" -np "$n" "$exe" "${bzc[@]}" --set time.end=1.6e-5 --set "output.directory=\"$w/bz$n\""
done
/usr/bin/python3 - "$w/bz1/bz_series.csv" "$w/bz$np/bz_series.csv" <<'PY' || fail "platen loads on $np ranks differ from one rank's"
import sys, csv
a, b = (list(csv.reader(open(p))) for p in sys.argv[1:3])
if a[0] != b[0] or len(a) != len(b): sys.exit("series header or row count differs")
cols = [i for i, h in enumerate(a[0]) if h.startswith("body")]
if len(cols) != 12: sys.exit(f"expected 12 platen load columns, found {len(cols)}")
scale = {}  # per platen and quantity (body<b>_F, body<b>_J): its largest component
for i in cols:
    k = a[0][i][:a[0][i].index("_") + 2]
    scale[k] = max(scale.get(k, 0.0), max(abs(float(r[i])) for r in a[1:]))
for i in cols:
    x = [float(r[i]) for r in a[1:]]; y = [float(r[i]) for r in b[1:]]
    s = scale[a[0][i][:a[0][i].index("_") + 2]]
    if s == 0 or max(abs(u - v) for u, v in zip(x, y)) > 1e-9 * s: sys.exit(f"{a[0][i]} differs")
PY
echo "driven platens on $np ranks: the platen loads of the series equal one rank's to 1e-9"
# stopped at half the loading and continued on NP ranks: the series (loads included) and the final
# snapshot bit-identical to the uninterrupted run (the drives' masses come from the set-up, not
# from how the particles are split at the restart)
"${run[@]}" -np "$np" "$exe" "${bzc[@]}" --set time.end=8e-6 --set "output.directory=\"$w/bzh\""
"${run[@]}" -np "$np" "$exe" "${bzc[@]}" --set time.end=1.6e-5 --set "output.directory=\"$w/bzh\"" \
  --restart "$w/bzh/bz_checkpoint.h5"
cmp -s "$w/bz$np/bz_series.csv" "$w/bzh/bz_series.csv" || fail "driven platens restarted on $np ranks: the series differs"
f=$(basename "$(ls "$w/bz$np"/bz_[0-9]*.h5 | tail -1)")
h5diff --exclude-path /provenance "$w/bz$np/$f" "$w/bzh/$f" >/dev/null || fail "driven platens restarted on $np ranks: $f differs"
echo "driven platens stopped at half the loading and continued on $np ranks: series and $f bit-identical"
