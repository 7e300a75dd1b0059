#!/usr/bin/env bash
# timed.sh DIR STAGE CMD...: run CMD, record its wall time in DIR/STAGE.json, keep its exit code.
set -u
dir=$1; stage=$2; shift 2
mkdir -p "$dir"
echo "+ $*" >&2
start=$(date +%s.%N)
"$@"
rc=$?
end=$(date +%s.%N)
printf '{"stage": "%s", "wall_s": %.3f, "exit_code": %d, "threads": "%s"}\n' \
  "$stage" "$(awk -v a="$start" -v b="$end" 'BEGIN{print b-a}')" "$rc" "${OMP_NUM_THREADS:-all}" > "$dir/$stage.json.tmp" \
  && mv "$dir/$stage.json.tmp" "$dir/$stage.json"
exit $rc
