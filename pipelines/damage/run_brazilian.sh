#!/usr/bin/env bash
# Dynamic Brazilian disk of basalt at several platen speeds (see tests/damage/brazilian.hpp).
# usage: run_brazilian.sh <damage_brazilian exe> <outdir> <cell_m> <courant> <nominal rates...>
# Appends one summary row per rate to <outdir>/summary.csv. SAMPLING=expected (environment)
# switches the basalt's flaw sampling from per-particle Poisson draws to the expected density.
set -euo pipefail
exe=$1; out=$2; cell=$3; cfl=$4; shift 4
mkdir -p "$out"
[ -f "$out/summary.csv" ] || echo "nominal_rate,effective_rate,peak_F_N,sigma_t_Pa,t_peak_s,steps,particles,wall_s,cell_m,courant" > "$out/summary.csv"
for r in "$@"; do
  line=$("$exe" "$out" "$r" "$cell" "$cfl" 1 tonge_ramesh "${SAMPLING:-poisson}" 2> "$out/log_${r}_h${cell}_c${cfl}.txt")
  echo "$line,$cell,$cfl" | tee -a "$out/summary.csv"
done
