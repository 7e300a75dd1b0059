"""3D cut-away renders of an impact run with ParaView (El Mir et al. 2019, Figs. 4 and 5).

    xvfb-run -a pvbatch render_cutaway.py --kind mpm|spheres --out FIG.png [--label TEXT] [--times T ...]
        [--workdir DIR] FILE.xmf [FILE.xmf ...]

Each FILE.xmf is the XDMF sidecar of an mpm-frag particle snapshot (`--kind mpm`) or of an
ssdem.spheres file (`--kind spheres`: the hand-off spheres and ssdem-grav snapshots). For each
file one 3D view is rendered and the views are put side by side into FIG.png:

  * centre c = mass-weighted median of the positions (per axis; robust to fast ejecta), the
    impact axis along z (the pipeline's impactor moves along -z and arrives from the top);
  * cut-away: the quarter x > c_x and y > c_y is removed (paper Fig. 4: a quarter of the target
    taken out), so the two exposed faces through the impact axis show the interior;
  * every item drawn as a sphere (ParaView's Point Gaussian, "Sphere" shader) of its own radius:
    spheres their `radius`, MPM particles the radius of a ball of their volume, r = (3V/4pi)^(1/3);
  * colour: the `damage` field (Turbo map: blue intact, red damaged, as the paper's Fig. 4) on one
    scale for all views, 0 to the largest damage shown (colour bar in the last view);
  * camera: parallel projection from the removed quarter's side, direction (1, 0.55, 0.5), up +z,
    framing 1.3 x the radius that holds 80 % of the mass (the largest over the views, so that all
    views share one length scale; escaping ejecta leave the frame).

Run under pvbatch (Debian `paraview` + `python3-paraview`); needs an X display, hence xvfb-run.
The views are drawn into --workdir (default: a temporary directory next to FIG.png). pvbatch aborts
(SIGABRT, no Python clean-up) when xvfb-run loses the race for a display, so a caller that retries
(figures.py) passes a directory it removes itself.
"""
import argparse
import contextlib
import math
import os
import sys
import tempfile

import numpy as np
from paraview import servermanager as sm
from paraview import simple as pv
from vtkmodules.numpy_interface import dataset_adapter as dsa
from paraview.vtk import vtkImageAppend
from vtkmodules.vtkIOImage import vtkPNGReader, vtkPNGWriter

PANEL = (700, 640)


def load(path, kind):
    """(reader, points (N,3), mass (N), radius (N), damage (N) or None, time) of one sidecar."""
    rd = pv.XDMFReader(FileNames=[path])
    rd.UpdatePipelineInformation()
    times = list(rd.TimestepValues) if hasattr(rd.TimestepValues, "__len__") else [rd.TimestepValues]
    t = float(times[0]) if times and times[0] is not None else 0.0
    rd.UpdatePipeline(t)
    d = dsa.WrapDataObject(sm.Fetch(rd))
    if hasattr(d, "GetNumberOfBlocks") or not hasattr(d, "Points"):
        raise SystemExit(f"render_cutaway: {path}: expected one point grid")
    pts = np.asarray(d.Points, dtype=float)
    pd = d.PointData
    mass = np.asarray(pd["mass"], dtype=float)
    if kind == "spheres":
        radius = np.asarray(pd["radius"], dtype=float)
    else:
        radius = np.cbrt(0.75 * np.asarray(pd["volume"], dtype=float) / math.pi)
    damage = np.asarray(pd["damage"], dtype=float) if "damage" in pd.keys() else None
    return rd, pts, mass, radius, damage, t


def weighted_median(x, m):
    out = []
    for k in range(3):
        o = np.argsort(x[:, k])
        c = np.cumsum(m[o])
        out.append(x[o[min(np.searchsorted(c, 0.5 * c[-1]), len(o) - 1)], k])
    return np.asarray(out)


def frame_radius(x, m, c):
    dist = np.linalg.norm(x - c, axis=1)
    o = np.argsort(dist)
    cm = np.cumsum(m[o])
    return float(dist[o[min(np.searchsorted(cm, 0.8 * cm[-1]), len(o) - 1)]])


def view_of(item):
    """(centre, half-width of the frame) of one snapshot."""
    _, x, m, r, _, _ = item
    c = weighted_median(x, m)
    return c, 1.3 * max(frame_radius(x, m, c), 2.0 * float(np.median(r)))


def render_one(item, kind, dmax, lim, out_png, label, bar_shown):
    rd, x, m, r, dmg, t = item
    c, _ = view_of(item)
    # radius array on the points (MPM: from the volume), then drop the quarter x > cx, y > cy
    src = rd
    if kind == "mpm":
        src = pv.Calculator(Input=src, AttributeType="Point Data", ResultArrayName="radius",
                            Function="(0.75*volume/3.141592653589793)^(1/3)")
    keep = pv.PythonCalculator(Input=src, ArrayName="keep",
                               Expression=f"1.0 - (inputs[0].Points[:,0] > {c[0]!r}) * (inputs[0].Points[:,1] > {c[1]!r})")
    cut = pv.Threshold(Input=keep, Scalars=["POINTS", "keep"], LowerThreshold=0.5, UpperThreshold=1.5,
                       ThresholdMethod="Between", AllScalars=0)
    view = pv.CreateRenderView()
    view.ViewSize = list(PANEL)
    view.Background = [1.0, 1.0, 1.0]
    view.UseColorPaletteForBackground = 0
    view.OrientationAxesVisibility = 1
    rep = pv.Show(cut, view)
    rep.SetRepresentationType("Point Gaussian")
    rep.ShaderPreset = "Sphere"
    rep.ScaleByArray = 1
    rep.SetScaleArray = ["POINTS", "radius"]
    rep.UseScaleFunction = 0  # the array is the radius itself
    rep.GaussianRadius = 1.0
    if dmg is not None:
        pv.ColorBy(rep, ("POINTS", "damage"))
        lut = pv.GetColorTransferFunction("damage")
        lut.ApplyPreset("Turbo", True)
        lut.RescaleTransferFunction(0.0, dmax)
        lut.AutomaticRescaleRangeMode = "Never"
        rep.SetScalarBarVisibility(view, bar_shown)
        bar = pv.GetScalarBar(lut, view)
        bar.Title = "damage"
        bar.ComponentTitle = ""
        bar.TitleColor = bar.LabelColor = [0.0, 0.0, 0.0]
        bar.WindowLocation = "Any Location"
        bar.Position = [0.86, 0.1]
        bar.ScalarBarLength = 0.5
        bar.Visibility = 1 if bar_shown else 0
    else:
        pv.ColorBy(rep, None)
        rep.AmbientColor = rep.DiffuseColor = [0.6, 0.6, 0.6]
    txt = pv.Text(Text=label)
    trep = pv.Show(txt, view)
    trep.Color = [0.0, 0.0, 0.0]
    trep.FontSize = 22
    trep.WindowLocation = "Upper Left Corner"
    pv.Render(view)  # the first render of a new view resets the camera: set it afterwards
    d = np.array([1.0, 0.55, 0.5])
    d /= np.linalg.norm(d)
    view.CameraFocalPoint = list(c)
    view.CameraPosition = list(c + 10.0 * lim * d)
    view.CameraViewUp = [0.0, 0.0, 1.0]
    view.CameraParallelProjection = 1
    view.CameraParallelScale = lim
    pv.Render(view)
    pv.SaveScreenshot(out_png, view, ImageResolution=list(PANEL))
    pv.Delete(view)
    return t


def side_by_side(pngs, out):
    app = vtkImageAppend()
    app.SetAppendAxis(0)
    readers = []
    for p in pngs:
        rr = vtkPNGReader()
        rr.SetFileName(p)
        rr.Update()
        readers.append(rr)
        app.AddInputConnection(rr.GetOutputPort())
    app.Update()
    tmp = os.path.join(os.path.dirname(os.path.abspath(out)), "." + os.path.basename(out) + ".tmp.png")
    w = vtkPNGWriter()
    w.SetFileName(tmp)
    w.SetInputConnection(app.GetOutputPort())
    w.Write()
    os.replace(tmp, out)  # atomic: a reader never sees half a PNG


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("files", nargs="+")
    ap.add_argument("--kind", choices=("mpm", "spheres"), required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--label", default="", help="prefix of each panel's caption (e.g. 'after hand-off')")
    ap.add_argument("--workdir", help="directory for the views (the caller removes it); default: a temporary one")
    ap.add_argument("--times", type=float, nargs="+",
                    help="the captions' times, one per file (default: each file's time attribute)")
    a = ap.parse_args(argv)
    if a.times is not None and len(a.times) != len(a.files):
        print(f"render_cutaway: {len(a.times)} --times for {len(a.files)} files", file=sys.stderr)
        return 2
    for f in a.files:
        if not os.path.isfile(f):
            print(f"render_cutaway: {f}: no such file", file=sys.stderr)
            return 2
    items = [load(f, a.kind) for f in a.files]
    dmax = max([float(np.max(it[4])) for it in items if it[4] is not None and it[4].size] + [0.0]) or 1.0
    lim = max(view_of(it)[1] for it in items)  # one scale for every view
    with tempfile.TemporaryDirectory(dir=os.path.dirname(os.path.abspath(a.out))) if a.workdir is None \
            else contextlib.nullcontext(a.workdir) as tmp:
        pngs = []
        for k, it in enumerate(items):
            tt = it[5] if a.times is None else a.times[k]
            when = f"{tt / 3600:.2f} h" if tt >= 7200 else f"{tt:.4g} s"
            label = f"{a.label}t = {when}\n{len(it[1])} {'particles' if a.kind == 'mpm' else 'spheres'}"
            p = os.path.join(tmp, f"panel_{k}.png")
            render_one(it, a.kind, dmax, lim, p, label, k == len(items) - 1)
            pngs.append(p)
        side_by_side(pngs, a.out)
    print(f"render_cutaway: wrote {a.out} ({len(pngs)} views, damage scale 0..{dmax:.3g})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
