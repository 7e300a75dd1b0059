#!/bin/bash
# ssdem-grav's files on 2 MPI ranks (issue 19 item 4): peak RSS of each rank and wall of a run
# that writes 5 snapshots, 5 series rows and a checkpoint of a 151 837-sphere lattice pile
# (nbody/scenes/rubble_pile.toml at body_radius 60 m, 40 steps), NEW against OLD (an MPI ssdem-grav
# of another commit), interleaved ROUNDS times; the snapshots must be h5diff-equal. OUT/files.md.
# Usage: nbody_files_bench.sh NEW OLD OUT ROUNDS MPIRUN...
set -u
NEW=$1 OLD=$2 OUT=$3 ROUNDS=$4
shift 4
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
mkdir -p "$OUT"
rm -f "$OUT/res.txt"
for r in $(seq "$ROUNDS"); do
  for v in old new; do
    exe=$OLD
    [ "$v" = new ] && exe=$NEW
    d=$OUT/${v}_$r
    rm -rf "$d"
    t0=$(date +%s.%N)
    OMP_NUM_THREADS=1 "$@" -np 2 /usr/bin/time -f "RSS %M" "$exe" --scene "$ROOT/nbody/scenes/rubble_pile.toml" -q \
      --set initial.body_radius=60.0 --set time.end=0.43 --set output.snapshot_interval=0.043 \
      --set output.series_every=10 --set "output.directory=\"$d\"" > "$d.log" 2>&1 || { echo "$v failed: $d.log"; exit 1; }
    t1=$(date +%s.%N)
    echo "$v $(echo "$t1 - $t0" | bc) $(grep -o 'RSS [0-9]*' "$d.log" | awk '{print $2}' | sort -n | tail -1)" >> "$OUT/res.txt"
  done
done
/usr/bin/python3 - "$OUT" <<'PY'
import statistics, sys
out = sys.argv[1]
w, m = {}, {}
for line in open(f"{out}/res.txt"):
    v, wall, rss = line.split()
    w.setdefault(v, []).append(float(wall))
    m.setdefault(v, []).append(int(rss) / 1024)
lines = ["| binary | wall (s), median | peak RSS of the largest rank (MiB), min-max |", "|---|---|---|"]
for v in ("old", "new"):
    lines.append(f"| {v} | {statistics.median(w[v]):.2f} | {min(m[v]):.0f}-{max(m[v]):.0f} |")
open(f"{out}/files.md", "w").write("\n".join(lines) + "\n")
print("\n".join(lines))
PY
for f in "$OUT"/new_1/snap_*.h5; do
  h5diff --exclude-path /provenance "$f" "$OUT/old_1/$(basename "$f")" > /dev/null && r=equal || r=DIFFERENT
  echo "$(basename "$f") new vs old: $r" | tee -a "$OUT/files.md"
done
