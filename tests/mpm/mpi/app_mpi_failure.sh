#!/usr/bin/env bash
# mpm-frag's run directory and failure path on MPI ranks (label mpi), as on one rank:
#  - a run completes and publishes its files in output.directory (no staging directory left);
#  - a second run into it while it is locked (flock held by another process) exits 2 naming the
#    directory in use, and changes nothing;
#  - a run whose body leaves the grid exits 3 on 1 and on NP ranks at the same step; the
#    published files of the earlier run stay byte for byte; the last good state (here the
#    intact current state) is saved as <prefix>_failed_<step>.h5 in the failed run's staging
#    directory, the same particles as one rank's (to DELTA in every value), and the series up to the
#    failure is committed there;
#  - with outflow removal the body leaves particle by particle, and the step at which every
#    remaining particle would leave stops the run before any is removed (exit 3) at the same
#    step on 1 and NP ranks, the remaining particles and the outflow file saved alike.
# A failure that leaves the state not intact saves the ranks' backups instead (every
# run.backup_every steps): no scene provokes one through the CFL-controlled driver, so that path
# is tested on the DomainSolver (test_mpm_mpi_failure.cpp, a 100x step).
# Usage: app_mpi_failure.sh <mpm-frag> <NP> <DELTA> <mpirun...>
set -euo pipefail
exe=$1 np=$2 delta=$3
shift 3
run=("$@")
w=$(mktemp -d "${TMPDIR:-/tmp}/mpm_app_mpi_failure.XXXXXX")
trap 'rm -rf "$w"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
# same_particles A B: the same particle ids, and every /particles dataset equal to DELTA relative
# to its scale (rows matched by id: the one-rank driver writes its storage order, the MPI one id
# order). Scales: the dataset's largest value, at least U = max |v| for velocities, rho c U for
# stresses (c = 106.5 m/s, this material's dilatational speed) and m U^2 for energies, so that
# round-off noise in a field that is nearly zero (a translating sphere's stress) is measured
# against the physics it stands for.
same_particles() {
  /usr/bin/python3 - "$1" "$2" "$delta" <<'PY'
import sys, h5py, numpy as np
a, b, d = h5py.File(sys.argv[1], "r"), h5py.File(sys.argv[2], "r"), float(sys.argv[3])
ia, ib = a["particles/id"][:], b["particles/id"][:]
if sorted(ia) != sorted(ib): sys.exit("different particle ids")
oa, ob = np.argsort(ia), np.argsort(ib)
P = a["particles"]
U = np.max(np.abs(P["velocity"][:]))
rho = np.max(P["mass"][:] / P["volume"][:])
floor = {"velocity": U, "stress": rho * 106.5 * U, "internal_energy": np.max(P["mass"][:]) * U * U}
for k in P:
    x, y = P[k][:][oa], b["particles"][k][:][ob]
    scale = max(float(np.max(np.abs(x), initial=0.0)), floor.get(k, 0.0))
    err = float(np.max(np.abs(x.astype(float) - y.astype(float)), initial=0.0))
    if x.shape != y.shape or err > d * scale: sys.exit(f"/particles/{k} differs by {err:.3g} (scale {scale:.3g})")
for g in ("/", "particles"):
    for k in ("time", "step"):
        if k in a[g].attrs and (k not in b[g].attrs or a[g].attrs[k] != b[g].attrs[k]): sys.exit(f"different {k}")
PY
}
cat >"$w/edge.toml" <<'TOML'
[grid]
domain_min = [0.0, 0.0, 0.0]
domain_max = [0.2, 0.1, 0.1]
cell_size = 0.01
[time]
end = 1.0
[output]
prefix = "edge"
snapshot_interval = 0.0005
series_every = 5
[[material]]
name = "m"
model = "elastic"
density = 1000.0
bulk_modulus = 1e7
shear_modulus = 1e6
[[body]]
material = "m"
shape = "sphere"
center = [0.1, 0.05, 0.05]
radius = 0.03
velocity = [20.0, 0.0, 0.0]
TOML
mpm() { local n=$1 dir=$2; shift 2; "${run[@]}" -np "$n" "$exe" --scene "$w/edge.toml" --set "output.directory=\"$w/$dir\"" "$@"; }
sums() { (cd "$w/$1" && find . -path './.staging-*' -prune -o -type f ! -name .lock -print | sort | xargs md5sum); }
steps=()
for n in 1 "$np"; do
  mpm "$n" "np$n" --quiet --set time.end=0.001 || fail "$n rank(s): the short run failed"
  ls "$w/np$n"/edge_000000.h5 "$w/np$n"/edge_series.csv "$w/np$n"/edge_checkpoint.h5 >/dev/null || fail "$n rank(s): not published"
  ! ls -d "$w/np$n"/.staging-* >/dev/null 2>&1 || fail "$n rank(s): a staging directory is left after a completed run"
  before=$(sums "np$n")
  set +e
  mpm "$n" "np$n" >"$w/np$n.log" 2>&1
  rc=$?
  set -e
  [ "$rc" -eq 3 ] || fail "$n rank(s): exit $rc for a body leaving the grid, expected 3: $(tail -3 "$w/np$n.log")"
  grep -q "left the grid" "$w/np$n.log" || fail "$n rank(s): the failure is not named"
  [ "$(sums "np$n")" = "$before" ] || fail "$n rank(s): the failed run changed the published files"
  f=$(ls "$w/np$n"/.staging-*/edge_failed_*.h5 2>/dev/null) || fail "$n rank(s): no last good state in the staging directory"
  grep -q "last good state saved to .*edge_failed_" "$w/np$n.log" || fail "$n rank(s): the saved state is not named"
  k=$(basename "$f" .h5 | sed 's/edge_failed_0*//')
  last=$(tail -1 "$(dirname "$f")/edge_series.csv" | cut -d, -f1)
  [ "$last" = "$k" ] || fail "$n rank(s): the committed series ends at step $last, the failure at step $k"
  steps+=("$k")
done
[ "${steps[0]}" = "${steps[1]}" ] || fail "the failure step differs: ${steps[0]} (1 rank) vs ${steps[1]} ($np ranks)"
one=$(ls "$w"/np1/.staging-*/edge_failed_*.h5) many=$(ls "$w/np$np"/.staging-*/edge_failed_*.h5)
same_particles "$one" "$many" || fail "the last good state on $np ranks differs from one rank's by more than $delta"
echo "body leaving the grid on $np ranks: exit 3 at step ${steps[1]} as on one rank; earlier files kept; state and series saved in staging"

# a second run while the directory is locked
exec 9>"$w/np$np/.lock"  # this shell holds the run lock (flock(2), as another run would)
flock -n 9 || fail "cannot take the lock of $w/np$np"
before=$(sums "np$np")
staged=$(ls -d "$w/np$np"/.staging-* | wc -l)
set +e
mpm "$np" "np$np" --set time.end=0.001 >"$w/locked.log" 2>&1
rc=$?
set -e
exec 9>&-
[ "$rc" -eq 2 ] || fail "a run into a locked directory on $np ranks: exit $rc, expected 2"
grep -q "in use by another run" "$w/locked.log" || fail "the refusal does not say the directory is in use: $(tail -2 "$w/locked.log")"
[ "$(sums "np$np")" = "$before" ] || fail "the refused run changed the directory"
[ "$(ls -d "$w/np$np"/.staging-* | wc -l)" = "$staged" ] || fail "the refused run left a staging directory"
echo "a second run into a locked directory on $np ranks: refused (exit 2), nothing changed"


# outflow removal: the last particles leave; the run stops before removing them, as on one rank
steps=()
for n in 1 "$np"; do
  set +e
  mpm "$n" "out$n" --set 'grid.outflow="remove"' >"$w/out$n.log" 2>&1
  rc=$?
  set -e
  [ "$rc" -eq 3 ] || fail "$n rank(s): exit $rc when every particle leaves, expected 3: $(tail -3 "$w/out$n.log")"
  grep -q "particles left the grid by" "$w/out$n.log" || fail "$n rank(s): the failure is not named: $(grep -m1 error "$w/out$n.log")"
  f=$(ls "$w/out$n"/.staging-*/edge_failed_*.h5 2>/dev/null) || fail "$n rank(s): no last good state"
  [ -f "$(dirname "$f")/edge_outflow.h5" ] || fail "$n rank(s): no outflow file beside the last good state"
  steps+=("$(basename "$f" .h5 | sed 's/edge_failed_0*//')")
done
[ "${steps[0]}" = "${steps[1]}" ] || fail "every particle leaving: step ${steps[0]} (1 rank) vs ${steps[1]} ($np ranks)"
one=$(ls "$w"/out1/.staging-*/edge_failed_*.h5) many=$(ls "$w/out$np"/.staging-*/edge_failed_*.h5)
same_particles "$one" "$many" || fail "every particle leaving: the saved state on $np ranks differs from one rank's"
same_particles "$(dirname "$one")/edge_outflow.h5" "$(dirname "$many")/edge_outflow.h5" ||
  fail "every particle leaving: the outflow file on $np ranks differs from one rank's"
echo "every particle leaving on $np ranks: exit 3 at step ${steps[1]} before any is removed, as on one rank"
