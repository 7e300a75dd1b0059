#!/bin/sh
# The four tools end to end on a tiny impact, as the pipeline chains them, with one restart of
# each simulation tool: mpm-frag (Tonge-Ramesh target, elastic impactor, artificial viscosity,
# outflow) -> continued from its published checkpoint -> mpm2spheres -> ssdem-grav (tree gravity;
# contacts off: the fragments fly at 300 m/s, and the unit tests cover contacts) -> continued from its checkpoint -> ssdem-analyse. Label `chain`: it also runs in the
# sanitizer pass (pipelines/Makefile ASAN_LABELS), so the executables themselves run under
# ASan+UBSan, not only the unit tests. Each step must exit 0 (a sanitizer report aborts the tool).
# usage: tools_chain.sh <mpm-frag> <mpm2spheres> <ssdem-grav> <ssdem-analyse> <work dir>
set -eu
MPM=$1 HANDOFF=$2 GRAV=$3 ANALYSE=$4 W=$5
rm -rf "$W"
mkdir -p "$W"
cd "$W"
cat > frag.toml <<'TOML'
[grid]
domain_min = [0.0, 0.0, 0.0]
domain_max = [0.2, 0.1, 0.1]
cell_size = 0.01
outflow = "remove"
[solver]
artificial_viscosity.enabled = true
[time]
end = 1e-5
[output]
directory = "frag"
prefix = "frag"
snapshot_interval = 1e-5
progress_interval = 100.0
[[material]]
name = "rock"
model = "tonge_ramesh"
density = 2700.0
[[material]]
name = "soft"
model = "elastic"
density = 1000.0
bulk_modulus = 1e8
shear_modulus = 1e7
[[body]]
name = "target"
material = "rock"
shape = "sphere"
center = [0.07, 0.05, 0.05]
radius = 0.03
[[body]]
name = "impactor"
material = "soft"
shape = "sphere"
center = [0.13, 0.05, 0.05]
radius = 0.012
velocity = [-300.0, 0.0, 0.0]
TOML
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
"$MPM" --quiet --scene frag.toml
"$MPM" --quiet --scene frag.toml --set time.end=2e-5 --restart frag/frag_checkpoint.h5
last=$(ls frag/frag_[0-9]*.h5 | tail -n 1)
"$HANDOFF" --quiet -i "$last" -o spheres.h5 --coarsen 1
"$GRAV" --quiet --scene grav.toml
"$GRAV" --quiet --scene grav.toml --set time.end=2e-5 --restart nbody/checkpoint.h5
"$ANALYSE" --quiet spheres.h5 nbody/snap_*.h5 --mpm "$last" --mpm-initial frag/frag_000000.h5 -o analysis
test -s analysis.json && test -s analysis.timeseries.csv && test -s analysis.damage.csv
echo "tools chain complete"
