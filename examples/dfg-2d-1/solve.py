"""The solver of the DFG 2D-1 example for `smartmesh adapt --solver`: steady laminar flow
around a cylinder in a channel (Schäfer & Turek 1996, benchmark 2D-1: rho = 1,
nu = 0.001, parabolic inflow of maximum 0.3 and mean 0.2, D = 0.1, Re = 20), solved by
Debian's OpenFOAM `simpleFoam` (SIMPLEC, laminar) to steady state:

    python3 solve.py MESH SOLUTION [SMARTMESH]

MESH is a mesh with the named curves Inlet, Outlet, Walls and Cylinder (the `.vtu`
`adapt` writes for its solver keeps the names, and its point order is meshio's). It is written as an OpenFOAM case beside
SOLUTION by `SMARTMESH convert MESH CASE.foam --extrude 0.01` (SMARTMESH: the third
argument, else $SMARTMESH, else `smartmesh` on PATH); the parabolic inlet profile is
set face by face from the case's own polyMesh. After the solve, OpenFOAM's `forceCoeffs`
function object gives the drag and lift coefficients of the cylinder
(c = 2 F / (rho U_mean^2 D dz)) and `probes` the pressure difference between the
cylinder's front and back points, (0.15, 0.2) and (0.25, 0.2).

SOLUTION gets the velocity magnitude `umag` at MESH's vertices (the area-weighted mean
of the cells around each vertex, 0 on the walls and the exact profile on the inlet) and
the vorticity `vort` (its z component, OpenFOAM's `vorticity`, the same mean), for the
Hessian (`adapt --field umag` or `--field vort`); one JSON line per run is appended to
`dfg.jsonl` beside SOLUTION (vertices, cells, cd, cl, dp, SIMPLE iterations, seconds).
"""

import json
import os
import re
import shutil
import subprocess
import sys
import time
from pathlib import Path

import meshio
import numpy as np
from scipy.spatial import cKDTree

H, UMAX, NU, D, DZ = 0.41, 0.3, 1e-3, 0.1, 0.01
UMEAN = 2.0 * UMAX / 3.0
HEADER = "FoamFile {{ version 2.0; format ascii; class {cls}; object {obj}; }}\n"


def foam_env():
    env = dict(os.environ)
    env.setdefault("WM_PROJECT_DIR", "/usr/share/openfoam")
    return env


def write(path, cls, obj, body):
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(HEADER.format(cls=cls, obj=obj) + body)


def numbers(text):
    return [float(x) for x in re.findall(r"[-+]?\d*\.?\d+(?:[eE][-+]?\d+)?", text)]


def foam_list(text):
    """The entries of the first `N ( ... )` list of an OpenFOAM ASCII file, as text."""
    m = re.search(r"\n(\d+)\s*\n\(\n", text)
    n = int(m.group(1))
    body = text[m.end():]
    return body.split("\n")[:n]


def inlet_centres(case):
    """The centres of the Inlet patch's faces, from the case's polyMesh."""
    mesh = case / "constant" / "polyMesh"
    points = np.array([numbers(l) for l in foam_list((mesh / "points").read_text())])
    faces = [[int(v) for v in l[l.index("(") + 1:l.index(")")].split()]
             for l in foam_list((mesh / "faces").read_text())]
    boundary = (mesh / "boundary").read_text()
    m = re.search(r"Inlet\s*\{[^}]*nFaces\s+(\d+);\s*startFace\s+(\d+);", boundary)
    n, start = int(m.group(1)), int(m.group(2))
    return np.array([points[f].mean(axis=0) for f in faces[start:start + n]])


def profile(y):
    return 4.0 * UMAX * y * (H - y) / (H * H)


def setup(case):
    ys = inlet_centres(case)[:, 1]
    inlet = "\n".join(f"({profile(y):.12g} 0 0)" for y in ys)
    empty = "    front { type empty; }\n    back { type empty; }\n"
    write(case / "0" / "U", "volVectorField", "U", f"""dimensions [0 1 -1 0 0 0 0];
internalField uniform (0 0 0);
boundaryField
{{
    Inlet {{ type fixedValue; value nonuniform List<vector> {len(ys)}
(
{inlet}
); }}
    Outlet {{ type zeroGradient; }}
    Walls {{ type noSlip; }}
    Cylinder {{ type noSlip; }}
{empty}}}
""")
    write(case / "0" / "p", "volScalarField", "p", f"""dimensions [0 2 -2 0 0 0 0];
internalField uniform 0;
boundaryField
{{
    Inlet {{ type zeroGradient; }}
    Outlet {{ type fixedValue; value uniform 0; }}
    Walls {{ type zeroGradient; }}
    Cylinder {{ type zeroGradient; }}
{empty}}}
""")
    write(case / "constant" / "transportProperties", "dictionary", "transportProperties",
          f"transportModel Newtonian;\nnu [0 2 -1 0 0 0 0] {NU};\n")
    write(case / "constant" / "turbulenceProperties", "dictionary", "turbulenceProperties",
          "simulationType laminar;\n")
    write(case / "system" / "controlDict", "dictionary", "controlDict", f"""application simpleFoam;
startFrom startTime; startTime 0; stopAt endTime; endTime 4000; deltaT 1;
writeControl timeStep; writeInterval 4000; purgeWrite 0; writeFormat ascii;
writePrecision 12; writeCompression off; timeFormat general; timePrecision 6;
runTimeModifiable false;
functions
{{
    forceCoeffs
    {{
        type forceCoeffs; libs ("libforces.so"); writeControl timeStep; writeInterval 1;
        patches (Cylinder); rho rhoInf; rhoInf 1; CofR (0.2 0.2 0);
        liftDir (0 1 0); dragDir (1 0 0); pitchAxis (0 0 1);
        magUInf {UMEAN}; lRef {D}; Aref {D * DZ};
    }}
    probes
    {{
        type probes; libs ("libsampling.so"); writeControl timeStep; writeInterval 1;
        fields (p); probeLocations ((0.15 0.2 {DZ / 2}) (0.25 0.2 {DZ / 2}));
    }}
}}
""")
    write(case / "system" / "fvSchemes", "dictionary", "fvSchemes", """ddtSchemes { default steadyState; }
gradSchemes { default Gauss linear; }
divSchemes
{
    default none;
    div(phi,U) bounded Gauss linearUpwind grad(U);
    div((nuEff*dev2(T(grad(U))))) Gauss linear;
}
laplacianSchemes { default Gauss linear corrected; }
interpolationSchemes { default linear; }
snGradSchemes { default corrected; }
""")
    write(case / "system" / "fvSolution", "dictionary", "fvSolution", """solvers
{
    p { solver GAMG; smoother GaussSeidel; tolerance 1e-10; relTol 0.05; }
    U { solver smoothSolver; smoother symGaussSeidel; tolerance 1e-12; relTol 0.1; }
}
SIMPLE
{
    consistent yes;
    nNonOrthogonalCorrectors 0;
    residualControl { p 1e-7; U 1e-8; }
}
relaxationFactors { equations { U 0.9; } fields { p 1; } }
""")


def last_row(path):
    rows = [l for l in path.read_text().splitlines() if l.strip() and not l.startswith("#")]
    head = [l for l in path.read_text().splitlines() if l.startswith("#")][-1]
    return head.lstrip("#").split(), rows[-1].split()


def results(case):
    post = case / "postProcessing"
    coeffs = next(p for p in sorted((post / "forceCoeffs").rglob("*.dat")))
    names, row = last_row(coeffs)
    cd, cl = float(row[names.index("Cd")]), float(row[names.index("Cl")])
    _, prow = last_row(next(iter(sorted((post / "probes").rglob("p")))))
    dp = float(prow[1]) - float(prow[2])
    return cd, cl, dp, int(float(row[0]))


def vertex_fields(mesh, case, time_dir):
    """|U| and the vorticity at the mesh's vertices: the area-weighted mean of the cells
    around each."""
    tri = np.vstack([c.data for c in mesh.cells if c.type == "triangle"])
    pts = mesh.points[:, :2]
    for func in ("writeCellCentres", "vorticity"):
        subprocess.run(["postProcess", "-case", str(case), "-func", func, "-time", time_dir],
                       check=True, env=foam_env(), capture_output=True)
    field = lambda name: np.array([numbers(l) for l in  # noqa: E731
                                   foam_list((case / time_dir / name).read_text())])
    centres, u, w = field("C"), field("U"), field("vorticity")
    centroid = pts[tri].mean(axis=1)
    dist, cell = cKDTree(centres[:, :2]).query(centroid)
    assert dist.max() < 1e-9, f"a triangle matches no cell ({dist.max()})"
    a, b, c = pts[tri[:, 0]], pts[tri[:, 1]], pts[tri[:, 2]]
    area = 0.5 * np.abs((b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1])
                        - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0]))

    def at_vertices(values):
        num, den = np.zeros(len(pts)), np.zeros(len(pts))
        for k in range(3):
            np.add.at(num, tri[:, k], area * values)
            np.add.at(den, tri[:, k], area)
        return num / np.where(den > 0, den, 1.0)

    umag = at_vertices(np.linalg.norm(u[cell, :2], axis=1))
    vort = at_vertices(w[cell, 2])
    # The boundary conditions, exactly: no slip on the walls, the profile at the inlet.
    names = {v[0]: k for k, v in mesh.field_data.items()}
    for block, tags in zip(mesh.cells, mesh.cell_data["gmsh:physical"]):
        if block.type != "line":
            continue
        for edge, tag in zip(block.data, tags):
            name = names.get(tag)
            if name in ("Walls", "Cylinder"):
                umag[edge] = 0.0
            elif name == "Inlet":
                umag[edge] = profile(pts[edge, 1])
    return umag, vort, len(tri)


def main(argv):
    mesh_path, out_path = Path(argv[1]), Path(argv[2])
    smartmesh = argv[3] if len(argv) > 3 else os.environ.get("SMARTMESH", "smartmesh")
    t0 = time.time()
    case = out_path.with_name(out_path.stem + ".foam")
    shutil.rmtree(case, ignore_errors=True)
    subprocess.run([smartmesh, "-q", "convert", str(mesh_path), str(case), "--extrude", str(DZ)],
                   check=True)
    setup(case)
    log = subprocess.run(["simpleFoam", "-case", str(case)], env=foam_env(),
                         capture_output=True, text=True)
    if log.returncode != 0:
        sys.stderr.write(log.stdout[-3000:] + log.stderr[-3000:])
        return 1
    times = [p.name for p in case.iterdir() if re.fullmatch(r"\d+", p.name) and p.name != "0"]
    time_dir = max(times, key=int)
    cd, cl, dp, iterations = results(case)
    mesh = meshio.read(mesh_path)
    umag, vort, cells = vertex_fields(mesh, case, time_dir)
    tri = np.vstack([c.data for c in mesh.cells if c.type == "triangle"])
    meshio.write(out_path, meshio.Mesh(mesh.points, [("triangle", tri)],
                                       point_data={"umag": umag, "vort": vort}))
    row = {"vertices": len(mesh.points), "cells": cells, "cd": cd, "cl": cl, "dp": dp,
           "iterations": iterations, "seconds": round(time.time() - t0, 2)}
    with open(out_path.parent / "dfg.jsonl", "a") as f:
        f.write(json.dumps(row) + "\n")
    print(json.dumps(row))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
