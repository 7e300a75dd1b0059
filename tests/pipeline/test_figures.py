#!/usr/bin/python3
"""impact-figures (pipelines/impact/figures.py, render_cutaway.py) on synthetic sphere sets.

    test_figures.py REPO_ROOT WORK_DIR

1. Damage profile (Fig. 6): a ball of radius R_T on a lattice, shifted off the origin, damage = r/R_T,
   plus one far, massive-looking ejecta sphere: the mass-weighted mean damage of each full shell
   equals the mass-weighted mean of r/R_T over its spheres (to 1e-12) and lies within half a shell
   width of the shell centre; the ejecta sphere does not move the centre.
2. An aborting pvbatch (a lost xvfb display race) leaves no directory in the figures directory.
3. Cut-away render (Figs. 4, 5; only where pvbatch is installed, else exit 77 = skipped): a ball whose
   quarter x > c_x, y > c_y carries damage 1 and the rest 0.5; with that quarter cut away, the views
   must show the 0.5 colour (Turbo: green) and none of the colour of damage 1 (dark red), and the PNG
   must hold one 700 x 640 view per input file side by side.
"""
import os
import shutil
import subprocess
import sys

import h5py
import numpy as np

root, work = sys.argv[1], sys.argv[2]
sys.path.insert(0, os.path.join(root, "pipelines", "impact"))
from figures import listed, shell_profile  # noqa: E402


def fail(msg):
    print("FAIL:", msg)
    sys.exit(1)


def lattice_ball(radius, h, centre):
    g = np.arange(-radius, radius + h / 2, h)
    x = np.stack(np.meshgrid(g, g, g, indexing="ij"), axis=-1).reshape(-1, 3)
    x = x[np.linalg.norm(x, axis=1) <= radius]
    return x + centre


# 0. the MPM stage's done list: the snapshots only (its last entries were taken as the end of the
#    MPM: the outflow file, which holds only the particles that left the grid, made the end-of-MPM
#    profile a single shell)
os.makedirs(work, exist_ok=True)
with open(os.path.join(work, "done"), "w") as f:
    f.write("r/fragment/frag_000000.h5\nr/fragment/frag_002424.h5\nr/fragment/frag_checkpoint.h5\n"
            "r/fragment/frag_outflow.h5\n")
got = listed(os.path.join(work, "done"))
if got != ["r/fragment/frag_000000.h5", "r/fragment/frag_002424.h5"]:
    fail(f"listed() kept {got}")

# 1. profile
R_T, h = 1000.0, 37.0
c0 = np.array([250.0, -120.0, 40.0])
x = lattice_ball(R_T, h, c0)
rr = np.linalg.norm(x - c0, axis=1) / R_T
m = np.ones(len(x)) * 2.0
x = np.vstack([x, c0 + [9e4, 0, 0]])  # far ejecta
m = np.append(m, 2.0)
d = np.append(rr, 0.123)
rc, mean, frac = shell_profile(x, m, d, R_T)
edges = np.linspace(0.0, 1.5, len(rc) + 1)
# the centre is the lattice's median: within one spacing of c0
for k in range(len(rc)):
    if edges[k + 1] > 0.95:
        break
    sel = (rr >= edges[k]) & (rr < edges[k + 1])
    if sel.sum() < 30:
        continue
    want = np.average(rr[sel], weights=m[:-1][sel])
    if abs(mean[k] - want) > 0.5 * h / R_T + 1e-12 or abs(mean[k] - rc[k]) > 0.5 * (edges[1] - edges[0]) + h / R_T:
        fail(f"shell {k}: mean damage {mean[k]:.6f}, expected {want:.6f} (shell centre {rc[k]:.4f})")
if abs(frac.sum() - (len(x) - 1) / len(x)) > 1e-12:
    fail(f"mass fractions in 0..1.5 R_T sum to {frac.sum()}, expected all but the ejecta")
print("ok: damage profile of a ball with damage r/R_T")

# 2. a pvbatch that aborts (as it does when xvfb-run -a loses the race for a display: SIGABRT, no
# Python clean-up) leaves no directory behind: figures.render gives each attempt a --workdir next to
# the figure and removes it itself (before, every lost race left an empty tmp* in figures/)
os.makedirs(work, exist_ok=True)
figdir = os.path.join(work, "abort")
shutil.rmtree(figdir, ignore_errors=True)
os.makedirs(figdir)
log = os.path.join(work, "abort.log")
if os.path.exists(log):
    os.remove(log)
fake = os.path.join(work, "aborting_pvbatch.sh")
with open(fake, "w") as f:
    f.write(f"""#!/bin/sh
while [ $# -gt 0 ]; do
  if [ "$1" = --workdir ]; then echo "$2" >> {log}; touch "$2/panel_0.png"; fi
  shift
done
kill -ABRT $$
""")
os.chmod(fake, 0o755)
import figures  # noqa: E402

try:
    figures.render(fake, "spheres", [(0.0, os.path.join(work, "none.h5"))], os.path.join(figdir, "f.png"), "")
    fail("figures.render returned after three aborted renders")
except SystemExit as e:
    if e.code != 3:
        fail(f"figures.render exit {e.code} after three aborted renders, expected 3")
given = open(log).read().split() if os.path.isfile(log) else []
if len(given) != 3 or any(os.path.dirname(g) != figdir for g in given):
    fail(f"work directories given to pvbatch: {given}, expected three in {figdir}")
left = [n for n in os.listdir(figdir)]
if left:
    fail(f"left in the figures directory after aborted renders: {left}")
print("ok: three aborted renders leave nothing behind")

# 3. render
pvbatch = shutil.which("pvbatch")
xvfb = shutil.which("xvfb-run")
if not pvbatch or not xvfb:
    print("pvbatch or xvfb-run not installed: render check skipped")
    sys.exit(77)
os.makedirs(work, exist_ok=True)
xb = lattice_ball(R_T, 100.0, np.zeros(3))
q = (xb[:, 0] > 0) & (xb[:, 1] > 0)
xb = xb[~((np.abs(xb[:, 0]) < 1e-9) | (np.abs(xb[:, 1]) < 1e-9))]  # no sphere on the cut planes
q = (xb[:, 0] > 0) & (xb[:, 1] > 0)
n = len(xb)
files = []
for k in range(2):
    p = os.path.join(work, f"ball_{k}.h5")
    with h5py.File(p, "w") as f:
        f.attrs["time"] = float(k * 10.0)
        g = f.create_group("spheres")
        g["position"] = xb
        g["mass"] = np.full(n, 1.0)
        g["radius"] = np.full(n, 50.0)
        g["damage"] = np.where(q, 1.0, 0.5)
    with open(p[:-3] + ".xmf", "w") as f:
        b = os.path.basename(p)
        f.write(f"""<?xml version="1.0" ?>
<Xdmf Version="3.0"><Domain><Grid Name="spheres" GridType="Uniform"><Time Value="{k * 10.0}"/>
<Topology TopologyType="Polyvertex" NumberOfElements="{n}" NodesPerElement="1"/>
<Geometry GeometryType="XYZ"><DataItem Format="HDF" NumberType="Float" Precision="8" Dimensions="{n} 3">{b}:/spheres/position</DataItem></Geometry>
<Attribute Name="mass" AttributeType="Scalar" Center="Node"><DataItem Format="HDF" NumberType="Float" Precision="8" Dimensions="{n}">{b}:/spheres/mass</DataItem></Attribute>
<Attribute Name="radius" AttributeType="Scalar" Center="Node"><DataItem Format="HDF" NumberType="Float" Precision="8" Dimensions="{n}">{b}:/spheres/radius</DataItem></Attribute>
<Attribute Name="damage" AttributeType="Scalar" Center="Node"><DataItem Format="HDF" NumberType="Float" Precision="8" Dimensions="{n}">{b}:/spheres/damage</DataItem></Attribute>
</Grid></Domain></Xdmf>
""")
    files.append(p[:-3] + ".xmf")
out = os.path.join(work, "cut.png")
cmd = [xvfb, "-a", pvbatch, os.path.join(root, "pipelines", "impact", "render_cutaway.py"), "--kind", "spheres",
       "--out", out] + files
for _ in range(3):
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode == 0:
        break
if r.returncode != 0:
    print(r.stdout, r.stderr)
    fail(f"render_cutaway exit {r.returncode}")
import matplotlib.image as mpimg  # noqa: E402

img = mpimg.imread(out)[..., :3]
if img.shape[:2] != (640, 1400):
    fail(f"image shape {img.shape[:2]}, expected 640 x 1400 (two 700 x 640 views)")
# colours left of the colour bar in each view (the bar is at 86 % of the last view's width)
body = np.concatenate([img[:, v * 700: v * 700 + 560].reshape(-1, 3) for v in range(2)])
red = (body[:, 0] > 0.35) & (body[:, 1] < 0.12) & (body[:, 2] < 0.12)          # Turbo at 1: dark red
green = (body[:, 1] > 0.5) & (body[:, 0] < 0.75) & (body[:, 2] < 0.5) & (body[:, 1] > body[:, 0])  # Turbo at 0.5
if green.sum() < 2000:
    fail(f"only {green.sum()} pixels of the damage-0.5 colour: the body is not drawn")
if red.sum() > 0.002 * green.sum():
    fail(f"{red.sum()} pixels of the damage-1 colour: the quarter x > c_x, y > c_y was not cut away")
print(f"ok: cut-away render ({green.sum()} body pixels, {red.sum()} of the removed quarter's colour)")
