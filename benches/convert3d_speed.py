#!/usr/bin/env python3
"""`smartmesh convert` on a tetrahedral mesh of about 10^6 cells, beside meshio and a plain
copy of the bytes, in the same run.

The mesh: the unit cube meshed by Gmsh's Python API (HXT 3D Delaunay, `--size` the mesh
size, 0.0185 by default: about 10^6 tetrahedra), with a physical volume and six
physical surfaces, saved by Gmsh as MSH 4.1 ASCII and binary. meshio writes the VTU
(binary, raw) and the Medit `.mesh` and `.meshb` inputs from it, so that each reader reads a file
another tool wrote.

Each case converts IN to OUT:
- smartmesh: `smartmesh convert IN OUT` (the release build; VTU written raw appended,
  as meshio writes it), the process;
- meshio: `meshio.read(IN)` then `meshio.write(OUT, ...)` in this process (its import is
  not counted), and the read and the write apart;
- copy: `cp IN OUT` (which copies inside the kernel) and `cat IN > OUT` (through user
  space) of the input's bytes, the floor for a binary-to-binary conversion.
Times are CPU times (user + system) and wall times of the same runs, each the best of
`--repeat` runs, the tools alternating: the machine is shared, and wall times there
measure the other jobs as much as the work. A case smartmesh refuses (a writer or a
reader that holds no tetrahedra yet) is reported with its error line, and a case where its
report lists the tetrahedra as dropped is reported so, not timed as a conversion.

    cargo build --release
    python3 benches/convert3d_speed.py                      # files in /tmp/convert3d-speed
    python3 benches/convert3d_speed.py --size 0.04 --repeat 1   # a quick check (~10^5)
    python3 benches/convert3d_speed.py --keep; python3 benches/convert3d_speed.py --reuse --only VTU

Targets (issue 34): ASCII at least 5x faster than meshio both ways; binary within 1.5x of
a copy of the bytes.
"""

import argparse
import json
import os
import resource
import shutil
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def make_mesh(dirpath, size):
    """The cube meshed by Gmsh, saved as MSH 4.1 ASCII and binary; returns the cell count."""
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
    t = time.perf_counter()
    gmsh.model.mesh.generate(3)
    print(f"gmsh meshed in {time.perf_counter() - t:.1f} s", flush=True)
    types, tags, _ = gmsh.model.mesh.getElements(3)
    ntets = sum(len(t) for t in tags)
    gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
    gmsh.option.setNumber("Mesh.Binary", 0)
    gmsh.write(str(dirpath / "cube41_ascii.msh"))
    gmsh.option.setNumber("Mesh.Binary", 1)
    gmsh.write(str(dirpath / "cube41_binary.msh"))
    gmsh.finalize()
    return ntets


def children_cpu():
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def timed(f):
    """CPU time (user + system, this process and the children it waited for) and wall
    time of `f`, in one run: on a machine shared with other jobs the wall time measures
    the load as much as the work."""
    c = time.process_time() + children_cpu()
    w = time.perf_counter()
    r = f()
    return (time.process_time() + children_cpu() - c, time.perf_counter() - w), r


def smartmesh(exe, src, dst, extra):
    """(CPU, wall) times of `smartmesh convert`, or (None, why) when it refuses or drops tetrahedra."""
    cmd = [exe, "convert", str(src), str(dst), "--json", "-q"] + extra
    dt, r = timed(lambda: subprocess.run(cmd, capture_output=True, text=True))
    if r.returncode != 0:
        return None, "refused: " + r.stderr.strip().splitlines()[-1].replace("smartmesh: error: ", "")
    dropped = json.loads(r.stdout).get("dropped", [])
    lost = [d for d in dropped if "tetra" in d]
    if lost:
        return None, "drops the tetrahedra: " + lost[0]
    return dt, None


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--size", type=float, default=0.0185)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--dir", default="/tmp/convert3d-speed")
    ap.add_argument("--keep", action="store_true", help="keep the files (default: deleted)")
    ap.add_argument("--only", help="the cases whose label contains this text")
    ap.add_argument("--reuse", action="store_true", help="reuse the Gmsh files of a --keep run")
    ap.add_argument("--exe", default=str(ROOT / "target" / "release" / "smartmesh"))
    args = ap.parse_args()

    import meshio

    exe = args.exe
    if not os.path.exists(exe):
        sys.exit(f"{exe} is missing: cargo build --release")
    d = Path(args.dir)
    d.mkdir(parents=True, exist_ok=True)
    print(f"load average before: {os.getloadavg()}")
    if args.reuse and (d / "cube41_binary.msh").exists():
        ntets = None
    else:
        ntets = make_mesh(d, args.size)
    m = meshio.read(d / "cube41_binary.msh")
    npts = len(m.points)
    ntets = ntets or sum(len(c.data) for c in m.cells if c.type == "tetra")
    meshio.write(d / "cube_raw.vtu", m, binary=True, compression=None)
    # meshio's Medit writer takes no point data (Gmsh's `gmsh:dim_tags` would break it).
    meshio.write(d / "cube.mesh", meshio.Mesh(m.points, m.cells))
    meshio.write(d / "cube.meshb", meshio.Mesh(m.points, m.cells))
    print(f"{ntets} tetrahedra, {npts} points; meshio {meshio.__version__}; best of {args.repeat}")

    msh_b = dict(file_format="gmsh", binary=True)
    vtu = dict(file_format="vtu", binary=True, compression=None)
    medit = dict(file_format="medit")
    # smartmesh's VTU default is zlib-compressed base64; meshio writes raw appended data.
    RAW = ["--vtu-encoding", "appended", "--no-compress"]
    # (label, input, output, smartmesh options, meshio write kwargs, copy floor?)
    cases = [
        ("MSH 4.1 ASCII -> ASCII", "cube41_ascii.msh", "o_a.msh", [], dict(file_format="gmsh", binary=False), False),
        ("MSH 4.1 ASCII -> binary", "cube41_ascii.msh", "o_b.msh", ["--binary"], msh_b, False),
        ("MSH 4.1 binary -> ASCII", "cube41_binary.msh", "o_a.msh", [], dict(file_format="gmsh", binary=False), False),
        ("MSH 4.1 binary -> binary", "cube41_binary.msh", "o_b.msh", ["--binary"], msh_b, True),
        ("MSH 4.1 binary -> VTU raw", "cube41_binary.msh", "o.vtu", RAW, vtu, False),
        ("VTU raw -> MSH 4.1 binary", "cube_raw.vtu", "o_b.msh", ["--binary"], msh_b, False),
        ("VTU raw -> VTU raw", "cube_raw.vtu", "o.vtu", RAW, vtu, True),
        ("MSH 4.1 binary -> Medit .mesh", "cube41_binary.msh", "o.mesh", [], medit, False),
        ("Medit .mesh -> MSH 4.1 binary", "cube.mesh", "o_b.msh", ["--binary"], msh_b, False),
        ("MSH 4.1 binary -> Medit .meshb", "cube41_binary.msh", "o.meshb", [], medit, False),
        ("Medit .meshb -> MSH 4.1 binary", "cube.meshb", "o_b.msh", ["--binary"], msh_b, False),
        ("Medit .meshb -> .meshb", "cube.meshb", "o.meshb", [], medit, True),
    ]
    inf = (float("inf"), float("inf"))

    def keep(best, key, t):
        best[key] = (min(best[key][0], t[0]), min(best[key][1], t[1]))

    rows = []
    for label, src, dst, extra, wkw, floor in cases:
        if args.only and args.only not in label:
            continue
        src, dst = d / src, d / dst
        best = {k: inf for k in ("smartmesh", "meshio", "read", "write", "cp", "cat")}
        why = None
        for _ in range(args.repeat):
            dt, why = smartmesh(exe, src, dst, extra)
            if dt is None:
                break
            keep(best, "smartmesh", dt)
            if dst.exists():
                dst.unlink()
            tr, mm = timed(lambda: meshio.read(src))
            if wkw["file_format"] == "medit":
                mm.point_data = {}
                mm.cell_data = {}
            if wkw["file_format"] == "gmsh" and "gmsh:dim_tags" not in mm.point_data:
                # meshio's MSH 4.1 writer refuses several cell kinds without Gmsh's
                # entities (which a Medit file has not): it writes the tetrahedra only.
                mm = meshio.Mesh(mm.points, [c for c in mm.cells if c.type == "tetra"])
            tw, _ = timed(lambda: meshio.write(dst, mm, **wkw))
            keep(best, "meshio", (tr[0] + tw[0], tr[1] + tw[1]))
            keep(best, "read", tr)
            keep(best, "write", tw)
            dst.unlink()
            if floor:
                # cp copies inside the kernel (copy_file_range); cat passes the bytes
                # through user space, as a converter must.
                tc, _ = timed(lambda: subprocess.run(["cp", str(src), str(dst)], check=True))
                dst.unlink()
                tk, _ = timed(lambda: subprocess.run(f"cat '{src}' > '{dst}'", shell=True, check=True))
                keep(best, "cat", tk)
                keep(best, "cp", tc)
                dst.unlink()
        size = src.stat().st_size / 1e6
        if why:
            rows.append(f"| {label} | {size:.1f} MB | {why} | | | |")
        else:
            sm, mi, rd, wr = best["smartmesh"], best["meshio"], best["read"], best["write"]
            cp = ""
            if floor:
                c, k = best["cp"], best["cat"]
                cp = (f"{sm[0] / c[0]:.1f}x cp ({c[0]:.3f} s; wall {c[1]:.3f} s), "
                      f"{sm[0] / k[0]:.1f}x cat ({k[0]:.3f} s; wall {k[1]:.3f} s)")
            rows.append(
                f"| {label} | {size:.1f} MB | {sm[0]:.2f} s (wall {sm[1]:.2f}) "
                f"| {mi[0]:.2f} s ({rd[0]:.2f} + {wr[0]:.2f}; wall {mi[1]:.2f}) "
                f"| {mi[0] / sm[0]:.1f}x (wall {mi[1] / sm[1]:.1f}x) | {cp} |"
            )
        print(rows[-1], flush=True)
    print()
    print("| conversion | input | smartmesh convert, CPU (wall) | meshio read + write, CPU (wall) | meshio / smartmesh | smartmesh / copy, CPU |")
    print("|---|---|---|---|---|---|")
    for r in rows:
        print(r)
    print(f"\nload average after: {os.getloadavg()}")
    if not args.keep:
        shutil.rmtree(d)


if __name__ == "__main__":
    main()
