"""Open a sphere file's XDMF sidecar with ParaView's two XDMF readers and print, per block, the
points, the cells, their VTK cell types and the cell arrays (a check that ParaView draws the bonds
of a file with /bonds as lines: block `bonds`, cell type 4 = VTK_POLY_LINE).

usage: pvpython --force-offscreen-rendering pipelines/nbody/pv_check_xdmf.py FILE.xmf
"""
import sys

import paraview.simple as ps
from paraview import servermanager as sm
import vtk


def blocks(d):
    if not d.IsA("vtkCompositeDataSet"):
        yield "(single grid)", d
        return
    it = d.NewIterator()
    it.InitTraversal()
    while not it.IsDoneWithTraversal():
        yield it.GetCurrentMetaData().Get(vtk.vtkCompositeDataSet.NAME()), it.GetCurrentDataObject()
        it.GoToNextItem()


for name, make in (("Xdmf3ReaderS", lambda f: ps.Xdmf3ReaderS(FileName=[f])),
                   ("XDMFReader", lambda f: ps.XDMFReader(FileNames=[f]))):
    r = make(sys.argv[1])
    r.UpdatePipeline()
    for bname, b in blocks(sm.Fetch(r)):
        types = sorted({b.GetCellType(i) for i in range(b.GetNumberOfCells())})
        arrays = [b.GetCellData().GetArrayName(i) for i in range(b.GetCellData().GetNumberOfArrays())]
        print(f"{name}: block {bname}: {b.GetNumberOfPoints()} points, {b.GetNumberOfCells()} cells, "
              f"cell types {types}, cell arrays {arrays}")
