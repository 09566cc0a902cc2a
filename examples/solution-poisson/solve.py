"""Poisson on the unit square with Mitchell's wave front (the NIST adaptivity benchmark
"wave front", mild): -Δu = f, u = g on the boundary, with the exact solution

    u = atan(ALPHA (r - R0)),  r = |(x, y) - (XC, YC)|,

a circular internal layer of width about 1/ALPHA that no geometric recipe knows of.
P1 finite elements (scikit-fem); the solver of `smartmesh adapt --solver`:

    python3 solve.py MESH SOLUTION [--error]

reads MESH (any meshio format; its triangles), writes SOLUTION with the point field
`u` on the same vertices, and with --error prints the L2 and H1-seminorm errors of the
P1 solution against the exact one (a 6-point rule per triangle).
"""

import sys

import meshio
import numpy as np
from skfem import Basis, BilinearForm, ElementTriP1, LinearForm, MeshTri, asm, condense, solve
from skfem.helpers import dot, grad

ALPHA, R0, XC, YC = 50.0, 0.7, -0.05, -0.05


def exact(x, y):
    return np.arctan(ALPHA * (np.hypot(x - XC, y - YC) - R0))


def exact_gradient(x, y):
    r = np.hypot(x - XC, y - YC)
    du = ALPHA / (1.0 + (ALPHA * (r - R0)) ** 2)
    return du * (x - XC) / r, du * (y - YC) / r


def load(x, y):
    r = np.hypot(x - XC, y - YC)
    s = ALPHA * (r - R0)
    du = ALPHA / (1.0 + s * s)
    d2u = -2.0 * ALPHA * ALPHA * s / (1.0 + s * s) ** 2
    return -(d2u + du / r)


def main(argv):
    mesh_path, out_path = argv[1], argv[2]
    m = meshio.read(mesh_path)
    triangles = np.vstack([c.data for c in m.cells if c.type == "triangle"])
    mesh = MeshTri(m.points[:, :2].T.copy(), triangles.T.copy())
    basis = Basis(mesh, ElementTriP1())

    @BilinearForm
    def laplace(u, v, _):
        return dot(grad(u), grad(v))

    @LinearForm
    def rhs(v, w):
        return load(w.x[0], w.x[1]) * v

    a, b = asm(laplace, basis), asm(rhs, basis)
    boundary = mesh.boundary_nodes()
    u = np.zeros(basis.N)
    u[boundary] = exact(mesh.p[0, boundary], mesh.p[1, boundary])
    u = solve(*condense(a, b, x=u, D=boundary))
    meshio.write(out_path, meshio.Mesh(m.points, [("triangle", triangles)], point_data={"u": u}))
    if "--error" in argv:
        fine = Basis(mesh, ElementTriP1(), intorder=4)
        uh = fine.interpolate(u)
        x, y = fine.global_coordinates().value
        dx = fine.dx
        l2 = np.sqrt(np.sum((uh.value - exact(x, y)) ** 2 * dx))
        gx, gy = exact_gradient(x, y)
        h1 = np.sqrt(np.sum(((uh.grad[0] - gx) ** 2 + (uh.grad[1] - gy) ** 2) * dx))
        print(f"{len(m.points)} vertices: L2 error {l2:.4e}, H1 seminorm error {h1:.4e}")


if __name__ == "__main__":
    main(sys.argv)
