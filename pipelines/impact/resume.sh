#!/usr/bin/env bash
# resume.sh OUTDIR CHECKPOINT CMD...: run a long stage (mpm-frag, ssdem-grav) so that a run that
# was interrupted (killed, out of time, SIGTERM) continues where it stopped instead of starting over.
#
# Both tools write into OUTDIR/.staging-<pid>/ and publish into OUTDIR only when the run completes
# (common/run_dir.hpp); an interrupted run leaves its staging directory with its last checkpoint
# (every output.checkpoint_wall seconds of wall time, 600 by default, and on SIGTERM/SIGINT).
# If such a checkpoint named CHECKPOINT exists (the newest, if several), CMD --restart <it> runs:
# the tool adopts that staging directory and continues bit-identically. The tool itself refuses a
# checkpoint of another run (scene, settings or the content of an input file changed: exit 2);
# then, and only then, CMD runs afresh. Nothing is deleted here: a fresh run replaces OUTDIR's
# files when it publishes, and a directory in use by another run is refused by the tool (exit 2).
set -u
out=$1; ck=$2; shift 2
latest=$(ls -t "$out"/.staging-*/"$ck" 2>/dev/null | head -n 1)
if [ -n "$latest" ]; then
  echo "resume.sh: continuing the interrupted run from $latest" >&2
  "$@" --restart "$latest"
  rc=$?
  [ "$rc" -ne 2 ] && exit "$rc"
  echo "resume.sh: the tool refused $latest (exit 2, its message above); running from the start" >&2
fi
exec "$@"
