"""Side by side: `smartmesh layer` against Gmsh's BoundaryLayer field (gmsh from PyPI,
its Python API, quads on) on the same geometries and the same heights.

Each geometry is built once in Gmsh (lines and circle arcs with physical groups) and
meshed twice with the same sizes: without a boundary layer (the input `smartmesh layer`
then skins) and with the BoundaryLayer field on the wall curves (Size = first height,
Ratio, Thickness; fans at the sharp points). Both results are measured by
`smartmesh info --json`: layers found from the cells, per-layer height and ratio, min
scaled Jacobian, max skewness, cell counts, validity (positive corners, no overlap, no
hanging node). Times: Gmsh's meshing with the field against Gmsh's meshing without it
plus `smartmesh layer` (release build, best of three), wall and CPU (Gmsh's process CPU
around its meshing; the `smartmesh` child's user + system time).

`--sweep` times the NACA 0012 case alone at 10 to 320 layers (ratio 1.02, the first
height solved for the same 0.05 thickness), Gmsh's field against `smartmesh layer`.

    cargo build --release
    python3 benches/compare_gmsh_layer.py            # table on stdout, files in target/compare-layer/
    python3 benches/compare_gmsh_layer.py --sweep    # time against the number of layers
"""
import json
import math
import os
import resource
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
    t0, c0 = time.perf_counter(), time.process_time()
    gmsh.model.mesh.generate(2)
    dt, dc = time.perf_counter() - t0, time.process_time() - c0
    gmsh.write(path)
    CPU.append(dc)
    return curves, (h0, r, t), dt


# The CPU time of each `gmsh_mesh` call, in order.
CPU = []


def child_cpu():
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def run_layer(args):
    """Runs `smartmesh -q layer ARGS`; returns (completed process, wall s, CPU s)."""
    t0, c0 = time.perf_counter(), child_cpu()
    out = subprocess.run([SM, "-q", "layer"] + args, capture_output=True, text=True)
    return out, time.perf_counter() - t0, child_cpu() - c0


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
        cpu_g, cpu_b, cpu_s = [], [], []
        for _ in range(3):
            try:
                curves, (h0, r, t), dt = gmsh_mesh(name, True, gm)
                times_g.append(dt)
                cpu_g.append(CPU[-1])
            except Exception as e:  # noqa: BLE001 - a Gmsh failure is a result
                times_g.append(float("nan"))
                cpu_g.append(float("nan"))
                print(f"{name}: gmsh with BoundaryLayer failed: {e}", file=sys.stderr)
            curves, (h0, r, t), dt = gmsh_mesh(name, False, base)
            times_b.append(dt)
            cpu_b.append(CPU[-1])
            out, dt, dc = run_layer(
                [base, "--curves", ",".join(curves), "--first-height", str(h0),
                 "--ratio", str(r), "--thickness", str(t), "-o", sk, "--json"])
            times_s.append(dt)
            cpu_s.append(dc)
            if out.returncode != 0:
                print(f"{name}: smartmesh layer failed: {out.stderr}", file=sys.stderr)
        jg, js = info(gm), info(sk)
        rows.append((name, "Gmsh BoundaryLayer", figures(jg) if jg else None,
                     (min(times_g), min(cpu_g)), None))
        rep = json.loads(out.stdout)["report"] if out.returncode == 0 else None
        rows.append((name, "smartmesh layer", figures(js) if js else None,
                     (min(times_b) + min(times_s), min(cpu_b) + min(cpu_s)), rep))
    gmsh.finalize()
    print("| geometry | tool | layers | quads | triangles | first height | ratio achieved | "
          "min scaled Jacobian | max skewness | valid | thinned columns | time (s) | CPU (s) |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for name, tool, f, (secs, cpu), rep in rows:
        if f is None:
            print(f"| {name} | {tool} | failed | | | | | | | | | {secs:.3f} | {cpu:.3f} |")
            continue
        th = "-" if rep is None else str(len(rep["thinned"]))
        print(f"| {name} | {tool} | {f['layers']} | {f['quads']} | {f['tri']} | "
              f"{f.get('h0', float('nan')):.4g} | {f['ratio']} | {f['msj']:.3f} | {f['skew']:.3f} | "
              f"{f['valid']} | {th} | {secs:.3f} | {cpu:.3f} |")


def sweep():
    """NACA 0012 at 10 to 320 layers: Gmsh's meshing with the field against its meshing
    without it plus `smartmesh layer` (best of three, wall and CPU)."""
    os.makedirs(OUT, exist_ok=True)
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
    base = os.path.join(OUT, "naca0012-base.msh")
    gm = os.path.join(OUT, "naca0012-sweep-gmsh.msh")
    sk = os.path.join(OUT, "naca0012-sweep-smartmesh.msh")
    print("| layers | Gmsh quads | Gmsh BoundaryLayer wall / CPU (s) | Gmsh without wall / CPU (s) | "
          "smartmesh layer wall / CPU (s) | smartmesh quads | valid (Gmsh / smartmesh) |")
    print("|---|---|---|---|---|---|---|")
    t, r = 0.05, 1.02
    global build
    plain = build
    for n in [10, 20, 40, 80, 160, 320]:
        h0 = t * (r - 1) / (r ** n - 1)

        def with_heights(name, h0=h0):
            curves, tags, fans, _ = plain(name)
            return curves, tags, fans, (h0, r, t)

        build = with_heights
        g, b, s, ok = [], [], [], True
        for _ in range(3):
            g.append((gmsh_mesh("naca0012", True, gm)[2], CPU[-1]))
            b.append((gmsh_mesh("naca0012", False, base)[2], CPU[-1]))
            out, dt, dc = run_layer([base, "--curves", "Airfoil", "--first-height", str(h0),
                                     "--ratio", str(r), "--layers", str(n), "-o", sk])
            s.append((dt, dc))
            if out.returncode != 0:
                ok = False
                print(f"{n} layers: smartmesh layer failed: {out.stderr}", file=sys.stderr)
        build = plain
        if not ok:
            print(f"| {n} | | | | failed | | |")
            continue
        jg, js = info(gm), info(sk)
        fg, fs = figures(jg), figures(js)
        print(f"| {n} | {fg['quads']} | {min(w for w, _ in g):.3f} / {min(c for _, c in g):.3f} | "
              f"{min(w for w, _ in b):.3f} / {min(c for _, c in b):.3f} | "
              f"{min(w for w, _ in s):.3f} / {min(c for _, c in s):.3f} | {fs['quads']} | "
              f"{fg['valid']} / {fs['valid']} |")
    gmsh.finalize()


if __name__ == "__main__":
    sweep() if "--sweep" in sys.argv[1:] else main()
