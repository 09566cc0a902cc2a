"""Times meshio on the files the `formats` criterion bench leaves in target/bench-meshes/,
so that smartmesh and meshio are measured on the same bytes in the same session.

    cargo bench -p smartmesh-formats --bench formats      # writes the files, times smartmesh
    python3 formats/benches/compare_meshio.py [target/bench-meshes]
    SMARTMESH_BENCH_ONLY=vtk51_binary,medit_binary python3 formats/benches/compare_meshio.py ...

Prints one line per file: best of `repeat` wall times for meshio read and write (the
write is of the mesh meshio just read, in the same format and encoding).
"""
import os
import sys
import time

import meshio

DIR = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..", "..", "target", "bench-meshes")
REPEAT = int(os.environ.get("REPEAT", "3"))
# SMARTMESH_BENCH_ONLY=vtk51_ascii,vtk51_binary: some cases only (as in the criterion bench).
ONLY = [c for c in os.environ.get("SMARTMESH_BENCH_ONLY", "").split(",") if c]

CASES = [
    # file, meshio read format, meshio write kwargs
    ("gmsh41_ascii.msh", "gmsh", dict(file_format="gmsh", binary=False)),
    ("gmsh41_binary.msh", "gmsh", dict(file_format="gmsh", binary=True)),
    ("gmsh22_ascii.msh", "gmsh", dict(file_format="gmsh22", binary=False)),
    ("gmsh22_binary.msh", "gmsh", dict(file_format="gmsh22", binary=True)),
    ("vtu_zlib.vtu", "vtu", dict(file_format="vtu", binary=True, compression="zlib")),
    ("vtu_appended_raw.vtu", "vtu", dict(file_format="vtu", binary=True, compression=None)),
    ("vtu_ascii.vtu", "vtu", dict(file_format="vtu", binary=False)),
    ("vtk42_ascii.vtk", "vtk", dict(file_format="vtk42", binary=False)),
    ("vtk42_binary.vtk", "vtk", dict(file_format="vtk42", binary=True)),
    ("vtk51_ascii.vtk", "vtk", dict(file_format="vtk51", binary=False)),
    ("vtk51_binary.vtk", "vtk", dict(file_format="vtk51", binary=True)),
    ("medit_ascii.mesh", "medit", dict(file_format="medit")),
    ("obj.obj", "obj", dict(file_format="obj")),
]


def best(f):
    t = []
    for _ in range(REPEAT):
        t0 = time.perf_counter()
        f()
        t.append(time.perf_counter() - t0)
    return min(t)


def main():
    print(f"meshio {meshio.__version__}, best of {REPEAT}")
    out = os.path.join(DIR, "meshio_out")
    os.makedirs(out, exist_ok=True)
    for name, fmt, wkw in CASES:
        if ONLY and os.path.splitext(name)[0] not in ONLY:
            continue
        path = os.path.join(DIR, name)
        if not os.path.exists(path):
            print(f"{name:24s} missing")
            continue
        try:
            mesh = meshio.read(path, file_format=fmt)
            tr = best(lambda: meshio.read(path, file_format=fmt))
        except Exception as e:  # meshio cannot read some variants; say so
            print(f"{name:24s} read failed: {type(e).__name__}: {e}")
            continue
        target = os.path.join(out, name)
        try:
            tw = best(lambda: meshio.write(target, mesh, **wkw))
        except Exception as e:
            print(f"{name:24s} read {tr:8.3f} s   write failed: {type(e).__name__}: {e}")
            continue
        print(f"{name:24s} read {tr:8.3f} s   write {tw:8.3f} s")


if __name__ == "__main__":
    main()
