#!/usr/bin/env python3
"""Which files meshio reads and which smartmesh reads.

Every file under the public fixtures folder (all of its folders) and a set of VTK
samples this script makes with VTK itself (every legacy dataset, XML PolyData,
multi-piece and parallel files, every linear and quadratic volume cell) is given to
`meshio.read` and to `smartmesh info`; a file counts as read when meshio returns a mesh
or smartmesh exits 0. Prints both counts and the files one reads and the other does not.

    python3 benches/read_coverage.py [--smartmesh target/release/smartmesh]
        [--fixtures ../shared/fixtures/public]

A sibling file that is no mesh by itself (a `.sol`, Triangle's `.node`...) counts as
a file like any other: both tools are asked about every file, as a user would be.
"""

import argparse
import contextlib
import io
import os
import subprocess
import sys
import tempfile
import warnings


def vtk_samples(d):
    """Writes the VTK samples into `d` and returns their paths."""
    import vtk

    paths = []

    def legacy(obj, stem):
        for ver in (42, 51):
            for binary in (False, True):
                p = os.path.join(d, f"{stem}_{ver}_{'bin' if binary else 'ascii'}.vtk")
                w = vtk.vtkDataSetWriter()
                w.SetInputData(obj)
                w.SetFileName(p)
                w.SetFileVersion(ver)
                w.SetFileTypeToBinary() if binary else w.SetFileTypeToASCII()
                w.Write()
                paths.append(p)

    pts = vtk.vtkPoints()
    for p in [(0, 0, 0), (1, 0, 0), (2, 0, 0), (0, 1, 0), (1, 1, 0), (2, 1, 0), (0.5, 2, 0), (1.5, 2.5, 0)]:
        pts.InsertNextPoint(p)
    m = vtk.vtkPolyData()
    m.SetPoints(pts)
    cells = vtk.vtkCellArray()
    cells.InsertNextCell(5, [0, 1, 4, 6, 3])
    cells.InsertNextCell(3, [1, 2, 5])
    m.SetPolys(cells)
    strips = vtk.vtkCellArray()
    strips.InsertNextCell(4, [3, 0, 4, 1])
    m.SetStrips(strips)
    legacy(m, "polydata")
    w = vtk.vtkXMLPolyDataWriter()
    w.SetInputData(m)
    w.SetFileName(os.path.join(d, "polydata.vtp"))
    w.Write()
    paths.append(os.path.join(d, "polydata.vtp"))

    img = vtk.vtkImageData()
    img.SetDimensions(3, 4, 2)
    legacy(img, "structured_points")
    rg = vtk.vtkRectilinearGrid()
    rg.SetDimensions(3, 2, 2)
    for f, vals in ((rg.SetXCoordinates, [0, 1, 3]), (rg.SetYCoordinates, [0, 2]), (rg.SetZCoordinates, [0, 0.5])):
        c = vtk.vtkDoubleArray()
        for v in vals:
            c.InsertNextValue(v)
        f(c)
    legacy(rg, "rectilinear")
    sg = vtk.vtkStructuredGrid()
    sg.SetDimensions(2, 2, 2)
    sp = vtk.vtkPoints()
    for k in range(2):
        for j in range(2):
            for i in range(2):
                sp.InsertNextPoint(i + 0.3 * j, j, k)
    sg.SetPoints(sp)
    legacy(sg, "structured_grid")

    # One cell of each volume type, at VTK's own parametric coordinates.
    for cls in (vtk.vtkTetra, vtk.vtkHexahedron, vtk.vtkWedge, vtk.vtkPyramid, vtk.vtkQuadraticTetra,
                vtk.vtkQuadraticHexahedron, vtk.vtkTriQuadraticHexahedron, vtk.vtkQuadraticWedge,
                vtk.vtkBiQuadraticQuadraticWedge, vtk.vtkQuadraticPyramid):
        c = cls()
        pc = c.GetParametricCoords()
        g = vtk.vtkUnstructuredGrid()
        p = vtk.vtkPoints()
        n = c.GetNumberOfPoints()
        for i in range(n):
            p.InsertNextPoint(pc[3 * i], pc[3 * i + 1], pc[3 * i + 2])
        g.SetPoints(p)
        g.InsertNextCell(c.GetCellType(), n, list(range(n)))
        name = cls.__name__[3:]
        for ext, w in (("vtu", vtk.vtkXMLUnstructuredGridWriter()), ("vtk", vtk.vtkUnstructuredGridWriter())):
            path = os.path.join(d, f"{name}.{ext}")
            w.SetInputData(g)
            w.SetFileName(path)
            w.Write()
            paths.append(path)

    src = vtk.vtkSphereSource()
    tri = vtk.vtkDataSetTriangleFilter()
    tri.SetInputConnection(src.GetOutputPort())
    piece = vtk.vtkExtractUnstructuredGridPiece()
    piece.SetInputConnection(tri.GetOutputPort())
    w = vtk.vtkXMLPUnstructuredGridWriter()
    w.SetInputConnection(piece.GetOutputPort())
    w.SetFileName(os.path.join(d, "parallel.pvtu"))
    w.SetNumberOfPieces(2)
    w.SetStartPiece(0)
    w.SetEndPiece(1)
    w.Write()
    paths.append(os.path.join(d, "parallel.pvtu"))
    w = vtk.vtkXMLUnstructuredGridWriter()
    w.SetInputConnection(piece.GetOutputPort())
    w.SetFileName(os.path.join(d, "two_pieces.vtu"))
    w.SetNumberOfPieces(2)
    w.Write()
    paths.append(os.path.join(d, "two_pieces.vtu"))
    return paths


def meshio_reads(path):
    import meshio

    # meshio prints its warnings, and some readers end the program (`SystemExit`)
    # rather than raise: both are kept from the report.
    sink = io.StringIO()
    try:
        with warnings.catch_warnings(), contextlib.redirect_stdout(sink), contextlib.redirect_stderr(sink):
            warnings.simplefilter("ignore")
            meshio.read(path)
        return True
    except BaseException:
        return False


def smartmesh_reads(exe, path):
    r = subprocess.run([exe, "info", path], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return r.returncode == 0


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--smartmesh", default=os.path.join(here, "..", "target", "release", "smartmesh"))
    ap.add_argument("--fixtures", default=os.path.join(here, "..", "..", "shared", "fixtures", "public"))
    a = ap.parse_args()
    files = sorted(
        os.path.join(r, f) for r, _, fs in os.walk(a.fixtures) for f in fs if f != "MANIFEST.md"
    )
    nfix = len(files)
    with tempfile.TemporaryDirectory() as d:
        files += vtk_samples(d)
        rows = [(f, meshio_reads(f), smartmesh_reads(a.smartmesh, f)) for f in files]
    rel = lambda f: os.path.relpath(f, a.fixtures) if f.startswith(a.fixtures) else "samples/" + os.path.basename(f)
    print(f"files: {len(rows)} ({nfix} public fixtures, {len(rows) - nfix} VTK samples made here)")
    print(f"meshio reads:    {sum(m for _, m, _ in rows)}")
    print(f"smartmesh reads: {sum(s for _, _, s in rows)}")
    print("read by meshio, not by smartmesh:")
    for f, m, s in rows:
        if m and not s:
            print("   ", rel(f))
    print("read by smartmesh, not by meshio:")
    for f, m, s in rows:
        if s and not m:
            print("   ", rel(f))
    return 0


if __name__ == "__main__":
    sys.exit(main())
