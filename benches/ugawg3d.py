#!/usr/bin/env python3
"""The UGAWG 3D benchmark's first cases driven through `smartmesh remesh` (mmg3d_O3).

The Unstructured Grid Adaptation Working Group's benchmark (github.com/UGAWG/adapt-benchmarks)
gives start meshes and analytic metrics; an adaptive code is run for a fixed number of
cycles, each cycle evaluating the analytic metric at the current mesh's vertices and
adapting to it, and the result is measured in the metric (MEASURES.md of that repository):

- edge length, Omega_h's formula: l_a = sqrt(v^T M_a v), l_b = sqrt(v^T M_b v) with the
  metrics of the end points, l = (l_a - l_b) / log(l_a / l_b) when |l_a - l_b| > 1e-3,
  else (l_a + l_b) / 2; the share of edges with l in [1/sqrt2, sqrt2] is reported;
- mean ratio of a tetrahedron: Q = (V_m / V_eq)^(2/3) / l_msq, with M_max the corner
  metric of largest determinant, V_m = V sqrt(det M_max), l_msq the mean of v^T M_max v
  over the six edges, V_eq = sqrt(2)/12 (the volume of the unit regular tetrahedron).

The cases and their metrics (the cube's README and cube-cylinder's README, checked against
nasa/refine's src/ref_metric.c, which the UGAWG acceptance scripts run):

- `linear` on the unit cube: diag(h_x^-2, h_y^-2, h_z^-2), h_x = h_y = 0.1,
  h_z = h0 + 2 (0.1 - h0) |z - 0.5|, h0 = 0.001 (refine's ref_metric_olympic_node);
- `polar-1` on the cube-cylinder (the unit cube less the cylinder r < 0.5 about the z
  axis): R(t) diag(h_r^-2, h_t^-2, h_z^-2) R(t)^T, t = atan2(y, x), h_z = h_t = 0.1,
  h_r = h0 + 2 (0.1 - h0) |r - 0.5|;
- `polar-2`: polar-1 with h_t = 0.1 d + 0.025 (1 - d), d = min(10 |r - 0.5|, 1), as
  refine's ref_metric_ugawg_node writes it (the README's d = (0.6 - r) 10 form is not
  symmetric about the layer; refine's code is what the acceptance runs use).

Start meshes: with --ugawg DIR (a checkout of UGAWG/adapt-benchmarks), its
cube/cube-linear-00.mesh (64 vertices) and cube-cylinder/cube-cylinder.mesh (286
vertices); without it, Gmsh (Python API) makes meshes of the same geometries (the unit
cube at size 1/3; the cube-cylinder at 0.1 on the cylinder, 0.5 elsewhere, as the
repository's .geo asks), each face its own physical surface.

Each cycle: the metric at the vertices goes to a Medit .sol written here (m11 m12 m22 m13
m23 m33), then

    smartmesh remesh cycle-K.mesh --metric cycle-K.sol -o cycle-K+1.mesh --hgrad -1 --json

(`--hgrad -1`: MMG's gradation off, so that it adapts to the metric as given; its
Hausdorff control and smooth surface reconstruction stay at their defaults), and the new
mesh is measured against the analytic metric at its own vertices. The tags of the faces
come back through MMG's references (smartmesh checks that every one is still there).

    python3 benches/ugawg3d.py --ugawg /path/to/adapt-benchmarks --cycles 5
    python3 benches/ugawg3d.py --cases linear --cycles 3      # Gmsh start meshes

Needs numpy, meshio, mmg3d_O3 on PATH (PyPI mmgpy) and, without --ugawg, gmsh.
"""

import argparse
import json
import math
import os
import subprocess
import sys
import time
from pathlib import Path

import meshio
import numpy as np

ROOT = Path(__file__).resolve().parent.parent
H0 = 0.001
V_EQ = math.sqrt(2.0) / 12.0


def metric(case, p):
    """The analytic metric of `case` at the points p (n x 3), as n 3x3 matrices."""
    x, y, z = p[:, 0], p[:, 1], p[:, 2]
    n = len(p)
    if case == "linear":
        hz = H0 + 2.0 * (0.1 - H0) * np.abs(z - 0.5)
        m = np.zeros((n, 3, 3))
        m[:, 0, 0] = 0.1**-2
        m[:, 1, 1] = 0.1**-2
        m[:, 2, 2] = hz**-2
        return m
    r = np.hypot(x, y)
    t = np.arctan2(y, x)
    h_r = H0 + 2.0 * (0.1 - H0) * np.abs(r - 0.5)
    h_t = np.full(n, 0.1)
    if case == "polar-2":
        d = np.minimum(10.0 * np.abs(r - 0.5), 1.0)
        h_t = 0.1 * d + 0.025 * (1.0 - d)
    h_z = np.full(n, 0.1)
    c, s = np.cos(t), np.sin(t)
    # Columns: the radial, tangential and axial directions.
    frame = np.zeros((n, 3, 3))
    frame[:, 0, 0], frame[:, 1, 0] = c, s
    frame[:, 0, 1], frame[:, 1, 1] = -s, c
    frame[:, 2, 2] = 1.0
    eig = np.stack([h_r**-2, h_t**-2, h_z**-2], axis=1)
    return np.einsum("nik,nk,njk->nij", frame, eig, frame)


def write_sol(path, m):
    """A Medit 3D .sol of type 3: m11 m12 m22 m13 m23 m33 per vertex."""
    rows = np.stack(
        [m[:, 0, 0], m[:, 1, 0], m[:, 1, 1], m[:, 2, 0], m[:, 2, 1], m[:, 2, 2]], axis=1
    )
    with open(path, "w") as f:
        f.write(f"MeshVersionFormatted 2\nDimension 3\nSolAtVertices\n{len(m)}\n1 3\n")
        np.savetxt(f, rows, fmt="%.17e")
        f.write("End\n")


def tetrahedra(mesh):
    return np.concatenate([c.data for c in mesh.cells if c.type == "tetra"])


def measure(case, mesh):
    """UGAWG's figures of `mesh` against the analytic metric at its vertices."""
    p = mesh.points[:, :3].astype(float)
    tets = tetrahedra(mesh)
    m = metric(case, p)
    pairs = [(0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)]
    e = np.concatenate([tets[:, list(ij)] for ij in pairs])
    e = np.unique(np.sort(e, axis=1), axis=0)
    v = p[e[:, 1]] - p[e[:, 0]]
    la = np.sqrt(np.einsum("ni,nij,nj->n", v, m[e[:, 0]], v))
    lb = np.sqrt(np.einsum("ni,nij,nj->n", v, m[e[:, 1]], v))
    close = np.abs(la - lb) <= 1e-3
    with np.errstate(divide="ignore", invalid="ignore"):
        log_mean = (la - lb) / np.log(la / lb)
    length = np.where(close, 0.5 * (la + lb), log_mean)
    inside = (length >= 1.0 / math.sqrt(2.0)) & (length <= math.sqrt(2.0))
    # Mean ratio, with the corner metric of largest determinant.
    corners = m[tets]  # (k, 4, 3, 3)
    det = np.linalg.det(corners)
    mmax = corners[np.arange(len(tets)), np.argmax(det, axis=1)]
    q = p[tets]
    a, b, c = q[:, 1] - q[:, 0], q[:, 2] - q[:, 0], q[:, 3] - q[:, 0]
    vol = np.einsum("ni,ni->n", a, np.cross(b, c)) / 6.0
    vm = vol * np.sqrt(np.linalg.det(mmax))
    lsq = sum(
        np.einsum("ni,nij,nj->n", q[:, j] - q[:, i], mmax, q[:, j] - q[:, i]) for i, j in pairs
    ) / 6.0
    ratio = np.cbrt(vm / V_EQ) ** 2 / lsq
    return {
        "vertices": int(len(np.unique(tets))),
        "tetrahedra": int(len(tets)),
        "edges": int(len(e)),
        "conforming_share": float(inside.mean()),
        "length_min": float(length.min()),
        "length_max": float(length.max()),
        "length_mean": float(length.mean()),
        "mean_ratio_min": float(ratio.min()),
        "mean_ratio_mean": float(ratio.mean()),
        "negative_volumes": int((vol <= 0).sum()),
    }


GMSH_CUBE = """
import sys, gmsh
gmsh.initialize(); gmsh.option.setNumber("General.Terminal", 0)
gmsh.model.occ.addBox(0, 0, 0, 1, 1, 1)
gmsh.model.occ.synchronize()
for d, t in gmsh.model.getEntities(2):
    gmsh.model.addPhysicalGroup(2, [t], t)
gmsh.model.addPhysicalGroup(3, [1], 100)
gmsh.option.setNumber("Mesh.MeshSizeMax", 1 / 3)
gmsh.model.mesh.generate(3)
gmsh.write(sys.argv[1])
"""

GMSH_CUBE_CYLINDER = """
import sys, gmsh
gmsh.initialize(); gmsh.option.setNumber("General.Terminal", 0)
box = gmsh.model.occ.addBox(0, 0, 0, 1, 1, 1)
cyl = gmsh.model.occ.addCylinder(0, 0, 0, 0, 0, 1, 0.5)
gmsh.model.occ.cut([(3, box)], [(3, cyl)])
gmsh.model.occ.synchronize()
for d, t in gmsh.model.getEntities(2):
    gmsh.model.addPhysicalGroup(2, [t], t)
gmsh.model.addPhysicalGroup(3, [t for _, t in gmsh.model.getEntities(3)], 100)
for d, t in gmsh.model.getEntities(0):
    x, y, z = gmsh.model.getValue(0, t, [])
    gmsh.model.mesh.setSize([(0, t)], 0.1 if math.hypot(x, y) < 0.51 else 0.5)
gmsh.model.mesh.generate(3)
gmsh.write(sys.argv[1])
"""


def start_mesh(case, args, work):
    """The start mesh of `case` as a .mesh file in `work`."""
    name = "cube" if case == "linear" else "cube-cylinder"
    out = work / f"{case}-00.mesh"
    if args.ugawg:
        rel = "cube/cube-linear-00.mesh" if name == "cube" else "cube-cylinder/cube-cylinder.mesh"
        src = Path(args.ugawg) / rel
        out.write_bytes(src.read_bytes())
        return out, f"UGAWG {rel}"
    script = GMSH_CUBE if name == "cube" else "import math\n" + GMSH_CUBE_CYLINDER
    msh = work / f"{case}-gmsh.msh"
    subprocess.run([sys.executable, "-c", script, str(msh)], check=True)
    subprocess.run([args.smartmesh, "convert", str(msh), str(out), "-q"], check=True)
    return out, "Gmsh"


def run_case(case, args, work):
    mesh_path, origin = start_mesh(case, args, work)
    mesh = meshio.read(mesh_path)
    rows = [{"cycle": 0, **measure(case, mesh), "seconds": 0.0}]
    print(f"{case} start ({origin}): {rows[0]}", flush=True)
    for k in range(1, args.cycles + 1):
        sol = work / f"{case}-{k - 1:02d}.sol"
        write_sol(sol, metric(case, mesh.points[:, :3].astype(float)))
        nxt = work / f"{case}-{k:02d}.mesh"
        cmd = [args.smartmesh, "remesh", str(mesh_path), "--metric", str(sol), "-o", str(nxt)]
        cmd += ["--adapter", "mmg3d", "--hgrad", "-1", "--json", "-q"]
        t0 = time.perf_counter()
        done = subprocess.run(cmd, capture_output=True, text=True)
        seconds = time.perf_counter() - t0
        if done.returncode != 0:
            sys.exit(f"{' '.join(cmd)} failed:\n{done.stderr}")
        mesh_path, mesh = nxt, meshio.read(nxt)
        rows.append({"cycle": k, **measure(case, mesh), "seconds": seconds})
        print(f"{case} cycle {k}: {rows[-1]}", flush=True)
    return {"case": case, "start": origin, "cycles": rows}


def table(results):
    lines = [
        "| case | cycle | vertices | tetrahedra | edges in [1/√2, √2] | length min | length max | mean ratio min | mean ratio mean | seconds |",
        "|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in results:
        for c in r["cycles"]:
            lines.append(
                f"| {r['case']} | {c['cycle']} | {c['vertices']} | {c['tetrahedra']} | "
                f"{100 * c['conforming_share']:.1f} % | {c['length_min']:.3f} | {c['length_max']:.2f} | "
                f"{c['mean_ratio_min']:.3f} | {c['mean_ratio_mean']:.3f} | {c['seconds']:.1f} |"
            )
    return "\n".join(lines)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--cases", default="linear,polar-1,polar-2")
    ap.add_argument("--cycles", type=int, default=4)
    ap.add_argument("--ugawg", help="a checkout of UGAWG/adapt-benchmarks (start meshes)")
    ap.add_argument("--smartmesh", default=None, help="the binary (default: target/release, else target/debug)")
    ap.add_argument("--work", default=None, help="where the meshes go (default: a temporary folder)")
    ap.add_argument("--json", help="write the figures as JSON here")
    args = ap.parse_args()
    if args.smartmesh is None:
        for b in ["release", "debug"]:
            if (ROOT / "target" / b / "smartmesh").exists():
                args.smartmesh = str(ROOT / "target" / b / "smartmesh")
                break
        else:
            sys.exit("no smartmesh binary: cargo build --release")
    import tempfile

    tmp = None
    if args.work:
        work = Path(args.work)
        work.mkdir(parents=True, exist_ok=True)
    else:
        tmp = tempfile.TemporaryDirectory(prefix="ugawg3d-")
        work = Path(tmp.name)
    results = [run_case(c, args, work) for c in args.cases.split(",")]
    print(table(results))
    if args.json:
        Path(args.json).write_text(json.dumps(results, indent=1) + "\n")


if __name__ == "__main__":
    main()
