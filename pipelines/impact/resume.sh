#!/usr/bin/env bash
# resume.sh OUTDIR CHECKPOINT [INPUT...] -- CMD...: run a long stage (mpm-frag, ssdem-grav) so that
# a run that was interrupted (killed, out of time, SIGTERM) continues where it stopped instead of
# starting over.
#
# Both tools write into OUTDIR/.staging-<pid>/ and publish into OUTDIR only when the run completes
# (common/run_dir.hpp); an interrupted run leaves its staging directory with its last checkpoint
# (every output.checkpoint_wall seconds of wall time, 600 by default, and on SIGTERM/SIGINT).
# The newest such checkpoint named CHECKPOINT is continued (CMD --restart <it>, bit-identical) only
# if it is newer than every INPUT (the stage's Make prerequisites: binary, scene, settings stamp,
# input files), i.e. only if the interrupted run was started with what the stage runs now; a
# rebuilt tool or a changed setting (time.end and output times included, which a restart may
# otherwise change) runs the stage from the start. (With RESUME_ACROSS_BUILDS=1 the impact rules
# pass the tools as order-only prerequisites, so they are not among the INPUTs: a rebuilt tool
# then continues the checkpoint.) The tool also refuses a checkpoint of another
# run (scene, settings or input file content differ) or a corrupt one, naming it; then, and only
# then, CMD runs from the start. Nothing is deleted here: a run replaces OUTDIR's files when it
# publishes, and a directory in use by another run is refused by the tool (exit 2).
set -u
out=$1; ck=$2; shift 2
inputs=()
while [ $# -gt 0 ] && [ "$1" != "--" ]; do inputs+=("$1"); shift; done
[ $# -gt 0 ] || { echo "resume.sh: usage: resume.sh OUTDIR CHECKPOINT [INPUT...] -- CMD..." >&2; exit 2; }
shift
latest=$(ls -t "$out"/.staging-*/"$ck" 2>/dev/null | head -n 1)
if [ -n "$latest" ]; then
  for f in "${inputs[@]}"; do
    if [ -e "$f" ] && ! [ "$latest" -nt "$f" ]; then
      echo "resume.sh: not continuing $latest: $f is newer (the stage changed since that run started)" >&2
      latest=""
      break
    fi
  done
fi
if [ -n "$latest" ]; then
  echo "resume.sh: continuing the interrupted run from $latest" >&2
  log=$(mktemp)
  "$@" --restart "$latest" 2>&1 | tee "$log"
  rc=${PIPESTATUS[0]}
  # the tool's own refusal (its message names the checkpoint), whatever exit code a launcher passes on
  if [ "$rc" -ne 0 ] && grep -qF -e "$latest: checkpoint of another run" -e "$latest: corrupt or unreadable" "$log"; then
    rm -f "$log"
    echo "resume.sh: the tool refused $latest (its message above); running the stage from the start" >&2
  else
    rm -f "$log"
    exit "$rc"
  fi
fi
exec "$@"
