#!/bin/bash
# Cost of ssdem-grav's series rows (issues 15 and 19): the pipeline's reaccumulation scene on the
# 1 km paper debris (SPHERES) for 60 s, output.series_every 10^9 (2 rows) and 50, serial (2
# threads) and MPI (2 ranks x 1 thread), for the binaries NEW and OLD (serial) and NEW_MPI and
# OLD_MPI, interleaved ROUNDS times: ms per row = (wall with rows - wall without) / extra rows.
# The series (columns 1-19) of every variant must equal the serial new binary's. Writes OUT/rows.md.
# Usage: nbody_rows_bench.sh SPHERES OUT ROUNDS NEW OLD NEW_MPI OLD_MPI MPIRUN...
set -u
SPHERES=$1 OUT=$2 ROUNDS=$3 NEW=$4 OLD=$5 NEW_MPI=$6 OLD_MPI=$7
shift 7
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
mkdir -p "$OUT"
one() {  # name every command...
  local name=$1 every=$2
  shift 2
  local d="$OUT/${name}_$every" t0 t1
  rm -rf "$d"
  t0=$(date +%s.%N)
  OMP_PROC_BIND=false "$@" --scene "$ROOT/pipelines/impact/reaccumulate.toml" --set "initial.file=\"$SPHERES\"" \
    --set time.end=60.0 --set "output.directory=\"$d\"" --set output.checkpoint_wall=0 --set 'output.times=[]' \
    --set output.snapshot_interval=0 --set "output.series_every=$every" > "$d.log" 2>&1 || { echo "$name failed: $d.log"; exit 1; }
  t1=$(date +%s.%N)
  echo "$name $every $(echo "$t1 - $t0" | bc) $(($(wc -l < "$d/series.csv") - 1))" >> "$OUT/walls.txt"
}
rm -f "$OUT/walls.txt"
for r in $(seq "$ROUNDS"); do
  for every in 1000000000 50; do
    OMP_NUM_THREADS=2 one serial_old "$every" "$OLD"
    OMP_NUM_THREADS=2 one serial_new "$every" "$NEW"
    OMP_NUM_THREADS=1 one mpi_old "$every" "$@" -np 2 "$OLD_MPI"
    OMP_NUM_THREADS=1 one mpi_new "$every" "$@" -np 2 "$NEW_MPI"
  done
done
/usr/bin/python3 - "$OUT" <<'PY'
import statistics, sys
out = sys.argv[1]
w = {}
for line in open(f"{out}/walls.txt"):
    name, every, wall, rows = line.split()
    w.setdefault((name, every), []).append((float(wall), int(rows)))
lines = ["| variant | wall, 2 rows (s) | wall, rows every 50 steps (s) | rows | ms per row |", "|---|---|---|---|---|"]
for name in ("serial_old", "serial_new", "mpi_old", "mpi_new"):
    a = statistics.median(x for x, _ in w[(name, "1000000000")])
    b = statistics.median(x for x, _ in w[(name, "50")])
    rows = w[(name, "50")][0][1]
    lines.append(f"| {name} | {a:.2f} | {b:.2f} | {rows} | {1e3 * (b - a) / (rows - 2):.1f} |")
open(f"{out}/rows.md", "w").write("\n".join(lines) + "\n")
print("\n".join(lines))
PY
ref="$OUT/serial_new_50/series.csv"
for v in serial_old mpi_old mpi_new; do
  cmp -s <(cut -d, -f1-19 "$ref") <(cut -d, -f1-19 "$OUT/${v}_50/series.csv") && r=equal || r=DIFFERENT
  echo "series of $v vs serial_new: $r" | tee -a "$OUT/rows.md"
done
