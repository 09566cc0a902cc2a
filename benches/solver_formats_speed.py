#!/usr/bin/env python3
"""Reading and writing the solver formats, smartmesh beside meshio, on the same files in
the same run: SU2 (`.su2`), Fluent (`.fluent.msh`, meshio's `ansys`) and CGNS (`.cgns`,
HDF5: smartmesh's `cgns` build, meshio through h5py). OpenFOAM is not in meshio (no
writer, meshio #660) and is timed for smartmesh alone.

The mesh: the unit cube meshed by Gmsh's Python API (HXT, `--size`, 0.03 by default:
about 2.3 x 10^5 tetrahedra; 0.0155 gives about 10^6) with a physical volume and six
named sides, saved as MSH 4.1 binary; smartmesh writes `cube.meshb` (the cheap binary
side of every smartmesh timing), `cube.su2` and `cube.fluent.msh` from it, which both
tools then read.

- smartmesh (release build) is timed as whole processes: a read is `convert FILE
  out.meshb`, a write `convert cube.meshb OUT`; the `cube.meshb -> .meshb` row is the
  floor both include (start-up, the binary side).
- meshio is timed in this process: `meshio.read(FILE)`, and `meshio.write(OUT, mesh)` of
  the tetrahedra read from `cube.meshb` (meshio's SU2 writer crashes when markers are
  present, meshio #1419, so it writes the volume cells only; its `ansys` writer writes
  cells by their nodes, which Fluent does not read, meshio #1339).
- CGNS: meshio's reader knows only a base named `Base`, a zone `Zone1` and one section of
  tetrahedra (its own writer's layout, gzip-compressed, without the CGNS library's
  labels), so each tool reads the file it wrote itself; the other's file is tried too
  (timed when it reads, its failure printed otherwise). A smartmesh built without `cgns` leaves the row out.
Times are CPU seconds (user + system), each the best of `--repeat` runs.

    cargo build --release --features cgns
    python3 benches/solver_formats_speed.py [--size 0.03] [--repeat 2] [--dir /tmp/solver-speed]
"""

import argparse
import os
import resource
import shutil
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
BIN = Path(os.environ.get("SMARTMESH_BIN", ROOT / "target" / "release" / "smartmesh"))


def make_mesh(d, size):
    import gmsh

    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.option.setNumber("General.NumThreads", 2)
    gmsh.model.add("cube")
    gmsh.model.occ.addBox(0, 0, 0, 1, 1, 1)
    gmsh.model.occ.synchronize()
    gmsh.model.addPhysicalGroup(3, [1], 10, "Solid")
    for s in range(1, 7):
        gmsh.model.addPhysicalGroup(2, [s], s, f"Side{s}")
    gmsh.option.setNumber("Mesh.MeshSizeMax", size)
    gmsh.option.setNumber("Mesh.MeshSizeMin", size)
    gmsh.option.setNumber("Mesh.Algorithm3D", 10)
    gmsh.model.mesh.generate(3)
    _, tags, _ = gmsh.model.mesh.getElements(3)
    n = sum(len(t) for t in tags)
    gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
    gmsh.option.setNumber("Mesh.Binary", 1)
    gmsh.write(str(d / "cube.msh"))
    gmsh.finalize()
    return n


def child_cpu():
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def smartmesh(args, repeat):
    best = float("inf")
    for _ in range(repeat):
        t = child_cpu()
        subprocess.run([str(BIN), "-q", *args], check=True)
        best = min(best, child_cpu() - t)
    return best


def meshio_cpu(f, repeat):
    best, out = float("inf"), None
    for _ in range(repeat):
        t = time.process_time()
        out = f()
        best = min(best, time.process_time() - t)
    return best, out


def cross_read(args):
    """Whether a read of the other tool's file succeeds: 'reads' or the error's first line."""
    try:
        args()
        return "reads"
    except Exception as e:  # noqa: BLE001 - a tool's failure is a result
        return f"fails: {str(e).strip().splitlines()[0][:200] if str(e).strip() else type(e).__name__}"


def cgns_row(d, tets, repeat, meshio):
    """CGNS: each tool writes the cube's tetrahedra and reads its own file back."""
    ours, theirs = d / "cube.cgns", d / "m.cube.cgns"
    if subprocess.run([str(BIN), "-q", "convert", str(d / "cube.meshb"), str(ours)],
                      capture_output=True).returncode != 0:
        print("| CGNS | smartmesh built without the `cgns` feature | | | |")
        return
    sw = smartmesh(["convert", str(d / "cube.meshb"), str(ours)], repeat)
    sr = smartmesh(["convert", str(ours), str(d / "back.meshb")], repeat)
    mw, _ = meshio_cpu(lambda: meshio.write(theirs, tets, file_format="cgns"), repeat)
    mr, got = meshio_cpu(lambda: meshio.read(theirs, file_format="cgns"), repeat)
    cells = sum(len(c.data) for c in got.cells)
    print(f"| CGNS | {sr:.2f} | {mr:.2f} ({cells} cells, its own file) | {sw:.2f} | {mw:.2f} |")
    def ours_reads_theirs():
        o = subprocess.run([str(BIN), "-q", "convert", str(theirs), str(d / "x.meshb")],
                           capture_output=True, text=True)
        if o.returncode != 0:
            raise RuntimeError(f"exit {o.returncode}: {o.stderr.strip()}")

    print("smartmesh reads meshio's .cgns:", cross_read(ours_reads_theirs))
    read = cross_read(lambda: meshio.read(ours, file_format="cgns"))
    if read == "reads":
        mr, got = meshio_cpu(lambda: meshio.read(ours, file_format="cgns"), repeat)
        read = f"{mr:.2f} s ({sum(len(c.data) for c in got.cells)} cells)"
    print("meshio reads smartmesh's .cgns:", read)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--size", type=float, default=0.03)
    ap.add_argument("--repeat", type=int, default=2)
    ap.add_argument("--dir", default="/tmp/solver-speed")
    a = ap.parse_args()
    import meshio

    d = Path(a.dir)
    shutil.rmtree(d, ignore_errors=True)
    d.mkdir(parents=True)
    n = make_mesh(d, a.size)
    for out in ["cube.meshb", "cube.su2", "cube.fluent.msh"]:
        subprocess.run([str(BIN), "-q", "convert", str(d / "cube.msh"), str(d / out)], check=True)
    print(f"{n} tetrahedra; CPU seconds, best of {a.repeat}")
    floor = smartmesh(["convert", str(d / "cube.meshb"), str(d / "floor.meshb")], a.repeat)
    print(f"| format | smartmesh read | meshio read | smartmesh write | meshio write |")
    print("|---|---:|---:|---:|---:|")
    print(f"| floor (`.meshb` -> `.meshb`) | {floor:.2f} | | | |")
    tets, _ = meshio_cpu(lambda: meshio.read(d / "cube.meshb"), 1)
    m = meshio.read(d / "cube.meshb")
    tets = meshio.Mesh(m.points, [c for c in m.cells if c.type == "tetra"])
    for name, file, fmt in [("SU2", "cube.su2", "su2"), ("Fluent", "cube.fluent.msh", "ansys")]:
        sr = smartmesh(["convert", str(d / file), str(d / "back.meshb")], a.repeat)
        mr, got = meshio_cpu(lambda: meshio.read(d / file, file_format=fmt), a.repeat)
        out = d / ("w." + file)
        sw = smartmesh(["convert", str(d / "cube.meshb"), str(out)], a.repeat)
        try:
            mw, _ = meshio_cpu(lambda: meshio.write(d / ("m." + file), tets, file_format=fmt),
                               a.repeat)
            mw = f"{mw:.2f}"
        except Exception as e:  # noqa: BLE001 - a tool's failure is a result
            mw = f"fails: {type(e).__name__}"
        cells = sum(len(c.data) for c in got.cells)
        print(f"| {name} | {sr:.2f} | {mr:.2f} ({cells} cells) | {sw:.2f} | {mw} |")
    cgns_row(d, tets, a.repeat, meshio)
    sw = smartmesh(["convert", str(d / "cube.meshb"), str(d / "case.foam")], a.repeat)
    sr = smartmesh(["convert", str(d / "case.foam"), str(d / "back.meshb")], a.repeat)
    print(f"| OpenFOAM (ASCII case) | {sr:.2f} | not in meshio | {sw:.2f} | not in meshio |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
