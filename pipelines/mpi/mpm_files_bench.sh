#!/bin/bash
# mpm-frag's files on MPI ranks (issue 19 item 4): peak memory per rank and wall of a run that
# writes snapshots and checkpoints, and of a restart, for the binary NEW against OLD (another
# build, e.g. from an earlier commit: `git worktree`), interleaved ROUNDS times; the final
# checkpoints and snapshots must be h5diff-equal (provenance aside).
# Scene: mpm/scenes/basalt_impact.toml at grid.cell_size=0.0055 (203 050 particles, 98 steps),
# 2 ranks x 1 thread, 11 snapshots, a checkpoint every 10 steps; the restart continues the final
# checkpoint to 22 us on 2 and 3 ranks. Writes OUT/files.md.
# Usage: mpm_files_bench.sh NEW OLD OUT ROUNDS MPIRUN...
set -u
NEW=$1 OLD=$2 OUT=$3 ROUNDS=$4
shift 4
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
SCENE=("--scene" "$ROOT/mpm/scenes/basalt_impact.toml" "--set" "grid.cell_size=0.0055" "--set" "output.snapshot_interval=2e-6")
mkdir -p "$OUT"
rss() { grep -o 'RSS_KB [0-9]*' "$1" | awk '{print $2}' | sort -n | tail -1; }
wall() { grep -o 'in [0-9.]* s wall' "$1" | awk '{print $2}'; }
run() {  # tag bin np dir extra...
  local tag=$1 bin=$2 np=$3 d=$4
  shift 4
  rm -rf "$d"
  mkdir -p "$d"
  OMP_NUM_THREADS=1 "$@" -np "$np" /usr/bin/time -f "RSS_KB %M" "$bin" "${SCENE[@]}" \
    --set "output.directory=\"$d\"" "${EXTRA[@]}" > "$d.log" 2>&1 || { echo "$tag failed: $d.log"; exit 1; }
}
echo "| round | binary | run | largest rank's peak RSS (MiB) | wall (s) |" > "$OUT/files.md"
echo "|---|---|---|---|---|" >> "$OUT/files.md"
for r in $(seq "$ROUNDS"); do
  for tag in old new; do
    bin=$OLD; [ "$tag" = new ] && bin=$NEW
    EXTRA=(--set output.checkpoint_every=10)
    run "$tag" "$bin" 2 "$OUT/write_$tag" "$@"
    echo "| $r | $tag | write, 2 ranks | $(( $(rss "$OUT/write_$tag.log") / 1024 )) | $(wall "$OUT/write_$tag.log") |" >> "$OUT/files.md"
  done
  for np in 2 3; do
    for tag in old new; do
      bin=$OLD; [ "$tag" = new ] && bin=$NEW
      EXTRA=(--set time.end=2.2e-5 --restart "$OUT/write_new/basalt_checkpoint.h5")
      run "$tag" "$bin" "$np" "$OUT/restart${np}_$tag" "$@"
      echo "| $r | $tag | restart, $np ranks | $(( $(rss "$OUT/restart${np}_$tag.log") / 1024 )) | $(wall "$OUT/restart${np}_$tag.log") |" >> "$OUT/files.md"
    done
  done
done
same() { h5diff --exclude-path /provenance "$1" "$2" > /dev/null && echo equal || echo DIFFERENT; }
{
  echo
  echo "final checkpoint old vs new: $(same "$OUT/write_old/basalt_checkpoint.h5" "$OUT/write_new/basalt_checkpoint.h5")"
  for np in 2 3; do
    last=$(ls "$OUT/restart${np}_new"/basalt_0*.h5 | tail -1)
    echo "restart on $np ranks, final snapshot old vs new: $(same "$OUT/restart${np}_old/$(basename "$last")" "$last")"
  done
} >> "$OUT/files.md"
cat "$OUT/files.md"
