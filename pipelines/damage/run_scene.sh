#!/usr/bin/env bash
# Brazilian disk as a user scene (pipelines/damage/brazilian.toml) through mpm-frag, strength read
# from its snapshots by lab_strength.py.
# usage: run_scene.sh <mpm-frag> <outdir> <cell_m> <nominal rates...>
# Environment: SAMPLING (flaw_sampling, default scale_aware), SEED (run.seed, default 1),
# SCENE (default pipelines/damage/brazilian.toml), EXTRA (more --set options), TAG (run-name suffix).
# Each rate runs into <outdir>/<sampling>_h<cell>_r<rate>_s<seed>/ and appends a row to
# <outdir>/scene_summary.csv (with wall and CPU = user + system seconds); time.end = 4 us ramp + 4e-3 / rate (Brazilian) or 1.5e-2 / rate
# (compression), past the peak; 120 snapshots. Platen speed v = rate x 5 mm (2v/D for the 10 mm
# disk, v/(L/2) for the 10 mm cylinder).
set -euo pipefail
exe=$1; out=$2; cell=$3; shift 3
here=$(cd "$(dirname "$0")" && pwd)
scene=${SCENE:-$here/brazilian.toml}; smp=${SAMPLING:-scale_aware}; seed=${SEED:-1}
mkdir -p "$out"
[ -f "$out/scene_summary.csv" ] || /usr/bin/python3 "$here/lab_strength.py" --header > "$out/scene_summary.csv"
for r in "$@"; do
  v=$(awk "BEGIN{printf \"%.6g\", $r*0.005}")
  if grep -q '^name = "disk"' "$scene"; then  # Brazilian disk: two platens along y
    tend=$(awk "BEGIN{printf \"%.6g\", 4e-6 + 4e-3/$r}")
    drive=(--set "body[1].drive.velocity=[0,-$v,0]" --set "body[2].drive.velocity=[0,$v,0]")
  else  # compression: one platen along z over the half-length model
    tend=$(awk "BEGIN{printf \"%.6g\", 4e-6 + 1.5e-2/$r}")
    drive=(--set "body[1].drive.velocity=[0,0,-$v]")
  fi
  snap=$(awk "BEGIN{printf \"%.6g\", $tend/120}")
  dir=$out/${smp}_h${cell}_r${r}_s${seed}${TAG:-}
  /usr/bin/time -f "%e %U %S" -o "$dir.time" "$exe" --scene "$scene" --set grid.cell_size=$cell \
    "${drive[@]}" \
    --set time.end=$tend --set output.snapshot_interval=$snap --set run.seed=$seed \
    --set "material[0].flaw_sampling=\"$smp\"" --set output.directory=$dir ${EXTRA:-} > "$dir.log" 2>&1
  row=$(/usr/bin/python3 "$here/lab_strength.py" "$dir")
  read -r wall usr sys < "$dir.time"
  echo "$row,$wall,$(awk "BEGIN{print $usr + $sys}")" | tee -a "$out/scene_summary.csv"
done
