#!/bin/bash
# mpm-frag's outflow record on MPI ranks (issue 19): peak memory per rank and wall of a run in
# which most particles leave the grid (grid.outflow = "remove"), for the binary NEW against OLD
# (another build, e.g. one that gathered the record to rank 0), interleaved ROUNDS times on 2
# ranks x 1 thread; the outflow files and the final checkpoints must be h5diff-equal
# (provenance aside). Scene (written below): an elastic slab of 187 500 particles (0.3 x 0.05 x
# 0.1 m, 4 mm cells, 8 per cell) flying out through y+ at 150 m/s beside a resting bar of 30 000
# (the run goes on after the slab has left), 11 snapshots (each with the outflow file) and a
# checkpoint every 50 steps. Writes OUT/outflow.md.
# Usage: mpm_outflow_bench.sh NEW OLD OUT ROUNDS MPIRUN...
set -u
NEW=$1 OLD=$2 OUT=$3 ROUNDS=$4
shift 4
mkdir -p "$OUT"
cat > "$OUT/fly.toml" <<'TOML'
[grid]
domain_min = [0.0, 0.0, 0.0]
domain_max = [0.4, 0.2, 0.2]
cell_size = 0.004
outflow = "remove"
[time]
end = 1.0e-3
[output]
prefix = "fly"
snapshot_interval = 1.0e-4
checkpoint_every = 50
[[material]]
name = "slab"
model = "elastic"
density = 1000.0
bulk_modulus = 1e7
shear_modulus = 3e6
[[body]]
material = "slab"
shape = "box"
min = [0.05, 0.1, 0.05]
max = [0.35, 0.15, 0.15]
velocity = [0.0, 150.0, 0.0]
[[body]]
material = "slab"
shape = "box"
min = [0.05, 0.01, 0.05]
max = [0.35, 0.018, 0.15]
TOML
rss() { grep -o 'RSS_KB [0-9]*' "$1" | awk '{print $2}' | sort -n | tail -1; }
wall() { grep -o 'in [0-9.]* s wall' "$1" | awk '{print $2}'; }
echo "| round | binary | largest rank's peak RSS (MiB) | wall (s) | particles removed |" > "$OUT/outflow.md"
echo "|---|---|---|---|---|" >> "$OUT/outflow.md"
for r in $(seq "$ROUNDS"); do
  for tag in old new; do
    bin=$OLD; [ "$tag" = new ] && bin=$NEW
    d="$OUT/run_$tag"
    rm -rf "$d"
    OMP_NUM_THREADS=1 "$@" -np 2 /usr/bin/time -f "RSS_KB %M" "$bin" --scene "$OUT/fly.toml" \
      --set "output.directory=\"$d\"" > "$d.log" 2>&1 || { echo "$tag failed: $d.log"; exit 1; }
    n=$(h5ls "$d/fly_outflow.h5/particles/id" | sed 's/.*{\([0-9]*\).*/\1/')
    echo "| $r | $tag | $(( $(rss "$d.log") / 1024 )) | $(wall "$d.log") | $n |" >> "$OUT/outflow.md"
  done
done
same() { h5diff --exclude-path /provenance "$1" "$2" > /dev/null && echo equal || echo DIFFERENT; }
{
  echo
  echo "outflow file old vs new: $(same "$OUT/run_old/fly_outflow.h5" "$OUT/run_new/fly_outflow.h5")"
  echo "final checkpoint old vs new: $(same "$OUT/run_old/fly_checkpoint.h5" "$OUT/run_new/fly_checkpoint.h5")"
} >> "$OUT/outflow.md"
cat "$OUT/outflow.md"
