#!/usr/bin/env bash
# `make -C pipelines impact-ensemble` (issue 17, item 4) on a tiny impact (2 km cells, a 4 km impactor
# at 3 km/s, 1 s of MPM, 30 s of N-body; about 1 s per seed):
#   1. each seed runs in its own directory with its own flaw seed (run.seed in the stage stamp and in
#      the fragment snapshot's provenance) and the seeds give different MPM states (damage);
#   2. ensemble.csv / ensemble_runs.csv equal the statistics recomputed here from the per-seed
#      analysis.json, spheres.audit.json and frag_series.csv (mean, std with n - 1, sem, min, max);
#   3. with known values written into the per-seed outputs, a rerun of the target reruns no stage and
#      its table holds the hand-computed statistics of those values;
#   4. ensemble.py refuses (exit 1) a seed given twice and a run that differs in the cell size.
# usage: test_make_ensemble.sh <repo root> <build dir> <work dir>
set -euo pipefail
root=$1; build=$2; work=$3
rm -rf "$work"; mkdir -p "$work"
ens=$work/ens
seeds="3 7 11"
vars=(BUILD="$build" ENSEMBLE="$ens" SEEDS="$seeds" CELL=2000 IMPACTOR_DIAMETER=4000 IMPACT_SPEED=3000 MPM_TIME=1
      SNAP_INTERVAL=0.5 COARSEN=1 NBODY_TIME=30 'NBODY_TIMES=[15.0, 30.0]' NBODY_SETS="--set time.steps_per_contact=10 --set time.min_steps_per_contact=10")
mk() { make -s -C "$root/pipelines" impact-ensemble "${vars[@]}" "$@" > "$work/make.log" 2>&1 || { cat "$work/make.log"; exit 1; }; }
fail() { echo "FAIL: $*"; exit 1; }
PY=/usr/bin/python3

mk
for s in $seeds; do
  grep -q "run.seed=$s " "$ens/seed$s/.vars/FRAGMENT" || fail "seed$s: run.seed=$s not in the fragment stamp"
done
$PY - "$ens" $seeds <<'EOF'
import csv, json, math, sys
import h5py, numpy as np
ens, seeds = sys.argv[1], [int(s) for s in sys.argv[2:]]
def fail(m): print("FAIL:", m); sys.exit(1)
vals = {k: [] for k in ("M_LR_over_M_PB", "beta", "ke_loss", "bound_mass_fraction", "mpm_energy_change",
                        "transfer_heat_frac")}
damage = []
for s in seeds:
    d = f"{ens}/seed{s}"
    fin = json.load(open(f"{d}/analysis.json"))["final"]
    for k in ("M_LR_over_M_PB", "beta", "bound_mass_fraction"):
        vals[k].append(fin[k])
    vals["ke_loss"].append(json.load(open(f"{d}/spheres.audit.json"))["kinetic_rel_loss"])
    rows = list(csv.DictReader(l for l in open(f"{d}/fragment/frag_series.csv") if not l.startswith("#")))
    e0, e1 = float(rows[0]["total_J"]), float(rows[-1]["total_J"])
    vals["mpm_energy_change"].append((e1 - e0) / e0)
    vals["transfer_heat_frac"].append(float(rows[-1]["transfer_heat_J"]) / e0)
    with h5py.File(f"{d}/fragment/final.h5", "r") as f:
        scene = f["provenance"].attrs["scene"]
        scene = scene.decode() if isinstance(scene, bytes) else str(scene)
        if f"seed = {s}" not in scene:
            fail(f"seed{s}: the fragment snapshot's provenance scene has no 'seed = {s}'")
        damage.append(np.asarray(f["particles/damage"][...]))
if any(np.array_equal(damage[0], x) for x in damage[1:]):
    fail("two seeds gave the same damage field: the seed does not reach mpm-frag")
table = {r["quantity"]: r for r in csv.DictReader(open(f"{ens}/ensemble.csv"))}
for k, v in vals.items():
    v = np.array(v, dtype=float)
    want = {"n": len(v), "mean": v.mean(), "std": v.std(ddof=1), "sem": v.std(ddof=1) / math.sqrt(len(v)),
            "min": v.min(), "max": v.max()}
    got = table[k]
    if int(got["n"]) != want["n"]:
        fail(f"{k}: n {got['n']} != {want['n']}")
    for c in ("mean", "std", "sem", "min", "max"):
        g, w = float(got[c]), want[c]
        if abs(g - w) > 1e-12 * max(1.0, abs(w)):
            fail(f"{k} {c}: table {g!r}, recomputed {w!r}")
runs = list(csv.DictReader(open(f"{ens}/ensemble_runs.csv")))
if [int(r["seed"]) for r in runs] != sorted(seeds):
    fail(f"ensemble_runs.csv seeds {[r['seed'] for r in runs]}")
for r, s in zip(runs, sorted(seeds)):
    i = seeds.index(s)
    for k in vals:
        if float(r[k]) != vals[k][i]:
            fail(f"ensemble_runs.csv seed {s} {k}: {r[k]} != {vals[k][i]!r}")
print("ok: table equals the statistics of the per-seed outputs;", {k: round(float(np.mean(v)), 6) for k, v in vals.items()})
EOF
echo "ok: each seed in its own run with its own flaws"

# 3. known values in the per-seed outputs: the table must hold their statistics, no stage may rerun
before=$(for s in $seeds; do stat -c '%.9Y' "$ens/seed$s/fragment/done" "$ens/seed$s/nbody/done"; done)
$PY - "$ens" <<'EOF'
import json, sys
ens = sys.argv[1]
known = {3: (0.61, 1.25, 0.02), 7: (0.73, 2.5, 0.05), 11: (0.92, 1.75, 0.011)}
for s, (m, b, k) in known.items():
    p = f"{ens}/seed{s}/analysis.json"; a = json.load(open(p))
    a["final"]["M_LR_over_M_PB"], a["final"]["beta"] = m, b
    json.dump(a, open(p, "w"))
    p = f"{ens}/seed{s}/spheres.audit.json"; a = json.load(open(p))
    a["kinetic_rel_loss"] = k
    json.dump(a, open(p, "w"))
EOF
sleep 1.1
mk
after=$(for s in $seeds; do stat -c '%.9Y' "$ens/seed$s/fragment/done" "$ens/seed$s/nbody/done"; done)
[ "$before" = "$after" ] || fail "a stage was rerun although only the outputs' values changed"
$PY - "$ens/ensemble.csv" <<'EOF'
import csv, sys
t = {r["quantity"]: r for r in csv.DictReader(open(sys.argv[1]))}
# by hand: M_LR 0.61, 0.73, 0.92: mean 0.753333..., deviations -0.143333, -0.023333, 0.166667,
# squares sum 0.048867, /2 -> std 0.156312; beta 1.25, 2.5, 1.75: mean 1.833333, std 0.629153;
# loss 0.02, 0.05, 0.011: mean 0.027, std 0.020421
want = {"M_LR_over_M_PB": (0.7533333333333333, 0.15631165450257807, 0.61, 0.92),
        "beta": (1.8333333333333333, 0.6291528696058958, 1.25, 2.5),
        "ke_loss": (0.027, 0.020420577856662138, 0.011, 0.05)}
for k, (mean, std, lo, hi) in want.items():
    r = t[k]
    got = (float(r["mean"]), float(r["std"]), float(r["min"]), float(r["max"]), float(r["sem"]))
    exp = (mean, std, lo, hi, std / 3 ** 0.5)
    if any(abs(g - e) > 1e-12 for g, e in zip(got, exp)):
        print(f"FAIL: {k}: table {got}, expected {exp}"); sys.exit(1)
print("ok: the table holds the statistics of known per-seed values")
EOF
grep -q "| M_LR/M_PB | 3 | 0.7533 | 0.1563 | 0.0902 | 0.6100 | 0.9200 |" "$ens/ensemble.md" \
  || { cat "$ens/ensemble.md"; fail "ensemble.md row for M_LR/M_PB"; }
echo "ok: a rerun with changed outputs reran no stage and re-aggregated"

# 4. not one ensemble: the same seed twice, or a run at another cell size
if $PY "$root/pipelines/impact/ensemble.py" "$ens/seed3" "$ens/seed3" --out "$work/dup" > "$work/dup.log" 2>&1; then
  fail "ensemble.py accepted the same seed twice"
fi
grep -q "used by more than one run" "$work/dup.log" || { cat "$work/dup.log"; fail "no message for a repeated seed"; }
cp -r "$ens/seed7" "$work/other"
sed -i 's/grid.cell_size=2000/grid.cell_size=1500/' "$work/other/.vars/FRAGMENT"
if $PY "$root/pipelines/impact/ensemble.py" "$ens/seed3" "$work/other" --out "$work/mixed" > "$work/mixed.log" 2>&1; then
  fail "ensemble.py averaged runs at different cell sizes"
fi
grep -q "runs differ in cell_m" "$work/mixed.log" || { cat "$work/mixed.log"; fail "no message for mixed cell sizes"; }
echo "ok: a repeated seed and mixed cell sizes are refused"
rm -rf "$work"
