#!/usr/bin/env bash
# A numerical failure on several ranks (label mpi): two bodies meeting at 50 m/s with a contact law
# far too soft for it (contact.normal.kn = 1e5 N/m: the overlap runs past the radius at step 120).
# On NP ranks, as on one: exit 3, the last verified state (step 100, kept every 100 steps at
# gravity-block boundaries) saved as a restartable checkpoint failed_state.h5 in the run's staging
# directory, h5diff-identical to the one-rank file; continued with --restart on NP2 ranks it fails
# again at the same step (the continuation is exact).
# Usage: app_mpi_failure.sh <ssdem-grav> <two_bodies.toml> <NP> <NP2> <mpirun...>
set -euo pipefail
exe=$1 scene=$2 np=$3 np2=$4
shift 4
run=("$@")
w=$(mktemp -d "${TMPDIR:-/tmp}/app_mpi_failure.XXXXXX")
trap 'rm -rf "$w"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
common=(--scene "$scene" --quiet --set contact.normal.kn=1e5 --set "initial.body2_velocity=[-50.0,0.0,0.0]"
  --set "initial.body2_offset=[130.0,2.0,0.0]" --set time.end=2000.0)
for n in 1 "$np"; do
  set +e
  "${run[@]}" -np "$n" "$exe" "${common[@]}" --set "output.directory=\"$w/np$n\"" >"$w/np$n.log" 2>&1
  rc=$?
  set -e
  [ "$rc" -eq 3 ] || fail "$n rank(s): exit $rc, expected 3 (numerical failure)"
  grep -q "at step 120" "$w/np$n.log" || fail "$n rank(s): the failure is not at step 120: $(grep -m1 error "$w/np$n.log")"
  grep -q "last good state (step 100) saved" "$w/np$n.log" || fail "$n rank(s): no last good state of step 100"
  [ ! -e "$w/np$n/failed_state.h5" ] || fail "$n rank(s): failed_state.h5 published beside the results"
done
one=$(ls "$w"/np1/.staging-*/failed_state.h5)
many=$(ls "$w"/np"$np"/.staging-*/failed_state.h5)
h5diff --exclude-path /provenance "$one" "$many" >/dev/null || fail "failed_state.h5 on $np ranks differs from one rank's"
h5dump -a /ssdem_state/energy0_J "$many" >/dev/null 2>&1 || fail "failed_state.h5 records no initial energy (energy0_J)"
echo "$np ranks: exit 3 at step 120, last good state (step 100) saved, equal to one rank's"
set +e
"${run[@]}" -np "$np2" "$exe" "${common[@]}" --set "output.directory=\"$w/again\"" --restart "$many" >"$w/again.log" 2>&1
rc=$?
set -e
[ "$rc" -eq 3 ] || fail "restart of failed_state.h5 on $np2 ranks: exit $rc, expected 3"
grep -q "at step 120" "$w/again.log" || fail "restart on $np2 ranks does not fail at step 120 again"
echo "failed_state.h5 restarted on $np2 ranks: fails again at step 120"
