"""Side by side: `smartmesh layer` against Gmsh's BoundaryLayer field (gmsh from PyPI,
its Python API, quads on) on the same geometries and the same heights.

Each geometry is built once in Gmsh (lines and circle arcs with physical groups) and
meshed twice with the same sizes: without a boundary layer (the input `smartmesh layer`
then skins) and with the BoundaryLayer field on the wall curves (Size = first height,
Ratio, Thickness; fans at the sharp points). Both results are measured by
`smartmesh info --json`: layers found from the cells, per-layer height and ratio, min
scaled Jacobian, max skewness, cell counts, validity (positive corners, no overlap, no
hanging node). Times: Gmsh's meshing with the field against Gmsh's meshing without it
plus `smartmesh layer` (release build, best of three).

    cargo build --release
    python3 benches/compare_gmsh_layer.py            # table on stdout, files in target/compare-layer/
"""
import json
import math
import os
import subprocess
import sys
import time

import gmsh

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
OUT = os.path.join(ROOT, "target", "compare-layer")
SM = os.environ.get("SMARTMESH_BIN", os.path.join(ROOT, "target", "release", "smartmesh"))


def naca_points():
    rows = [l.split("#")[0].split() for l in open(os.path.join(ROOT, "fixtures", "naca0012.poly"))]
    rows = [r for r in rows if r]
    n = int(rows[0][0])
    pts = [(float(r[1]), float(r[2])) for r in rows[1:1 + n]]
    return pts[4:]  # the box corners first, then the airfoil


def build(name):
    """Adds the geometry `name` to the current model; returns (wall curve tags, fan point
    tags, far size, wall size, heights (h0, ratio, thickness))."""
    occ = gmsh.model.geo
    if name == "naca0012":
        far, near = 0.5, 0.02
        box = [occ.addPoint(x, y, 0, far) for x, y in [(-2, -2), (3, -2), (3, 2), (-2, 2)]]
        bl = [occ.addLine(box[i], box[(i + 1) % 4]) for i in range(4)]
        af = [occ.addPoint(x, y, 0, near) for x, y in naca_points()]
        al = [occ.addLine(af[i], af[(i + 1) % len(af)]) for i in range(len(af))]
        outer = occ.addCurveLoop(bl)
        inner = occ.addCurveLoop(al)
        occ.addPlaneSurface([outer, inner], 1)
        occ.synchronize()
        gmsh.model.addPhysicalGroup(1, bl, 1, "Farfield")
        gmsh.model.addPhysicalGroup(1, al, 4, "Airfoil")
        gmsh.model.addPhysicalGroup(2, [1], 10, "Fluid")
        # Trailing edge: the airfoil point at x = 1.
        te = [af[i] for i, (x, y) in enumerate(naca_points()) if abs(x - 1.0) < 1e-9]
        # y+ 1 at Re 5000 over the chord (laminar flat plate): 2.92e-3.
        return ["Airfoil"], al, te, (0.00292, 1.2, 0.05)
    if name == "cylinder":
        h = 0.05
        p = [occ.addPoint(x, y, 0, h) for x, y in [(0, 0), (4, 0), (4, 1), (0, 1)]]
        l = [occ.addLine(p[i], p[(i + 1) % 4]) for i in range(4)]
        c = occ.addPoint(1, 0.5, 0, h)
        q = [occ.addPoint(x, y, 0, 0.02) for x, y in [(0.85, 0.5), (1, 0.35), (1.15, 0.5), (1, 0.65)]]
        arcs = [occ.addCircleArc(q[i], c, q[(i + 1) % 4]) for i in range(4)]
        occ.addPlaneSurface([occ.addCurveLoop(l), occ.addCurveLoop(arcs)], 1)
        occ.synchronize()
        gmsh.model.addPhysicalGroup(1, [l[0], l[2]], 3, "Walls")
        gmsh.model.addPhysicalGroup(1, [l[1]], 2, "Outlet")
        gmsh.model.addPhysicalGroup(1, [l[3]], 1, "Inlet")
        gmsh.model.addPhysicalGroup(1, arcs, 4, "Cylinder")
        gmsh.model.addPhysicalGroup(2, [1], 10, "Fluid")
        return ["Cylinder"], arcs, [], (0.002, 1.2, 0.03)
    if name == "concave-corner":
        h = 0.08
        xy = [(0, 0), (2, 0), (2, 1), (1, 1), (1, 2), (0, 2)]
        p = [occ.addPoint(x, y, 0, h) for x, y in xy]
        l = [occ.addLine(p[i], p[(i + 1) % 6]) for i in range(6)]
        occ.addPlaneSurface([occ.addCurveLoop(l)], 1)
        occ.synchronize()
        gmsh.model.addPhysicalGroup(1, [l[0], l[5]], 1, "Wall")
        gmsh.model.addPhysicalGroup(1, [l[1]], 2, "Outlet")
        gmsh.model.addPhysicalGroup(1, [l[2], l[3]], 3, "Step")
        gmsh.model.addPhysicalGroup(1, [l[4]], 4, "Inlet")
        gmsh.model.addPhysicalGroup(2, [1], 10, "Fluid")
        return ["Wall"], [l[0], l[5]], [], (0.005, 1.2, 0.06)
    if name == "thin-gap":
        h = 0.02
        p = [occ.addPoint(x, y, 0, h) for x, y in [(0, 0), (1, 0), (1, 0.05), (0, 0.05)]]
        l = [occ.addLine(p[i], p[(i + 1) % 4]) for i in range(4)]
        occ.addPlaneSurface([occ.addCurveLoop(l)], 1)
        occ.synchronize()
        gmsh.model.addPhysicalGroup(1, [l[0]], 1, "Lower")
        gmsh.model.addPhysicalGroup(1, [l[2]], 3, "Upper")
        gmsh.model.addPhysicalGroup(1, [l[1]], 2, "Outlet")
        gmsh.model.addPhysicalGroup(1, [l[3]], 4, "Inlet")
        gmsh.model.addPhysicalGroup(2, [1], 10, "Fluid")
        return ["Lower", "Upper"], [l[0], l[2]], [], (0.002, 1.2, 0.06)
    raise ValueError(name)


def gmsh_mesh(name, layer, path):
    gmsh.clear()
    gmsh.model.add(name)
    curves, tags, fans, (h0, r, t) = build(name)
    if layer:
        f = gmsh.model.mesh.field.add("BoundaryLayer")
        gmsh.model.mesh.field.setNumbers(f, "CurvesList", tags)
        gmsh.model.mesh.field.setNumber(f, "Size", h0)
        gmsh.model.mesh.field.setNumber(f, "Ratio", r)
        gmsh.model.mesh.field.setNumber(f, "Thickness", t)
        gmsh.model.mesh.field.setNumber(f, "Quads", 1)
        if fans:
            gmsh.model.mesh.field.setNumbers(f, "FanPointsList", fans)
        gmsh.model.mesh.field.setAsBoundaryLayer(f)
    t0 = time.perf_counter()
    gmsh.model.mesh.generate(2)
    dt = time.perf_counter() - t0
    gmsh.write(path)
    return curves, (h0, r, t), dt


def info(path):
    out = subprocess.run([SM, "info", path, "--json"], capture_output=True, text=True)
    if out.returncode != 0:
        return None
    return json.loads(out.stdout)


def figures(j):
    cells = j["cells"]
    q = j.get("quads")
    if q is None:
        return dict(tri=cells.get("triangle", 0), quads=0, layers=0, msj=float("nan"),
                    skew=float("nan"), ratio="-", valid="-")
    ql = q["quality"]
    ratios = [l["ratio"][1] for l in ql["layers"] if l["ratio"]]
    v = q["validity"]
    valid = "yes" if not (v["inverted"] or v["overlaps"] or v["hanging"] or v["bad_edges"]) else \
        f"no ({len(v['inverted'])} inv, {len(v['overlaps'])} ovl, {len(v['hanging'])} hang)"
    return dict(
        tri=cells.get("triangle", 0), quads=ql["quads"], layers=len(ql["layers"]),
        msj=ql["min_scaled_jacobian"], skew=ql["max_skewness"],
        ratio=(f"{min(ratios):.3f}–{max(ratios):.3f}" if ratios else "-"),
        h0=ql["layers"][0]["height"][1] if ql["layers"] else float("nan"),
        valid=valid)


def main():
    os.makedirs(OUT, exist_ok=True)
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
    rows = []
    for name in ["naca0012", "cylinder", "concave-corner", "thin-gap"]:
        base = os.path.join(OUT, f"{name}-base.msh")
        gm = os.path.join(OUT, f"{name}-gmsh.msh")
        sk = os.path.join(OUT, f"{name}-smartmesh.msh")
        times_g, times_b, times_s = [], [], []
        for _ in range(3):
            try:
                curves, (h0, r, t), dt = gmsh_mesh(name, True, gm)
                times_g.append(dt)
            except Exception as e:  # noqa: BLE001 - a Gmsh failure is a result
                times_g.append(float("nan"))
                print(f"{name}: gmsh with BoundaryLayer failed: {e}", file=sys.stderr)
            curves, (h0, r, t), dt = gmsh_mesh(name, False, base)
            times_b.append(dt)
            t0 = time.perf_counter()
            out = subprocess.run(
                [SM, "-q", "layer", base, "--curves", ",".join(curves), "--first-height", str(h0),
                 "--ratio", str(r), "--thickness", str(t), "-o", sk, "--json"],
                capture_output=True, text=True)
            times_s.append(time.perf_counter() - t0)
            if out.returncode != 0:
                print(f"{name}: smartmesh layer failed: {out.stderr}", file=sys.stderr)
        jg, js = info(gm), info(sk)
        rows.append((name, "Gmsh BoundaryLayer", figures(jg) if jg else None,
                     min(times_g), None))
        rep = json.loads(out.stdout)["report"] if out.returncode == 0 else None
        rows.append((name, "smartmesh layer", figures(js) if js else None,
                     min(times_b) + min(times_s), rep))
    gmsh.finalize()
    print("| geometry | tool | layers | quads | triangles | first height | ratio achieved | "
          "min scaled Jacobian | max skewness | valid | thinned columns | time (s) |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for name, tool, f, secs, rep in rows:
        if f is None:
            print(f"| {name} | {tool} | failed | | | | | | | | | {secs:.3f} |")
            continue
        th = "-" if rep is None else str(len(rep["thinned"]))
        print(f"| {name} | {tool} | {f['layers']} | {f['quads']} | {f['tri']} | "
              f"{f.get('h0', float('nan')):.4g} | {f['ratio']} | {f['msj']:.3f} | {f['skew']:.3f} | "
              f"{f['valid']} | {th} | {secs:.3f} |")


if __name__ == "__main__":
    main()
