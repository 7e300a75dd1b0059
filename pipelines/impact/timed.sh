#!/usr/bin/env bash
# timed.sh DIR STAGE CMD...: run CMD, record its wall time in DIR/STAGE.json, keep its exit code.
# STAGE_MPI_RANKS (environment): the ranks the stage ran on (0: one process).
set -u
dir=$1; stage=$2; shift 2
mkdir -p "$dir"
echo "+ $*" >&2
start=$(date +%s.%N)
"$@"
rc=$?
end=$(date +%s.%N)
printf '{"stage": "%s", "wall_s": %.3f, "exit_code": %d, "threads": "%s", "mpi_ranks": %d}\n' \
  "$stage" "$(awk -v a="$start" -v b="$end" 'BEGIN{print b-a}')" "$rc" "${OMP_NUM_THREADS:-all}" "${STAGE_MPI_RANKS:-0}" > "$dir/$stage.json.tmp" \
  && mv "$dir/$stage.json.tmp" "$dir/$stage.json"
exit $rc
