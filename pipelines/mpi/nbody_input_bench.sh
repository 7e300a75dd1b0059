#!/bin/bash
# ssdem-grav's input on MPI ranks (issue 19: a start that reads only the rank's rows): peak RSS of
# the largest rank and wall, NEW against OLD (an MPI ssdem-grav of another commit), interleaved
# ROUNDS times, on 2, 3 and 6 ranks (6: oversubscribed, as a rank's share of a larger machine):
#   pile-restart : a restart from a 151 837-sphere pile's checkpoint (nbody/scenes/rubble_pile.toml,
#                  body_radius 60 m, 4 steps on one rank first), one step;
#   pile-file    : a fresh start from that pile's sphere file, one step;
#   debris-restart: (if DEBRIS_RUN holds nbody/checkpoint.h5) a restart from an impact chain's
#                  N-body checkpoint (the 750 m paper-method run: 19 377 spheres, ~30 000 contact
#                  history records) under pipelines/impact/reaccumulate.toml, 0.1 s.
# The final checkpoints of NEW and OLD must be h5diff-equal. OUT/input.md.
# Usage: nbody_input_bench.sh NEW OLD OUT ROUNDS DEBRIS_RUN MPIRUN...
set -u
NEW=$1 OLD=$2 OUT=$3 ROUNDS=$4 DEBRIS_RUN=$5
shift 5
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
mkdir -p "$OUT"
rm -f "$OUT/res.txt"
scene=(--scene "$ROOT/nbody/scenes/rubble_pile.toml" --set initial.body_radius=60.0 --set output.checkpoint_wall=0)
if [ ! -f "$OUT/pile/checkpoint.h5" ]; then
  rm -rf "$OUT/pile"
  OMP_NUM_THREADS=2 "$NEW" -q "${scene[@]}" --set time.end=0.043 --set output.snapshot_interval=0.043 \
    --set "output.directory=\"$OUT/pile\"" || { echo "the pile run failed"; exit 1; }
fi
snap=$(ls "$OUT"/pile/snap_*.h5 | tail -1)
cases="pile-restart pile-file"
[ -f "$DEBRIS_RUN/nbody/checkpoint.h5" ] && cases="$cases debris-restart"
for r in $(seq "$ROUNDS"); do
  for np in 2 3 6; do
    for case in $cases; do
      for v in old new; do
        exe=$OLD
        [ "$v" = new ] && exe=$NEW
        d=$OUT/${case}_${np}_${v}_$r
        rm -rf "$d"
        case $case in
          pile-restart)
            cp -r "$OUT/pile" "$d"
            args=("${scene[@]}" --set time.end=0.054 --set output.snapshot_interval=0 --restart "$d/checkpoint.h5") ;;
          pile-file)
            args=("${scene[@]}" --set initial.source=\"file\" --set "initial.file=\"$snap\"" --set time.end=0.011) ;;
          debris-restart)
            mkdir -p "$d" && cp "$DEBRIS_RUN/nbody/checkpoint.h5" "$d/"
            t=$(h5dump -a /ssdem_state/time "$d/checkpoint.h5" | awk '/\(0\)/{print $2}')
            args=(--scene "$ROOT/pipelines/impact/reaccumulate.toml" --set "initial.file=\"$DEBRIS_RUN/spheres.h5\""
                  --set "time.end=$(echo "$t + 0.1" | bc -l)" --set 'output.times=[]' --set output.checkpoint_wall=0
                  --restart "$d/checkpoint.h5") ;;
        esac
        t0=$(date +%s.%N)
        OMP_NUM_THREADS=1 "$@" -np "$np" /usr/bin/time -f "RSS %M" "$exe" -q "${args[@]}" \
          --set "output.directory=\"$d\"" > "$d.log" 2>&1 || { echo "$case $np $v failed: $d.log"; exit 1; }
        t1=$(date +%s.%N)
        echo "$case $np $v $(echo "$t1 - $t0" | bc) $(grep -o 'RSS [0-9]*' "$d.log" | awk '{print $2}' | sort -n | tail -1)" >> "$OUT/res.txt"
      done
    done
  done
done
/usr/bin/python3 - "$OUT" <<'PY'
import statistics, sys
out = sys.argv[1]
w, m = {}, {}
for line in open(f"{out}/res.txt"):
    case, np, v, wall, rss = line.split()
    w.setdefault((case, np, v), []).append(float(wall))
    m.setdefault((case, np, v), []).append(int(rss) / 1024)
lines = ["| start | ranks | binary | wall (s), median | peak RSS of the largest rank (MiB), min-max |",
         "|---|---|---|---|---|"]
for case in ("pile-restart", "pile-file", "debris-restart"):
    for np in ("2", "3", "6"):
        for v in ("old", "new"):
            k = (case, np, v)
            if k not in w:
                continue
            lines.append(f"| {case} | {np} | {v} | {statistics.median(w[k]):.2f} | {min(m[k]):.0f}-{max(m[k]):.0f} |")
open(f"{out}/input.md", "w").write("\n".join(lines) + "\n")
print("\n".join(lines))
PY
for case in $cases; do
  for np in 2 3 6; do
    h5diff --exclude-path /provenance "$OUT/${case}_${np}_new_1/checkpoint.h5" "$OUT/${case}_${np}_old_1/checkpoint.h5" \
      > /dev/null && r=equal || r=DIFFERENT
    echo "$case on $np ranks: final checkpoint new vs old: $r" | tee -a "$OUT/input.md"
  done
done
