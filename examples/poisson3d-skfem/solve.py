"""Poisson in the unit cube with a spherical wave front: -Δu = f, u = g on the boundary,
with the exact solution (Mitchell's 2D "wave front" benchmark carried to 3D)

    u = atan(ALPHA (r - R0)),  r = |x - C|,  C = (-0.05, -0.05, -0.05),

a spherical internal layer of width about 1/ALPHA that the geometric recipe does not
know of. P1 finite elements on tetrahedra (scikit-fem); the solver of
`smartmesh adapt --solver`:

    python3 solve.py MESH SOLUTION [--error] [--log FILE]

reads MESH (any meshio format; its tetrahedra), writes SOLUTION (a .vtu) with the point
field `u` on the same vertices; with --error prints the L2 and H1-seminorm errors of the
P1 solution against the exact one (a degree-4 rule per tetrahedron), and with --log
appends them as one JSON line to FILE.
"""

import json
import sys

import meshio
import numpy as np
from skfem import Basis, BilinearForm, ElementTetP1, LinearForm, MeshTet, asm, condense, solve
from skfem.helpers import dot, grad

ALPHA, R0 = 20.0, 0.8
C = np.array([-0.05, -0.05, -0.05])


def radius(x):
    return np.sqrt(sum((x[i] - C[i]) ** 2 for i in range(3)))


def exact(x):
    return np.arctan(ALPHA * (radius(x) - R0))


def exact_gradient(x):
    r = radius(x)
    du = ALPHA / (1.0 + (ALPHA * (r - R0)) ** 2)
    return [du * (x[i] - C[i]) / r for i in range(3)]


def load(x):
    # -Δu for a radial u in 3D: -(u'' + 2 u' / r).
    r = radius(x)
    s = ALPHA * (r - R0)
    du = ALPHA / (1.0 + s * s)
    d2u = -2.0 * ALPHA * ALPHA * s / (1.0 + s * s) ** 2
    return -(d2u + 2.0 * du / r)


def errors(mesh, u):
    """The L2 and H1-seminorm errors of the P1 field u against the exact solution."""
    fine = Basis(mesh, ElementTetP1(), intorder=4)
    uh = fine.interpolate(u)
    x = fine.global_coordinates().value
    dx = fine.dx
    l2 = np.sqrt(np.sum((uh.value - exact(x)) ** 2 * dx))
    g = exact_gradient(x)
    h1 = np.sqrt(np.sum(sum((uh.grad[i] - g[i]) ** 2 for i in range(3)) * dx))
    return l2, h1


def main(argv):
    mesh_path, out_path = argv[1], argv[2]
    m = meshio.read(mesh_path)
    tets = np.vstack([c.data for c in m.cells if c.type == "tetra"])
    mesh = MeshTet(m.points[:, :3].T.copy(), tets.T.copy())
    basis = Basis(mesh, ElementTetP1())

    @BilinearForm
    def laplace(u, v, _):
        return dot(grad(u), grad(v))

    @LinearForm
    def rhs(v, w):
        return load(w.x) * v

    a, b = asm(laplace, basis), asm(rhs, basis)
    boundary = mesh.boundary_nodes()
    u = np.zeros(basis.N)
    u[boundary] = exact(mesh.p[:, boundary])
    u = solve(*condense(a, b, x=u, D=boundary))
    # Vertices no tetrahedron uses (none in a valid mesh) keep u = 0.
    meshio.write(out_path, meshio.Mesh(m.points, [("tetra", tets)], point_data={"u": u}))
    if "--error" in argv or "--log" in argv:
        l2, h1 = errors(mesh, u)
        line = {"vertices": len(m.points), "tetrahedra": len(tets), "l2": l2, "h1": h1}
        if "--error" in argv:
            print(f"{len(m.points)} vertices: L2 error {l2:.4e}, H1 seminorm error {h1:.4e}")
        if "--log" in argv:
            with open(argv[argv.index("--log") + 1], "a") as f:
                f.write(json.dumps(line) + "\n")


if __name__ == "__main__":
    main(sys.argv)
