#!/bin/bash
# ssdem-grav's gravity on MPI ranks (issue 19): NEW against OLD (MPI ssdem-grav binaries of two
# commits, e.g. replicated positions against locally essential trees), interleaved ROUNDS times,
# gravity every step, on:
#   pile   : a 151 837-sphere lattice pile (nbody/scenes/rubble_pile.toml, body_radius 60 m), 20 steps;
#   bodies : two bodies of 50 m and 15 m (1 m spheres, 89 012), as nbody-mpi-scaling, 20 steps;
# each on 2 ranks x 1 thread, and the pile also on 3 ranks (oversubscribed here: its wall is not
# a speed, its memory and traffic are). Reported: wall (median), peak RSS of the largest rank,
# bytes sent per rank per step by gravity (run_info.txt), the tree's own figures (new), and an
# h5diff of the final checkpoints of OLD and NEW (the forces must be the same bits).
# Usage: nbody_gravity_bench.sh NEW OLD OUT ROUNDS MPIRUN...
set -u
NEW=$1 OLD=$2 OUT=$3 ROUNDS=$4
shift 4
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
mkdir -p "$OUT"
rm -f "$OUT/res.txt"
common=(--set output.snapshot_interval=0.0 --set output.series_every=1000000 --set output.checkpoint_wall=0.0
        --set gravity.every=1)
for r in $(seq "$ROUNDS"); do
  for case in pile_np2 bodies_np2 pile_np3; do
    np=${case##*_np}
    if [ "${case%_np*}" = pile ]; then
      args=(--scene "$ROOT/nbody/scenes/rubble_pile.toml" --set initial.body_radius=60.0 --set time.end=0.2149)
    else
      args=(--scene "$ROOT/nbody/scenes/two_bodies.toml" --set initial.body_radius=50.0 --set initial.body2_radius=15.0
            --set "initial.body2_offset=[66.0, 2.0, 0.0]" --set "initial.body2_velocity=[-1.0, 0.0, 0.0]")
    fi
    for v in old new; do
      exe=$OLD
      [ "$v" = new ] && exe=$NEW
      d=$OUT/${case}_${v}_$r
      rm -rf "$d"
      extra=()
      if [ "${case%_np*}" = bodies ]; then  # 20 steps of the scene's dt
        dt=$(OMP_NUM_THREADS=1 "$exe" -q "${args[@]}" "${common[@]}" --set time.end=1e-12 \
               --set "output.directory=\"$d.probe\"" > /dev/null 2>&1; grep -o 'dt = [0-9.e+-]*' "$d.probe/run_info.txt" | head -1 | awk '{print $3}')
        extra=(--set "time.end=$(/usr/bin/python3 -c "print(20 * $dt * (1 - 1e-6))")")
      fi
      t0=$(date +%s.%N)
      OMP_NUM_THREADS=1 "$@" -np "$np" /usr/bin/time -f "RSS %M" "$exe" -q "${args[@]}" "${common[@]}" "${extra[@]}" \
        --set "output.directory=\"$d\"" > "$d.log" 2>&1 || { echo "$case $v failed: $d.log"; exit 1; }
      t1=$(date +%s.%N)
      g=$(grep -o 'gravity [0-9.e+-]* B; communication' "$d/run_info.txt" | awk '{print $2}' | sort -g | tail -1)
      rss=$(grep -o 'RSS [0-9]*' "$d.log" | awk '{print $2}' | sort -n | tail -1)
      echo "$case $v $(echo "$t1 - $t0" | bc) ${rss:-0} $g" >> "$OUT/res.txt"
      echo "round $r $case $v: $(tail -1 "$OUT/res.txt")"
    done
  done
done
/usr/bin/python3 - "$OUT" <<'PY'
import statistics, sys
out = sys.argv[1]
w, m, g = {}, {}, {}
for line in open(f"{out}/res.txt"):
    case, v, wall, rss, gb = line.split()
    w.setdefault((case, v), []).append(float(wall))
    if int(rss) > 0:  # 0: the ranks' /usr/bin/time lines interleaved in the log
        m.setdefault((case, v), []).append(int(rss) / 1024)
    g[(case, v)] = float(gb)
lines = ["| scene, ranks | binary | wall (s), median | peak RSS of the largest rank (MiB), min-max | gravity sent per rank per step (B), largest rank |",
         "|---|---|---|---|---|"]
for case in ("pile_np2", "bodies_np2", "pile_np3"):
    for v in ("old", "new"):
        lines.append(f"| {case} | {v} | {statistics.median(w[(case, v)]):.2f} | {min(m.get((case, v), [0])):.0f}-{max(m.get((case, v), [0])):.0f} | {g[(case, v)]:.4g} |")
open(f"{out}/gravity.md", "w").write("\n".join(lines) + "\n")
print("\n".join(lines))
PY
for case in pile_np2 bodies_np2 pile_np3; do
  h5diff --exclude-path /provenance "$OUT/${case}_new_1/checkpoint.h5" "$OUT/${case}_old_1/checkpoint.h5" > /dev/null \
    && r=equal || r=DIFFERENT
  echo "$case final checkpoint new vs old: $r" | tee -a "$OUT/gravity.md"
  grep -o 'rank [0-9]*: .*gravity tree per evaluation.*' "$OUT/${case}_new_1/run_info.txt" | sed 's/^rank \([0-9]*\):.*gravity tree/rank \1: gravity tree/' \
    | tee -a "$OUT/gravity.md"
done
