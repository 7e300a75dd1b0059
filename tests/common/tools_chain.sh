#!/bin/sh
# The four tools end to end on a tiny impact, as the pipeline chains them, with one restart of
# each simulation tool: mpm-frag (Tonge-Ramesh target, elastic impactor, artificial viscosity,
# outflow) -> continued from its published checkpoint -> mpm2spheres -> ssdem-grav (tree gravity;
# contacts off: the fragments fly at 300 m/s, and the unit tests cover contacts) -> continued from its checkpoint -> ssdem-analyse. Label `chain`: it also runs in the
# sanitizer pass (pipelines/Makefile ASAN_LABELS), so the executables themselves run under
# ASan+UBSan, not only the unit tests. Each step must exit 0 (a sanitizer report aborts the tool).
# usage: tools_chain.sh <mpm-frag> <mpm2spheres> <ssdem-grav> <ssdem-analyse> <source dir> <work dir>
set -eu
MPM=$1 HANDOFF=$2 GRAV=$3 ANALYSE=$4 SRC=$5 W=$6
rm -rf "$W"
mkdir -p "$W"
cd "$W"
cat > grav.toml <<'TOML'
[time]
end = 1e-5
dt = 1e-6
[initial]
source = "file"
file = "spheres.h5"
[gravity]
solver = "tree"
every = 2
[contact]
enabled = false
[output]
directory = "nbody"
snapshot_interval = 5e-6
series_every = 2
checkpoint_wall = 0.0
progress_interval = 100.0
TOML
FRAG="--quiet --scene $SRC/tests/common/data/tiny_impact.toml --set output.directory=\"frag\" --set output.prefix=\"frag\" --set output.snapshot_interval=1e-5"
"$MPM" $FRAG --set time.end=1e-5
"$MPM" $FRAG --set time.end=2e-5 --restart frag/frag_checkpoint.h5
last=$(ls frag/frag_[0-9]*.h5 | tail -n 1)
"$HANDOFF" --quiet -i "$last" -o spheres.h5 --coarsen 1
"$GRAV" --quiet --scene grav.toml
"$GRAV" --quiet --scene grav.toml --set time.end=2e-5 --restart nbody/checkpoint.h5
"$ANALYSE" --quiet spheres.h5 nbody/snap_*.h5 --mpm "$last" --mpm-initial frag/frag_000000.h5 -o analysis
test -s analysis.json && test -s analysis.timeseries.csv && test -s analysis.damage.csv
echo "tools chain complete"
