#!/usr/bin/env python3
"""nasa/refine's 2D analytic metrics as a benchmark: smartmesh remesh beside mmg2d_O3.

The seven metrics of refine's `ref_metric_twod_analytic_node` (src/ref_metric.c) that its
2D acceptance cases use or vary: linear-0001, linear-01, masabl-1, side, polar-2,
radial-1, circle-1, written here from their formulas (x, y the plane's coordinates;
polar-2 centred at the origin, radial-1 and circle-1 at (-0.5, 0.5)). As refine's
acceptance scripts do, each run starts from refine's start mesh (`ref_acceptance 2`: the
unit square, 4 x 4 vertices) and cycles: the metric evaluated at the current mesh's
vertices, one adaptation to it, again; 4 cycles (3 for masabl-1, 5 for circle-1, as the
scripts). The final mesh is measured against the metric evaluated at its own vertices
by `smartmesh info --metric --measures ugawg` (the UGAWG's edge length by the log-mean of
its ends' lengths and the mean-ratio quality, refine's `ref_histogram` definitions), the
same yardstick for both tools; refine's acceptance limits on the shortest and longest
edge (`check.rb`) are printed beside them.

    smartmesh remesh in.mesh --metric in.sol -o out.mesh
    mmg2d_O3 -in in.mesh -sol in.sol -out out.mesh -hgrad -1 -hausd 10 -v -1

MMG runs without its gradation (`-hgrad -1`, adapting to the metric as given, as
smartmesh does) and without geometric refinement of the (straight) boundary.

    python3 benches/refine_2d.py [--smartmesh target/release/smartmesh] [--json out.json]
"""

import argparse
import json
import math
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent

# name: (cycles, refine's check.rb limits on min and max edge length, or None)
CASES = {
    "linear-0001": (4, (0.40, 1.8)),
    "linear-01": (4, None),
    "masabl-1": (3, (0.40, 1.6)),
    "side": (4, (0.50, 1.6)),
    "polar-2": (4, (0.20, 3.0)),
    "radial-1": (4, (0.25, 1.6)),
    "circle-1": (5, (0.30, 3.5)),
}


def polar(h_r, h_t, t):
    """R diag(1/h_r^2, 1/h_t^2) R^T with R the rotation by t: (m11, m12, m22)."""
    c, s = math.cos(t), math.sin(t)
    a, b = 1.0 / (h_r * h_r), 1.0 / (h_t * h_t)
    return (a * c * c + b * s * s, (a - b) * c * s, a * s * s + b * c * c)


def metric(name, x, y):
    if name == "masabl-1":
        hx = 0.01 + 0.2 * math.cos(math.pi * (x - 0.5))
        hy = 0.001 * math.exp(6.0 * y)
        return (1 / hx**2, 0.0, 1 / hy**2)
    if name == "side":
        hh = 0.01 + (0.1 - 0.01) * y
        return (1 / 0.1**2, 0.0, 1 / hh**2)
    if name in ("linear-0001", "linear-01"):
        h = 0.0001 if name == "linear-0001" else 0.01
        hh = h + (0.1 - h) * abs(y - 0.5) / 0.5
        return (1 / 0.1**2, 0.0, 1 / hh**2)
    if name == "polar-2":
        r = math.hypot(x, y)
        h_r = 0.001 + 2 * (0.1 - 0.001) * abs(r - 0.5)
        d0 = min(10.0 * abs(r - 0.5), 1.0)
        h_t = 0.1 * d0 + 0.025 * (1.0 - d0)
        return polar(h_r, h_t, math.atan2(y, x))
    if name == "radial-1":
        x, y = x + 0.5, y - 0.5
        return polar(0.01, 0.1, math.atan2(y, x))
    if name == "circle-1":
        x, y = x + 0.5, y - 0.5
        r = math.hypot(x, y)
        h_r = 0.0005 + 1.5 * abs(1.0 - r)
        h_t = 0.1 * r + 1.5 * abs(1.0 - r)
        return polar(h_r, h_t, math.atan2(y, x))
    raise ValueError(name)


def start_mesh():
    """refine's twod brick grid of dimension 4: the unit square, 4 x 4 vertices."""
    n = 4
    pts = [(i / (n - 1), j / (n - 1)) for j in range(n) for i in range(n)]
    v = lambda i, j: j * n + i  # noqa: E731
    tris = []
    for j in range(n - 1):
        for i in range(n - 1):
            tris.append((v(i, j), v(i + 1, j), v(i + 1, j + 1)))
            tris.append((v(i, j), v(i + 1, j + 1), v(i, j + 1)))
    edges = []
    for k in range(n - 1):
        edges += [(v(k, 0), v(k + 1, 0), 1), (v(n - 1, k), v(n - 1, k + 1), 2)]
        edges += [(v(k + 1, n - 1), v(k, n - 1), 3), (v(0, k + 1), v(0, k), 4)]
    return pts, tris, edges


def write_mesh(path, mesh):
    pts, tris, edges = mesh
    out = ["MeshVersionFormatted 2", "Dimension 2", "Vertices", str(len(pts))]
    out += ["%r %r 0" % p for p in pts]
    out += ["Triangles", str(len(tris))] + ["%d %d %d 1" % tuple(a + 1 for a in t) for t in tris]
    out += ["Edges", str(len(edges))] + ["%d %d %d" % (a + 1, b + 1, r) for a, b, r in edges]
    Path(path).write_text("\n".join(out + ["End", ""]))


def write_sol(path, name, pts):
    out = ["MeshVersionFormatted 2", "Dimension 2", "SolAtVertices", str(len(pts)), "1 3"]
    out += ["%r %r %r" % metric(name, x, y) for x, y in pts]
    Path(path).write_text("\n".join(out + ["End", ""]))


def read_mesh(path):
    words = Path(path).read_text().split()
    pts, tris, edges = [], [], []
    i = 0
    while i < len(words):
        w = words[i]
        if w == "Vertices":
            n = int(words[i + 1])
            pts = [(float(words[i + 2 + 3 * k]), float(words[i + 3 + 3 * k])) for k in range(n)]
            i += 2 + 3 * n
        elif w == "Triangles":
            n = int(words[i + 1])
            tris = [tuple(int(words[i + 2 + 4 * k + c]) - 1 for c in range(3)) for k in range(n)]
            i += 2 + 4 * n
        elif w == "Edges":
            n = int(words[i + 1])
            edges = [
                (int(words[i + 2 + 3 * k]) - 1, int(words[i + 3 + 3 * k]) - 1, int(words[i + 4 + 3 * k]))
                for k in range(n)
            ]
            i += 2 + 3 * n
        else:
            i += 1
    return pts, tris, edges


def real_mmg():
    import mmgpy

    return str(Path(mmgpy.__file__).parent / "bin" / "mmg2d_O3")


def cpu_children():
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def adapt(tool, sm, mmg, work, name, cycles):
    """The cycles of one tool on one metric: the final mesh's vertex count, its UGAWG
    measures, and the remeshers' wall and CPU seconds summed over the cycles (the
    writing of inputs and the measuring are not counted)."""
    mesh = start_mesh()
    wall = cpu = 0.0
    for c in range(cycles):
        inp, sol, out = work / f"{tool}-{c}.mesh", work / f"{tool}-{c}.sol", work / f"{tool}-{c + 1}.o.mesh"
        write_mesh(inp, mesh)
        write_sol(sol, name, mesh[0])
        if tool == "smartmesh":
            cmd = [sm, "-q", "remesh", str(inp), "--metric", str(sol), "-o", str(out)]
        else:
            cmd = [mmg, "-in", str(inp), "-sol", str(sol), "-out", str(out), "-hgrad", "-1", "-hausd", "10", "-v", "-1"]
        c0, t0 = cpu_children(), time.perf_counter()
        subprocess.run(cmd, check=True, capture_output=True)
        wall += time.perf_counter() - t0
        cpu += cpu_children() - c0
        mesh = read_mesh(out)
    final, sol = work / f"{tool}-final.mesh", work / f"{tool}-final.sol"
    write_mesh(final, mesh)
    write_sol(sol, name, mesh[0])
    info = subprocess.run(
        [sm, "info", "--json", "--no-solution", str(final), "--metric", str(sol), "--measures", "ugawg"],
        check=True,
        capture_output=True,
        text=True,
    )
    return len(mesh[0]), json.loads(info.stdout)["metric"]["ugawg"], wall, cpu


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--smartmesh", default=str(ROOT / "target" / "release" / "smartmesh"))
    ap.add_argument("--json", help="write every figure here")
    ap.add_argument("--cases", default=",".join(CASES), help="comma-separated metric names")
    ap.add_argument("--work", help="keep every cycle's files in this folder (default: a temporary one)")
    a = ap.parse_args()
    mmg = real_mmg()
    rows = []
    print("| metric | tool | vertices | edges in [1/√2, √2] | L min | L max | L mean | quality min | quality mean | refine's limits | CPU s | wall s |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as d:
        if a.work:
            d = a.work
        for name in a.cases.split(","):
            cycles, limits = CASES[name]
            for tool in ("smartmesh", "mmg2d_O3"):
                work = Path(d) / name
                work.mkdir(parents=True, exist_ok=True)
                nv, u, wall, cpu = adapt(tool, a.smartmesh, mmg, work, name, cycles)
                lo, hi = u["edge_length_range"]
                met = "—" if limits is None else (
                    f"[{limits[0]}, {limits[1]}] " + ("met" if lo >= limits[0] and hi <= limits[1] else "NOT met")
                )
                print(
                    f"| {name} | {tool} | {nv} | {100 * u['conforming_share']:.1f}% | {lo:.3f} | {hi:.3f} | "
                    f"{u['mean_edge_length']:.3f} | {u['min_quality']:.3f} | {u['mean_quality']:.3f} | {met} | {cpu:.3f} | {wall:.3f} |",
                    flush=True,
                )
                rows.append(
                    {"metric": name, "tool": tool, "cycles": cycles, "vertices": nv, "ugawg": u, "cpu_s": cpu, "wall_s": wall}
                )
    if a.json:
        Path(a.json).write_text(json.dumps(rows, indent=1) + "\n")


if __name__ == "__main__":
    sys.exit(main())
