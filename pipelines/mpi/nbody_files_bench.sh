#!/bin/bash
# ssdem-grav's files on 2 MPI ranks (issue 19 item 4): peak RSS of the largest rank and wall,
# NEW against OLD (an MPI ssdem-grav of another commit), interleaved ROUNDS times, on two scenes:
#   pile   : a 151 837-sphere lattice pile (nbody/scenes/rubble_pile.toml, body_radius 60 m), 40
#            steps, 5 snapshots, 5 series rows and a checkpoint;
#   debris : the 1 km impact debris of the pipeline (SPHERES, 8 217 spheres) under
#            pipelines/impact/reaccumulate.toml, 60 s, a snapshot every 6 s, the pipeline's rows.
# The snapshots must be h5diff-equal. OUT/files.md.
# Usage: nbody_files_bench.sh NEW OLD OUT ROUNDS SPHERES MPIRUN...
set -u
NEW=$1 OLD=$2 OUT=$3 ROUNDS=$4 SPHERES=$5
shift 5
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
mkdir -p "$OUT"
rm -f "$OUT/res.txt"
for r in $(seq "$ROUNDS"); do
  for case in pile debris; do
    if [ "$case" = pile ]; then
      args=(--scene "$ROOT/nbody/scenes/rubble_pile.toml" --set initial.body_radius=60.0 --set time.end=0.43
            --set output.snapshot_interval=0.043 --set output.series_every=10)
    else
      args=(--scene "$ROOT/pipelines/impact/reaccumulate.toml" --set "initial.file=\"$SPHERES\"" --set time.end=60.0
            --set output.snapshot_interval=6.0 --set 'output.times=[]' --set output.checkpoint_wall=0)
    fi
    for v in old new; do
      exe=$OLD
      [ "$v" = new ] && exe=$NEW
      d=$OUT/${case}_${v}_$r
      rm -rf "$d"
      t0=$(date +%s.%N)
      OMP_NUM_THREADS=1 "$@" -np 2 /usr/bin/time -f "RSS %M" "$exe" -q "${args[@]}" --set "output.directory=\"$d\"" \
        > "$d.log" 2>&1 || { echo "$case $v failed: $d.log"; exit 1; }
      t1=$(date +%s.%N)
      echo "$case $v $(echo "$t1 - $t0" | bc) $(grep -o 'RSS [0-9]*' "$d.log" | awk '{print $2}' | sort -n | tail -1)" >> "$OUT/res.txt"
    done
  done
done
/usr/bin/python3 - "$OUT" <<'PY'
import statistics, sys
out = sys.argv[1]
w, m = {}, {}
for line in open(f"{out}/res.txt"):
    case, v, wall, rss = line.split()
    w.setdefault((case, v), []).append(float(wall))
    m.setdefault((case, v), []).append(int(rss) / 1024)
lines = ["| scene | binary | wall (s), median | peak RSS of the largest rank (MiB), min-max |", "|---|---|---|---|"]
for case in ("pile", "debris"):
    for v in ("old", "new"):
        lines.append(f"| {case} | {v} | {statistics.median(w[(case, v)]):.2f} | {min(m[(case, v)]):.0f}-{max(m[(case, v)]):.0f} |")
open(f"{out}/files.md", "w").write("\n".join(lines) + "\n")
print("\n".join(lines))
PY
for case in pile debris; do
  for f in "$OUT/${case}_new_1"/snap_*.h5; do
    h5diff --exclude-path /provenance "$f" "$OUT/${case}_old_1/$(basename "$f")" > /dev/null && r=equal || r=DIFFERENT
    echo "$case $(basename "$f") new vs old: $r" | tee -a "$OUT/files.md"
  done
done
