"""P1 interpolation error at (nearly) equal vertex count on problems with exact solutions:

  (a) a uniform Delaunay mesh (PyPI `triangle`, quality 30 deg, area bound set to the count),
  (b) the geometric recipe alone (`smartmesh adapt --recipe`), whose vertex count sets N,
  (c) the solution loop with recovered Hessians (`smartmesh adapt --solver`, no recipe,
      vertex count N asked; the "solver" interpolates the exact solution),
  (d) mmg2d_O3 fed the Lp-optimal metric of the exact Hessian, normalised to N,
      remeshed 5 times from (a) (the ideal: no recovery error),
  (e) the solution loop with the geometric recipe intersected (`adapt --recipe R
      --solver ... --complexity N`): the recipe's field takes at most --recipe-share of
      the budget N (smartmesh's default unless given here), the solution's metric is
      scaled to the rest.
(c), (d) and (e) run for each norm exponent of --p (default 2 and inf): p = 2 minimises the L2
norm of the interpolation error; p = inf gives the density |H| (det|H|^(1/2)) that the
H1 seminorm asks for, since the gradient error of P1 interpolation is about h |H| (for
an isotropic cell of size h, |grad e|^2 h^2 ~ h^4 |H|^2 summed over N ~ 1/h^2 cells is
smallest at fixed N when h^2 |H| is constant). (c) and (d) share the bounds: h_max 0.1,
h_min 1e-6 sqrt(2), aspect ratio at most 1e4.

Problems on the unit square: a boundary layer exp(-x/0.01), Mitchell's wave front
atan(100 (r - 0.7)) about (-0.05, -0.05), and the corner singularity r^(2/3) sin(2 theta / 3)
at the origin. Errors: L2 and H1 seminorm of u - I_h u by a 7-point degree-5 rule per
triangle. Everything goes to a temporary directory.

    python3 benches/solution_error.py [--smartmesh target/release/smartmesh] [--problems layer,front,corner] [--p 2,inf] [--recipe-share F]

The table of BENCHMARKS.md ("Solution-driven adaptation") comes from this script.
"""

import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile

import meshio
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)

# ---------------------------------------------------------------- the problems


def layer(x, y):
    eps = 0.01
    u = np.exp(-x / eps)
    z = np.zeros_like(x)
    return u, (-u / eps, z), (u / eps**2, z, z)


def front(x, y):
    alpha, r0, xc, yc = 100.0, 0.7, -0.05, -0.05
    dx, dy = x - xc, y - yc
    r = np.hypot(dx, dy)
    s = alpha * (r - r0)
    u = np.arctan(s)
    ur = alpha / (1 + s * s)
    urr = -2 * alpha * alpha * s / (1 + s * s) ** 2
    nx, ny = dx / r, dy / r
    hxx = urr * nx * nx + ur / r * (1 - nx * nx)
    hxy = urr * nx * ny - ur / r * nx * ny
    hyy = urr * ny * ny + ur / r * (1 - ny * ny)
    return u, (ur * nx, ur * ny), (hxx, hxy, hyy)


def corner(x, y):
    # u = Im z^(2/3): harmonic, gradient ~ r^(-1/3) at the origin.
    z = (x + 1j * y).astype(complex)
    z = np.where(z == 0, 1e-300, z)
    u = np.imag(z ** (2 / 3))
    d1 = (2 / 3) * z ** (-1 / 3)
    d2 = -(2 / 9) * z ** (-4 / 3)
    return u, (np.imag(d1), np.real(d1)), (np.imag(d2), np.real(d2), -np.imag(d2))


PROBLEMS = {"layer": layer, "front": front, "corner": corner}

# The largest size of (c) and (d), as --hmax: without it the Lp metric of a layer asks for
# elements the size of the domain away from it, which no remesher makes in a unit square.
HMAX = 0.1

# The geometric recipes: what an engineer knows before solving. Tags of the square:
# points 1-4 (corner 1 at the origin), curves 11 Bottom, 12 Right, 13 Top, 14 Left, face 100.
RECIPES = {
    "layer": """
[global]
hmax = 0.05
[regions]
Left = [14]
Domain = [100]
[functions.Across]
kind = "distance"
size_at_source = 0.003
size_at_max_distance = 0.05
max_distance = 0.15
exponent = 1.0
[functions.Along]
kind = "distance"
size_at_source = 0.05
size_at_max_distance = 0.05
max_distance = 0.15
exponent = 1.0
[[algorithms]]
type = "uniform"
size = 0.05
regions = ["Domain"]
[[algorithms]]
type = "distance_to_border"
perpendicular = "Across"
parallel = "Along"
regions = ["Left"]
""",
    # The front is where no recipe knows: the recipe can only be uniform.
    "front": """
[global]
hmax = 0.03
[regions]
Domain = [100]
[[algorithms]]
type = "uniform"
size = 0.03
regions = ["Domain"]
""",
    "corner": """
[global]
hmax = 0.05
[regions]
Origin = [1]
Domain = [100]
[functions.Grow]
kind = "distance"
size_at_source = 0.002
size_at_max_distance = 0.05
max_distance = 0.4
exponent = 1.0
[[algorithms]]
type = "uniform"
size = 0.05
regions = ["Domain"]
[[algorithms]]
type = "distance_to_point"
function = "Grow"
regions = ["Origin"]
""",
}

SQUARE_POLY = """4 2 0 1
1 0 0 1
2 1 0 2
3 1 1 3
4 0 1 4
4 1
1 1 2 11
2 2 3 12
3 3 4 13
4 4 1 14
0
1
1 0.5 0.5 100 0
"""

# ---------------------------------------------------------------- errors

# Dunavant's 7-point rule, degree 5 (barycentric coordinates, weights summing to 1).
_A, _B = 0.059715871789770, 0.470142064105115
_C, _D = 0.797426985353087, 0.101286507323456
BARY = np.array(
    [[1 / 3, 1 / 3, 1 / 3], [_A, _B, _B], [_B, _A, _B], [_B, _B, _A], [_C, _D, _D], [_D, _C, _D], [_D, _D, _C]]
)
WEIGHTS = np.array([0.225] + [0.132394152788506] * 3 + [0.125939180544827] * 3)


def interpolation_error(points, tris, problem):
    """L2 and H1-seminorm norms of u - I_h u."""
    f = PROBLEMS[problem]
    p = points[:, :2]
    uv = f(p[:, 0], p[:, 1])[0]
    a, b, c = p[tris[:, 0]], p[tris[:, 1]], p[tris[:, 2]]
    e1, e2 = b - a, c - a
    det = e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]
    area = 0.5 * np.abs(det)
    d1, d2 = uv[tris[:, 1]] - uv[tris[:, 0]], uv[tris[:, 2]] - uv[tris[:, 0]]
    gx = (d1 * e2[:, 1] - d2 * e1[:, 1]) / det
    gy = (d2 * e1[:, 0] - d1 * e2[:, 0]) / det
    l2 = h1 = 0.0
    for w, (l0, l1, l2b) in zip(WEIGHTS, BARY):
        q = l0 * a + l1 * b + l2b * c
        u, (ux, uy), _ = f(q[:, 0], q[:, 1])
        uh = l0 * uv[tris[:, 0]] + l1 * uv[tris[:, 1]] + l2b * uv[tris[:, 2]]
        l2 += np.sum(w * area * (u - uh) ** 2)
        h1 += np.sum(w * area * ((ux - gx) ** 2 + (uy - gy) ** 2))
    return float(np.sqrt(l2)), float(np.sqrt(h1))


def read_triangles(path):
    m = meshio.read(path)
    tris = np.vstack([c.data for c in m.cells if c.type == "triangle"])
    return m.points, tris


# ---------------------------------------------------------------- (a) uniform


def uniform(n, out):
    import triangle

    square = {
        "vertices": np.array([[0, 0], [1, 0], [1, 1], [0, 1]], float),
        "segments": np.array([[0, 1], [1, 2], [2, 3], [3, 0]]),
    }
    area = 1.0 / (1.9 * n)
    for _ in range(6):
        t = triangle.triangulate(square, f"pq30a{area:.10f}")
        got = len(t["vertices"])
        if abs(got / n - 1) < 0.02:
            break
        area *= got / n
    pts = np.column_stack([t["vertices"], np.zeros(len(t["vertices"]))])
    meshio.write(out, meshio.Mesh(pts, [("triangle", t["triangles"])]))
    return out


# ---------------------------------------------------------------- (d) exact metric + MMG


def lp_metric(points, tris, problem, n, p=2.0, aspect=1e4):
    """The Lp-optimal metric of the exact Hessian at the vertices, normalised to n vertices."""
    x, y = points[:, 0], points[:, 1]
    _, _, (hxx, hxy, hyy) = PROBLEMS[problem](x, y)
    hs = np.stack([np.stack([hxx, hxy], -1), np.stack([hxy, hyy], -1)], -2)
    hs = np.nan_to_num(hs, nan=0.0, posinf=1e30, neginf=-1e30)
    lam, vec = np.linalg.eigh(hs)
    lam = np.abs(lam)
    big = lam.max(axis=1)
    floor = np.maximum(1e-12 * big.max(), big / aspect**2)
    lam = np.maximum(lam, floor[:, None])
    g = np.prod(lam, axis=1) ** (-1.0 / (2 * p + 2))
    hmin, hmax = 1e-6 * np.sqrt(2.0), HMAX
    a, b, c = points[tris[:, 0], :2], points[tris[:, 1], :2], points[tris[:, 2], :2]
    area = 0.5 * np.abs((b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0]))

    def sizes(log_d):
        h = 1.0 / np.sqrt(np.exp(log_d) * g[:, None] * lam)
        h = np.clip(h, hmin, hmax)
        h = np.minimum(h, h.min(axis=1, keepdims=True) * aspect)
        return h

    def count(log_d):
        h = sizes(log_d)
        # The Log-Euclidean mean at the centroid (as smartmesh's exact complexity
        # integrates it): a singular vertex does not swamp its triangles.
        log_sq = -np.log(h[:, 0] * h[:, 1])
        c_ = np.sum(area * np.exp(log_sq[tris].mean(axis=1)))
        return 2 * c_ / np.sqrt(3)

    lo, hi = -60.0, 60.0
    for _ in range(100):
        mid = 0.5 * (lo + hi)
        if count(mid) < n:
            lo = mid
        else:
            hi = mid
    h = sizes(0.5 * (lo + hi))
    m = np.einsum("nij,nj,nkj->nik", vec, 1.0 / h**2, vec)
    return m


def mmg_ideal(start, problem, n, work, mmg, p):
    pts, tris = read_triangles(start)
    for k in range(5):
        m = lp_metric(pts, tris, problem, n, p=p)
        base = os.path.join(work, f"mmg-{k}")
        meshio.write(base + ".mesh", meshio.Mesh(pts[:, :2], [("triangle", tris)]))
        with open(base + ".sol", "w") as f:
            f.write(f"MeshVersionFormatted 2\nDimension 2\nSolAtVertices\n{len(pts)}\n1 3\n")
            for t in m:
                f.write(f"{t[0, 0]:.17g} {t[0, 1]:.17g} {t[1, 1]:.17g}\n")
            f.write("End\n")
        out = os.path.join(work, f"mmg-{k + 1}.mesh")
        subprocess.run(
            [mmg, "-in", base + ".mesh", "-sol", base + ".sol", "-out", out, "-hgrad", "-1", "-v", "-1"],
            check=True,
            capture_output=True,
        )
        pts, tris = read_triangles(out)
    return pts, tris


# ---------------------------------------------------------------- driver


def solve_mode(problem, mesh_path, out_path):
    m = meshio.read(mesh_path)
    u = PROBLEMS[problem](m.points[:, 0], m.points[:, 1])[0]
    meshio.write(out_path, meshio.Mesh(m.points, m.cells, point_data={"u": u}))


def run(cmd):
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"failed: {' '.join(cmd)}\n{r.stderr}")
    return r


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--smartmesh", default=None)
    ap.add_argument("--problems", default="layer,front,corner")
    ap.add_argument("--p", default="2,inf", help="the norm exponents of (c) and (d)")
    ap.add_argument("--recipe-share", default=None, help="passed to (e)")
    ap.add_argument("--solve", nargs=3, metavar=("PROBLEM", "MESH", "SOLUTION"), help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.solve:
        solve_mode(*args.solve)
        return
    sm = args.smartmesh
    if sm is None:
        for c in ["target/release/smartmesh", "target/debug/smartmesh"]:
            if os.path.exists(os.path.join(ROOT, c)):
                sm = os.path.join(ROOT, c)
                break
    mmg = shutil.which("mmg2d_O3")
    if not mmg:
        import mmgpy

        mmg = os.path.join(os.path.dirname(mmgpy.__file__), "bin", "mmg2d_O3")
    rows = []
    with tempfile.TemporaryDirectory() as work:
        poly = os.path.join(work, "square.poly")
        with open(poly, "w") as f:
            f.write(SQUARE_POLY)
        start = os.path.join(work, "start.vtu")
        run([sm, "mesh", poly, "--size", "0.05", "-o", start])
        for problem in args.problems.split(","):
            recipe = os.path.join(work, f"{problem}.toml")
            with open(recipe, "w") as f:
                f.write(RECIPES[problem])
            b = os.path.join(work, f"{problem}-b.vtu")
            run([sm, "adapt", start, "--recipe", recipe, "-o", b])
            pts, tris = read_triangles(b)
            n = len(pts)
            res = {"b": (n,) + interpolation_error(pts, tris, problem)}
            a = uniform(n, os.path.join(work, f"{problem}-a.vtu"))
            pts, tris = read_triangles(a)
            res["a"] = (len(pts),) + interpolation_error(pts, tris, problem)
            solver = f"{sys.executable} {os.path.abspath(__file__)} --solve {problem} {{mesh}} {{solution}}"
            for p in args.p.split(","):
                c = os.path.join(work, f"{problem}-c-{p}.vtu")
                run([sm, "adapt", start, "--solver", solver, "--complexity-start", str(n // 4),
                     "--complexity-growth", "2", "--complexity", str(n), "--max-iterations", "8",
                     "--hmax", str(HMAX), "--p", p, "-o", c])
                pts, tris = read_triangles(c)
                res["c" + p] = (len(pts),) + interpolation_error(pts, tris, problem)
                e = os.path.join(work, f"{problem}-e-{p}.vtu")
                run([sm, "adapt", start, "--recipe", recipe, "--solver", solver,
                     "--complexity-start", str(n // 4), "--complexity-growth", "2",
                     "--complexity", str(n), "--max-iterations", "8", "--p", p, "-o", e,
                     *(["--recipe-share", args.recipe_share] if args.recipe_share else [])])
                pts, tris = read_triangles(e)
                res["e" + p] = (len(pts),) + interpolation_error(pts, tris, problem)
                pts, tris = mmg_ideal(a, problem, n, work, mmg, float(p))
                res["d" + p] = (len(pts),) + interpolation_error(pts, tris, problem)
            rows.append((problem, res))
            print(json.dumps({"problem": problem, **res}), file=sys.stderr)
    cell = lambda res, k: f"{res[k][0]} v: {res[k][1]:.2e}, {res[k][2]:.2e}"
    ratio = lambda res, x, y: f"{res[x][1] / res[y][1]:.2f}, {res[x][2] / res[y][2]:.2f}"
    print("| problem | (a) uniform Delaunay | (b) geometric recipe |")
    print("|---|---|---|")
    for problem, res in rows:
        print(f"| {problem} | {cell(res, 'a')} | {cell(res, 'b')} |")
    print()
    print("| problem | p | (c) solution loop | (d) MMG, exact Hessian | (c)/(d) L2, H1 | (c)/(b) L2, H1 |")
    print("|---|---|---|---|---|---|")
    for problem, res in rows:
        for p in args.p.split(","):
            c, d = "c" + p, "d" + p
            print(f"| {problem} | {p} | {cell(res, c)} | {cell(res, d)} | {ratio(res, c, d)} | {ratio(res, c, 'b')} |")
    print()
    print("| problem | p | (e) loop with recipe | vertices/N | (e)/(d) L2, H1 | (e)/(b) L2, H1 |")
    print("|---|---|---|---|---|---|")
    for problem, res in rows:
        for p in args.p.split(","):
            e, d = "e" + p, "d" + p
            print(f"| {problem} | {p} | {cell(res, e)} | {res[e][0] / res['b'][0]:.3f} | {ratio(res, e, d)} | {ratio(res, e, 'b')} |")


if __name__ == "__main__":
    main()
