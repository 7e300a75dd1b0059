#!/usr/bin/env bash
# Dynamic Brazilian disk of basalt at several platen speeds (see tests/damage/brazilian.hpp).
# usage: run_brazilian.sh <damage_brazilian exe> <outdir> <cell_m> <courant> <nominal rates...>
# Appends one summary row per rate to <outdir>/summary.csv. Environment: SAMPLING (flaw
# sampling of the basalt: scale_aware (default), poisson or expected), BLOCK (flaw_block_count,
# default 1), SEED (run.seed, default 1), PLATEN (platen density of the relaxation drive, or
# "kinematic": the exact velocity drive of the scenes, mpm/include/mpm/body_drive.hpp).
set -euo pipefail
exe=$1; out=$2; cell=$3; cfl=$4; shift 4
smp=${SAMPLING:-scale_aware}; blk=${BLOCK:-1}; seed=${SEED:-1}
mkdir -p "$out"
[ -f "$out/summary.csv" ] || echo "nominal_rate,effective_rate,peak_F_N,sigma_t_Pa,t_peak_s,steps,particles,wall_s,centre_rate,cell_m,courant,seed,sampling,block_count" > "$out/summary.csv"
for r in "$@"; do
  line=$("$exe" "$out" "$r" "$cell" "$cfl" "$seed" tonge_ramesh "$smp" "$blk" ${PLATEN:+"$PLATEN"} 2> "$out/log_${r}_h${cell}_c${cfl}_s${seed}.txt")
  echo "$line,$cell,$cfl,$seed,$smp,$blk" | tee -a "$out/summary.csv"
done
