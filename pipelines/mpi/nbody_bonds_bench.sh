#!/bin/bash
# Bonds on MPI ranks (issue 19): a bonded two-body collision (nbody/scenes/two_bodies.toml with
# bodies of 30 m and 12 m of 1 m spheres, bonds.generate, weak bonds that break as the bodies
# settle: 19 012 spheres, 107 724 bonds, 10 s = 1 508 steps), interleaved ROUNDS times:
#   serial_old, serial_new : the serial ssdem-grav of another commit (OLD) and of this one (NEW),
#                            2 OpenMP threads (the serial path's cost: must not grow);
#   mpi_1x2, mpi_2x1       : this commit's MPI ssdem-grav, one rank x 2 threads (the serial driver)
#                            and 2 ranks x 1 thread.
# Reported: wall (median), the bonds line of run_info.txt, each rank's bonds held and traffic,
# and whether the final checkpoints of serial_new, mpi_1x2 and mpi_2x1 are identical (h5diff).
# Usage: nbody_bonds_bench.sh NEW_MPI NEW_SERIAL OLD_SERIAL OUT ROUNDS MPIRUN...
set -u
NEW_MPI=$1 NEW=$2 OLD=$3 OUT=$4 ROUNDS=$5
shift 5
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
mkdir -p "$OUT"
rm -f "$OUT/res.txt"
args=(--scene "$ROOT/nbody/scenes/two_bodies.toml" --set initial.body_radius=30.0 --set initial.body2_radius=12.0
      --set "initial.body2_offset=[43.0, 2.0, 0.0]" --set "initial.body2_velocity=[-0.05, 0.0, 0.0]"
      --set bonds.generate=true --set bonds.gap=0.2 --set bonds.kn=1e4 --set bonds.ks=1e4
      --set bonds.sigma_c=0.05 --set bonds.tau_c=0.05 --set time.end=10.0
      --set output.snapshot_interval=0.0 --set output.series_every=100 --set output.checkpoint_wall=0.0)
for r in $(seq "$ROUNDS"); do
  for case in serial_old serial_new mpi_1x2 mpi_2x1; do
    d=$OUT/${case}_$r
    rm -rf "$d"
    t0=$(date +%s.%N)
    case $case in
      serial_old) OMP_NUM_THREADS=2 "$OLD" -q "${args[@]}" --set "output.directory=\"$d\"" > "$d.log" 2>&1 ;;
      serial_new) OMP_NUM_THREADS=2 "$NEW" -q "${args[@]}" --set "output.directory=\"$d\"" > "$d.log" 2>&1 ;;
      mpi_1x2) OMP_NUM_THREADS=2 "$@" -x OMP_NUM_THREADS=2 -np 1 "$NEW_MPI" -q "${args[@]}" \
                 --set "output.directory=\"$d\"" > "$d.log" 2>&1 ;;
      mpi_2x1) OMP_NUM_THREADS=1 "$@" -x OMP_NUM_THREADS=1 -np 2 "$NEW_MPI" -q "${args[@]}" \
                 --set "output.directory=\"$d\"" > "$d.log" 2>&1 ;;
    esac || { echo "$case failed: $d.log"; exit 1; }
    t1=$(date +%s.%N)
    echo "$case $(echo "$t1 - $t0" | bc)" >> "$OUT/res.txt"
    echo "round $r: $(tail -1 "$OUT/res.txt")"
  done
done
{
  echo "| case | wall (s), median of $ROUNDS | min-max |"
  echo "|---|---|---|"
  /usr/bin/python3 - "$OUT/res.txt" <<'PY'
import statistics, sys
w = {}
for line in open(sys.argv[1]):
    c, t = line.split()
    w.setdefault(c, []).append(float(t))
for c in ("serial_old", "serial_new", "mpi_1x2", "mpi_2x1"):
    print(f"| {c} | {statistics.median(w[c]):.2f} | {min(w[c]):.2f}-{max(w[c]):.2f} |")
PY
  grep -h "^spheres:\|^dt = \|bonds generated" "$OUT/serial_new_1/run_info.txt" | head -3
  grep -h "^bonds:" "$OUT/serial_new_1/run_info.txt" "$OUT/mpi_2x1_1/run_info.txt"
  grep -o 'rank [0-9]*: [0-9]* own spheres, [0-9]* ghosts; [0-9]* exchanges.*sent per step: [^;]*;' "$OUT/mpi_2x1_1/run_info.txt"
  grep -o 'rank [0-9]*: .*bonds held [0-9]*' "$OUT/mpi_2x1_1/run_info.txt" | sed 's/: .*bonds held/: bonds held/'
  for c in mpi_1x2 mpi_2x1; do
    h5diff --exclude-path /provenance "$OUT/serial_new_1/checkpoint.h5" "$OUT/${c}_1/checkpoint.h5" > /dev/null \
      && r=identical || r=DIFFERENT
    echo "final checkpoint serial_new vs $c: $r"
  done
  # against OLD the checkpoint gained bonds/released and released_base, and the released total is
  # now an exact sum: the trajectory and the bond state must still be the same bits
  r=identical
  for o in /spheres /ssdem_state/a /ssdem_state/alpha /ssdem_state/bonds/Fs /ssdem_state/bonds/Mb \
           /ssdem_state/bonds/Mt /ssdem_state/bonds/broken /ssdem_state/history/S; do
    h5diff "$OUT/serial_new_1/checkpoint.h5" "$OUT/serial_old_1/checkpoint.h5" "$o" "$o" > /dev/null || r="DIFFERENT ($o)"
  done
  echo "final state and bond state serial_new vs serial_old: $r"
  /usr/bin/python3 -c 'import h5py, sys
e = [h5py.File(f, "r")["ssdem_state/bonds"].attrs["released_energy"] for f in sys.argv[1:]]
print(f"released_energy old (sum in breaking order) {e[0]!r}, new (exact sum) {e[1]!r}: {abs(e[1] - e[0]) / e[1]:.2g} relative")' \
    "$OUT/serial_old_1/checkpoint.h5" "$OUT/serial_new_1/checkpoint.h5"
} | tee "$OUT/bonds.md"
