# Sourced by the MPI end-to-end tests (tests/*/mpi/app_mpi_*.sh).
# signal_one_rank SIG MPIRUN_PID: sends SIG to one rank of the job that mpirun MPIRUN_PID runs (a
# child of mpirun, found in /proc, no procps needed), waits for mpirun (so it must be called from
# the shell that started it, not in a subshell) and sets mpirun_rc to its exit code. Returns 1 if
# mpirun has no child.
signal_one_rank() {
  local sig=$1 pid=$2 rank_pid
  rank_pid=$(grep -l "^PPid:[[:space:]]*$pid\$" /proc/[0-9]*/status 2>/dev/null | tail -1 | cut -d/ -f3 || true)
  [ -n "$rank_pid" ] || return 1
  kill "-$sig" "$rank_pid"
  set +e
  wait "$pid"
  mpirun_rc=$?
  set -e
}
# kill_rank_after GLOB MPIRUN_PID: waits (at most 60 s) for a file matching GLOB (unquoted, so
# it expands) while mpirun MPIRUN_PID runs, then SIGKILLs one of its ranks (signal_one_rank) and
# sets found to the file and mpirun_rc. Returns 1 if mpirun ended first, no file appeared, or
# mpirun has no child. Call it from the shell that started mpirun.
kill_rank_after() {
  local glob=$1 pid=$2
  found=
  for _ in $(seq 1 1200); do
    found=$(ls $glob 2>/dev/null | head -1 || true)
    [ -n "$found" ] && break
    kill -0 "$pid" 2>/dev/null || return 1
    sleep 0.05
  done
  [ -n "$found" ] || return 1
  signal_one_rank KILL "$pid"
}
