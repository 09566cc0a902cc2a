#!/usr/bin/env python3
"""The wing in a box of examples/wing3d, meshed by Gmsh (Python API, OpenCASCADE kernel).

The wing: a NACA 0012 section (the closed-trailing-edge variant, last coefficient
-0.1036, so the trailing edge is a sharp ridge), chord 1, half span SPAN along +y from
the symmetry plane y = 0, set at INCIDENCE degrees (nose up, about the quarter chord).
The tip is rounded: the upper half of the section revolved by 180 degrees about the
chord line at y = SPAN, a body of revolution whose cross-section at each chord station
is a half circle of the section's half thickness there, tangent to the upper and lower
surfaces. The box: BOX (x, y, z ranges), its face y = 0 the symmetry plane.

Tags (physical groups, named):
  volume  1 Fluid
  surface 1 Wing (upper, lower and the rounded tip), 2 Symmetry (y = 0, the root's
          hole in it), 3 Farfield (the five other faces of the box)
  curve   1 TrailingEdge (along the span, root to tip; the tip's cap closes on it)

    python3 examples/wing3d/geometry.py start.msh [--size-wing H] [--size-far H]

writes the starting tetrahedral mesh (MSH 4.1): Gmsh's Delaunay, size SIZE_WING on the
wing (finer where its curvature asks, 12 elements per radian) growing to SIZE_FAR at
the box. Deterministic for one version of gmsh (4.15.2 here), one thread. With
--wake FILE it also writes the wake sheet the recipe names (wake.stl here is its output:
a flat sheet from the trailing edge downstream, write_wake).
"""
import argparse
import math

import gmsh

SPAN = 1.5  # half span, in chords (the rounded tip adds the section's half thickness)
INCIDENCE = 5.0  # degrees, nose up, about (0.25, 0)
BOX = ((-3.0, 6.0), (0.0, 4.0), (-3.0, 3.0))
POINTS = 41  # points per side of the section


def half_thickness(x):
    """NACA 0012 half thickness, closed trailing edge."""
    return 0.6 * (0.2969 * math.sqrt(x) - 0.1260 * x - 0.3516 * x**2 + 0.2843 * x**3
                  - 0.1036 * x**4)


def side(occ, y, sign, ends=None):
    """One side of the section in the plane y as a spline from the leading edge
    (0, y, 0) to the trailing edge (1, y, 0) through points at x = s^2 (s uniform), so
    that they crowd at the nose, with the exact unit tangent at each point (vertical at
    the nose: the two sides meet there without a kink; Gmsh's spline is then within
    1e-5 of the section). `ends`: the point tags of the nose and the tail when another
    side already made them."""
    tags, tangents = [], []
    for i in range(POINTS):
        s = i / (POINTS - 1)
        x = s * s
        if ends and i in (0, POINTS - 1):
            tags.append(ends[0] if i == 0 else ends[1])
        else:
            tags.append(occ.addPoint(x, y, sign * half_thickness(x)))
        # d/ds of (x, z) = (s^2, half_thickness(s^2)).
        dz = 0.6 * (0.2969 - 2 * 0.1260 * s - 4 * 0.3516 * s**3 + 6 * 0.2843 * s**5
                    - 8 * 0.1036 * s**7)
        n = math.hypot(2 * s, dz)
        tangents += [2 * s / n, 0.0, sign * dz / n]
    return (tags[0], tags[-1]), occ.addSpline(tags, tangents=tangents)


def build():
    """The fluid volume: the box less the wing (module header)."""
    occ = gmsh.model.occ
    ends, upper = side(occ, 0.0, 1.0)
    _, lower = side(occ, 0.0, -1.0, ends)
    root = occ.addPlaneSurface([occ.addCurveLoop([upper, -lower])])
    # The straight part: each side swept along +y (extrude gives the top curve first).
    up = occ.extrude([(1, upper)], 0, SPAN, 0)
    low = occ.extrude([(1, lower)], 0, SPAN, 0)
    # The rounded tip: the upper side's tip curve revolved by 180 degrees about the
    # chord, over +y, onto the lower side's tip curve.
    cap = occ.revolve([up[0]], 0, SPAN, 0, 1, 0, 0, -math.pi)
    faces = [root, up[1][1], low[1][1], cap[1][1]]
    # The cap's last curve lies on the lower side's tip curve but is another entity:
    # sewing makes them one, so the four faces close a shell.
    shell = occ.addSurfaceLoop(faces, sewing=True)
    wing = [(3, occ.addVolume([shell]))]
    occ.remove([(2, f) for f in faces[1:]])
    occ.rotate(wing, 0.25, 0, 0, 0, 1, 0, math.radians(INCIDENCE))
    (x0, x1), (y0, y1), (z0, z1) = BOX
    box = occ.addBox(x0, y0, z0, x1 - x0, y1 - y0, z1 - z0)
    fluid, _ = occ.cut([(3, box)], wing)
    occ.synchronize()
    return fluid


def tag(fluid):
    """The physical groups of the module header, found by position."""
    model = gmsh.model
    (x0, x1), (y0, y1), (z0, z1) = BOX
    eps = 1e-6
    wing, symmetry, farfield = [], [], []
    for _, s in model.getBoundary(fluid, oriented=False):
        b = model.getBoundingBox(2, s)
        if b[1] > y0 - eps and b[4] < y0 + eps and (b[0] < x0 + eps and b[3] > x1 - eps):
            symmetry.append(s)
        elif any(abs(b[i] - v) < eps and abs(b[i + 3] - v) < eps
                 for i, v in ((0, x0), (0, x1), (1, y1), (2, z0), (2, z1))):
            farfield.append(s)
        else:
            wing.append(s)
    model.addPhysicalGroup(3, [t for _, t in fluid], 1, "Fluid")
    model.addPhysicalGroup(2, wing, 1, "Wing")
    model.addPhysicalGroup(2, symmetry, 2, "Symmetry")
    model.addPhysicalGroup(2, farfield, 3, "Farfield")
    # The trailing edge: the curve of the wing from the root to the tip that lies
    # farthest downstream (the leading edge is left untagged: the wing is smooth there,
    # and a tagged curve would split it into two patches for the curvature).
    edges = set()
    for s in wing:
        for _, c in model.getBoundary([(2, s)], oriented=False):
            b = model.getBoundingBox(1, c)
            if b[1] < eps and abs(b[4] - SPAN) < 1e-3:
                edges.add((b[0], c))
    edges = sorted(edges)
    assert len(edges) == 2, f"expected two spanwise edges, found {edges}"
    model.addPhysicalGroup(1, [edges[1][1]], 1, "TrailingEdge")
    return wing


def mesh(wing, size_wing, size_far):
    """Size size_wing on the wing growing linearly to size_far 3 chords away; finer
    where the curvature asks."""
    field = gmsh.model.mesh.field
    d = field.add("Distance")
    field.setNumbers(d, "SurfacesList", wing)
    field.setNumber(d, "Sampling", 60)
    t = field.add("Threshold")
    field.setNumber(t, "InField", d)
    field.setNumber(t, "SizeMin", size_wing)
    field.setNumber(t, "SizeMax", size_far)
    field.setNumber(t, "DistMin", 0.0)
    field.setNumber(t, "DistMax", 3.0)
    field.setAsBackgroundMesh(t)
    opt = gmsh.option.setNumber
    opt("Mesh.MeshSizeExtendFromBoundary", 0)
    opt("Mesh.MeshSizeFromPoints", 0)
    opt("Mesh.MeshSizeFromCurvature", 12)
    opt("Mesh.MeshSizeMin", size_wing / 8)
    opt("Mesh.MeshSizeMax", size_far)
    opt("Mesh.Algorithm", 6)
    opt("Mesh.Algorithm3D", 1)
    opt("General.NumThreads", 1)
    gmsh.model.mesh.generate(3)


WAKE_END = 4.0  # the wake sheet runs from the trailing edge to x = WAKE_END
WAKE_CELLS = (12, 6)  # its quads along x and along y, each split into two triangles


def trailing_edge():
    """(x, z) of the trailing edge once the wing is set at its incidence."""
    a = math.radians(INCIDENCE)
    # OpenCASCADE's rotation by +a about +y through (0.25, 0, 0): z goes to -x sin a.
    return 0.25 + 0.75 * math.cos(a), -0.75 * math.sin(a)


def write_wake(path):
    """The wake sheet as an ASCII STL: the plane z = z(trailing edge) from the trailing
    edge downstream to x = WAKE_END (the free stream is along +x), from the symmetry
    plane to the tip (y = SPAN), WAKE_CELLS quads each split along its diagonal. The
    numbers are printed to 6 decimals: the file is the same on every machine."""
    x0, z = trailing_edge()
    nx, ny = WAKE_CELLS
    p = lambda i, j: (x0 + (WAKE_END - x0) * i / nx, SPAN * j / ny, z)
    lines = ["solid wake"]
    for i in range(nx):
        for j in range(ny):
            for tri in ((p(i, j), p(i + 1, j), p(i + 1, j + 1)),
                        (p(i, j), p(i + 1, j + 1), p(i, j + 1))):
                lines.append("  facet normal 0 0 1")
                lines.append("    outer loop")
                lines += ["      vertex %.6f %.6f %.6f" % v for v in tri]
                lines.append("    endloop")
                lines.append("  endfacet")
    lines.append("endsolid wake")
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("out")
    p.add_argument("--size-wing", type=float, default=0.08)
    p.add_argument("--size-far", type=float, default=1.0)
    p.add_argument("--verbose", action="store_true")
    p.add_argument("--wake", metavar="FILE", help="also write the wake sheet (ASCII STL)")
    a = p.parse_args()
    if a.wake:
        write_wake(a.wake)
    gmsh.initialize(["-noenv"])
    gmsh.option.setNumber("General.Terminal", 1 if a.verbose else 0)
    gmsh.model.add("wing3d")
    fluid = build()
    wing = tag(fluid)
    mesh(wing, a.size_wing, a.size_far)
    gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
    gmsh.option.setNumber("Mesh.SaveAll", 0)
    gmsh.write(a.out)
    gmsh.finalize()


if __name__ == "__main__":
    main()
