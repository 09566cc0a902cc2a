#!/usr/bin/env python3
"""Curved boundaries kept by `smartmesh remesh` and by MMG's mmg2d_O3, same run, same
input mesh and same metric.

Four domains whose curved boundary is known exactly:

    disk     the disk of radius 0.5 about the origin
    holed    the unit square with a hole of radius 0.25 about (0.5, 0.5)
    ellipse  the ellipse of semi-axes 0.5 and 0.25
    naca     the NACA 0012 (closed trailing edge, 4-digit formula with -0.1036) of chord
             1 in the box [-0.5, 1.5] x [-0.5, 0.5]

The input is meshed by Gmsh (OpenCASCADE curves; the airfoil as a B-spline through 400
points of the exact formula), fine along the curved boundary (600 edges on it) and
coarse away from it (size 0.05), and every node Gmsh put on the curved boundary is then moved onto the
exact curve (by at most 1e-7 for the airfoil's spline, by rounding for the others), so the
input's boundary vertices are on the curve. The metric is isotropic, the size growing
fourfold from left to right (h = h0 (0.5 + 1.5 (x - xmin)/(xmax - xmin))), so along the
curve a remesher both refines and coarsens the input; h0 is set so that MMG's output has
about 10^4 and 10^5 triangles (from the area of equilateral triangles of the metric's
size, corrected by one MMG run). Both tools read the
same .mesh + .sol:

    smartmesh remesh in.mesh -o ours.mesh --hausd 0.01
    mmg2d_O3 in.mesh -sol in.sol -out mmg.mesh -hgrad -1 -hausd 0.01 -v -1

(`-hgrad -1`: MMG adapts to the metric as given; `-hausd 0.01` is MMG's default, given
to both so that both bound the curve's sagitta the same way.) Measured on each output,
by this script: the largest distance of the vertices on the curved boundary to the exact
curve (closest point found by sampling then golden-section search on the curve's
parameter; analytic for circles), the relative change of the domain's area from the
input mesh's, and the relative error of the output's area against the exact domain.

    python3 benches/curved_boundary.py                    # 1e4,1e5, every domain
    python3 benches/curved_boundary.py --sizes 1e4 --cases disk,naca
    python3 benches/curved_boundary.py --extra "--boundary polyline"   # another run of ours
"""

import argparse
import json
import math
import shlex
import shutil
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
T = 0.12  # NACA 0012 thickness


def real_mmg():
    try:
        import mmgpy  # noqa: F401

        p = Path(mmgpy.__file__).parent / "bin" / "mmg2d_O3"
        if p.exists():
            return str(p)
    except ImportError:
        pass
    return shutil.which("mmg2d_O3")


def run(cmd):
    t = time.perf_counter()
    r = subprocess.run(cmd, capture_output=True, text=True)
    dt = time.perf_counter() - t
    if r.returncode != 0:
        sys.exit(f"failed ({r.returncode}): {' '.join(cmd)}\n{r.stdout[-2000:]}\n{r.stderr[-2000:]}")
    return dt


# ---- the exact curves: c(u) for u in [0, 1), closed ------------------------------------

def naca_yt(x):
    x = np.clip(x, 0.0, 1.0)
    return 5 * T * (0.2969 * np.sqrt(x) - 0.1260 * x - 0.3516 * x**2 + 0.2843 * x**3 - 0.1036 * x**4)


def curve_point(case, u):
    b = 2 * np.pi * np.asarray(u)
    if case == "disk":
        return np.stack([0.5 * np.cos(b), 0.5 * np.sin(b)], -1)
    if case == "holed":
        return np.stack([0.5 + 0.25 * np.cos(b), 0.5 + 0.25 * np.sin(b)], -1)
    if case == "ellipse":
        return np.stack([0.5 * np.cos(b), 0.25 * np.sin(b)], -1)
    # naca: x = cos^2(b/2) runs 1 -> 0 -> 1, the upper side first.
    x = np.cos(b / 2) ** 2
    return np.stack([x, np.sign(np.sin(b)) * naca_yt(x)], -1)


def distance_to_curve(case, p):
    """Distance of each point of p (n x 2) to the exact curve, and its closest point."""
    p = np.asarray(p, dtype=float)
    if case in ("disk", "holed"):
        c, r = (np.zeros(2), 0.5) if case == "disk" else (np.array([0.5, 0.5]), 0.25)
        d = p - c
        n = np.hypot(d[:, 0], d[:, 1])
        return np.abs(n - r), c + d * (r / n)[:, None]
    from scipy.spatial import cKDTree

    m = 200_000
    us = (np.arange(m) + 0.5) / m
    tree = cKDTree(curve_point(case, us))
    _, i = tree.query(p)
    lo, hi = us[i] - 1.0 / m, us[i] + 1.0 / m
    g = (math.sqrt(5) - 1) / 2
    f = lambda u: np.sum((curve_point(case, u) - p) ** 2, -1)
    for _ in range(80):
        a, b = hi - g * (hi - lo), lo + g * (hi - lo)
        left = f(a) < f(b)
        hi = np.where(left, b, hi)
        lo = np.where(left, lo, a)
    u = 0.5 * (lo + hi)
    q = curve_point(case, u)
    return np.sqrt(np.sum((q - p) ** 2, -1)), q


def exact_area(case):
    if case == "disk":
        return math.pi * 0.25
    if case == "holed":
        return 1.0 - math.pi * 0.0625
    if case == "ellipse":
        return math.pi * 0.5 * 0.25
    # 2 * integral of y_t over [0, 1], with x = s^2 to take the square root away.
    s = np.linspace(0.0, 1.0, 2_000_001)
    f = naca_yt(s * s) * 2 * s
    return 2.0 - 2.0 * float(np.sum((f[1:] + f[:-1]) * 0.5 * np.diff(s)))


# ---- the input ------------------------------------------------------------------------

def make_input(case, path_msh):
    import gmsh

    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.model.add(case)
    occ = gmsh.model.occ
    if case == "disk":
        s = occ.addDisk(0, 0, 0, 0.5, 0.5)
    elif case == "ellipse":
        s = occ.addDisk(0, 0, 0, 0.5, 0.25)
    elif case == "holed":
        s = occ.cut([(2, occ.addRectangle(0, 0, 0, 1, 1))], [(2, occ.addDisk(0.5, 0.5, 0, 0.25, 0.25))])[0][0][1]
    else:
        n = 400
        pts = curve_point("naca", np.arange(n) / n)
        tags = [occ.addPoint(x, y, 0) for x, y in pts]
        spline = occ.addSpline(tags + [tags[0]])
        foil = occ.addPlaneSurface([occ.addCurveLoop([spline])])
        s = occ.cut([(2, occ.addRectangle(-0.5, -0.5, 0, 2, 1))], [(2, foil)])[0][0][1]
    occ.synchronize()
    curves = [c[1] for c in gmsh.model.getBoundary([(2, s)], oriented=False)]
    # The curved curve: the one whose middle is on the exact curve.
    curved = []
    for c in curves:
        lo, hi = gmsh.model.getParametrizationBounds(1, c)
        xyz = gmsh.model.getValue(1, c, [0.5 * (lo[0] + hi[0])])
        if distance_to_curve(case, np.array([xyz[:2]]))[0][0] < 1e-3:
            curved.append(c)
    straight = [c for c in curves if c not in curved]
    gmsh.model.addPhysicalGroup(1, curved, 1)
    if straight:
        gmsh.model.addPhysicalGroup(1, straight, 2)
    gmsh.model.addPhysicalGroup(2, [s], 10)
    length = {"disk": math.pi, "holed": math.pi / 2, "ellipse": 2.42, "naca": 2.04}[case]
    fine = length / 600
    f = gmsh.model.mesh.field
    d = f.add("Distance")
    f.setNumbers(d, "CurvesList", curved)
    f.setNumber(d, "Sampling", 2000)
    th = f.add("Threshold")
    f.setNumber(th, "InField", d)
    f.setNumber(th, "SizeMin", fine)
    f.setNumber(th, "SizeMax", 0.05)
    f.setNumber(th, "DistMin", 0.0)
    f.setNumber(th, "DistMax", 0.3)
    f.setAsBackgroundMesh(th)
    gmsh.option.setNumber("Mesh.MeshSizeExtendFromBoundary", 0)
    gmsh.option.setNumber("Mesh.MeshSizeFromPoints", 0)
    gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", 0)
    gmsh.model.mesh.generate(2)
    # Every node on the curved curve onto the exact curve.
    for c in curved:
        tags, xyz, _ = gmsh.model.mesh.getNodes(1, c, includeBoundary=True)
        p = xyz.reshape(-1, 3)
        _, q = distance_to_curve(case, p[:, :2])
        for t, (x, y) in zip(tags, q):
            gmsh.model.mesh.setNode(int(t), [x, y, 0.0], [])
    gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
    gmsh.write(str(path_msh))
    gmsh.finalize()


# ---- Medit .mesh / .sol ----------------------------------------------------------------

def read_medit(path):
    """Vertices (n x 2), triangles (m x 3, 0-based), edges (k x 2, 0-based) and edge refs."""
    toks = Path(path).read_text().split()
    sizes = {"Vertices": 3, "Triangles": 4, "Edges": 3, "Corners": 1, "RequiredVertices": 1,
             "Ridges": 1, "RequiredEdges": 1, "Quadrilaterals": 5, "Normals": 2, "Tangents": 2,
             "NormalAtVertices": 2, "TangentAtVertices": 2, "RequiredTriangles": 1}
    out = {}
    i = 0
    while i < len(toks):
        k = toks[i]
        if k in ("MeshVersionFormatted", "Dimension"):
            i += 2
        elif k in sizes:
            n = int(toks[i + 1])
            w = sizes[k]
            out[k] = np.array(toks[i + 2:i + 2 + n * w], dtype=float).reshape(n, w)
            i += 2 + n * w
        else:
            i += 1
    v = out["Vertices"][:, :2]
    t = out["Triangles"][:, :3].astype(int) - 1
    e = out.get("Edges", np.zeros((0, 3)))
    return v, t, e[:, :2].astype(int) - 1, e[:, 2].astype(int)


def area(v, t):
    a, b, c = v[t[:, 0]], v[t[:, 1]], v[t[:, 2]]
    return float(np.sum(np.abs((b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0]))) / 2)


def write_sol(mesh_path, sol_path, case, scale):
    v, _, _, _ = read_medit(mesh_path)
    h = size_at(v, scale)
    m = 1.0 / (h * h)
    rows = [f"{float(x)!r} 0 {float(x)!r}" for x in m]
    Path(sol_path).write_text("MeshVersionFormatted 2\n\nDimension 2\n\nSolAtVertices\n%d\n1 3\n%s\n\nEnd\n" % (len(rows), "\n".join(rows)))


def size_at(v, scale):
    lo, hi = v[:, 0].min(), v[:, 0].max()
    return (0.5 + 1.5 * (v[:, 0] - lo) / (hi - lo)) / math.sqrt(scale)


def expected_triangles(mesh_path):
    """Equilateral triangles of the metric's size (scale 1) that fill the mesh."""
    v, t, _, _ = read_medit(mesh_path)
    lo, hi = v[:, 0].min(), v[:, 0].max()
    c = (v[t[:, 0]] + v[t[:, 1]] + v[t[:, 2]]) / 3
    h = 0.5 + 1.5 * (c[:, 0] - lo) / (hi - lo)
    a, b, d = v[t[:, 0]], v[t[:, 1]], v[t[:, 2]]
    ar = np.abs((b[:, 0] - a[:, 0]) * (d[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (d[:, 0] - a[:, 0])) / 2
    return float(np.sum(ar / (math.sqrt(3) / 4 * h * h)))


def measure(case, out_mesh, input_area):
    v, t, e, ref = read_medit(out_mesh)
    on = np.unique(e[ref == 1].ravel())
    d, _ = distance_to_curve(case, v[on])
    a = area(v, t)
    return {"triangles": int(len(t)), "curve_vertices": int(len(on)), "max_distance": float(d.max()),
            "area_change": abs(a - input_area) / input_area, "area_error": abs(a - exact_area(case)) / exact_area(case)}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--sizes", default="1e4,1e5")
    ap.add_argument("--cases", default="disk,holed,ellipse,naca")
    ap.add_argument("--work", default=str(ROOT / "target" / "curved-boundary"))
    ap.add_argument("--smartmesh", default=str(ROOT / "target" / "release" / "smartmesh"))
    ap.add_argument("--mmg", default=real_mmg())
    ap.add_argument("--extra", action="append", default=[], help="another run of smartmesh with these further arguments")
    a = ap.parse_args()
    if not a.mmg:
        sys.exit("mmg2d_O3 not found (pip install mmgpy)")
    work = Path(a.work)
    work.mkdir(parents=True, exist_ok=True)
    sm = a.smartmesh
    results = []
    for case in a.cases.split(","):
        msh = work / f"{case}.msh"
        make_input(case, msh)
        base = work / f"{case}.mesh"
        run([sm, "convert", str(msh), str(base)])
        v, t, _, _ = read_medit(base)
        a_in = area(v, t)
        for target in [float(x) for x in a.sizes.split(",")]:
            tag = f"{case}-{int(target):d}"
            inp = work / f"in-{tag}.mesh"
            shutil.copy(base, inp)
            # The scale: equilateral triangles of the metric's size, then one MMG run.
            scale = target / expected_triangles(base)
            write_sol(base, inp.with_suffix(".sol"), case, scale)
            run([a.mmg, str(inp), "-sol", str(inp.with_suffix(".sol")), "-out", str(work / "calib.mesh"), "-hgrad", "-1", "-hausd", "0.01", "-v", "-1"])
            scale *= target / len(read_medit(work / "calib.mesh")[1])
            write_sol(base, inp.with_suffix(".sol"), case, scale)
            tools = [("smartmesh", [sm, "remesh", str(inp), "--hausd", "0.01", "-o"])]
            tools += [(f"smartmesh {x}", [sm, "remesh", str(inp), "--hausd", "0.01"] + shlex.split(x) + ["-o"]) for x in a.extra]
            tools += [("mmg2d_O3", [a.mmg, str(inp), "-sol", str(inp.with_suffix(".sol")), "-hgrad", "-1", "-hausd", "0.01", "-v", "-1", "-out"])]
            for name, cmd in tools:
                out = work / f"{name.replace(' ', '_').replace('-', '')}-{tag}.mesh"
                dt = run(cmd + [str(out)])
                r = {"case": case, "target": int(target), "tool": name, "seconds": dt, "input_triangles": int(len(t))}
                r.update(measure(case, out, a_in))
                results.append(r)
                print(json.dumps(r), file=sys.stderr, flush=True)
    print("| case | target | tool | triangles | curve vertices | max distance to the curve | area change vs input | area error vs exact | wall s |")
    print("|---|---|---|---|---|---|---|---|---|")
    for r in results:
        print(f"| {r['case']} | {r['target']:.0e} | {r['tool']} | {r['triangles']} | {r['curve_vertices']} | {r['max_distance']:.2e} | "
              f"{r['area_change']:.2e} | {r['area_error']:.2e} | {r['seconds']:.2f} |")
    (work / "results.json").write_text(json.dumps(results, indent=1))


if __name__ == "__main__":
    main()
