"""Writes the geometries of smartmesh's examples as Triangle .poly files, and a starting
mesh for each made with PyPI `triangle` and written by PyPI `gmsh` as MSH 4.1 ASCII.

Run from the repository root:

    python3 examples/make_examples.py            # every example
    python3 examples/make_examples.py u-duct     # some of them: naca0012-agard01 to -agard05,
                                                 # gamm-a7-viscous, u-duct, distributor-1-narrow,
                                                 # distributor-2-thick, distributor-3-s-shaped
    python3 examples/make_examples.py --out DIR  # into DIR instead of examples/
    python3 examples/make_examples.py --estimate [names]   # expected triangle counts
    python3 examples/make_examples.py --mmg [names]        # adapt with mmg2d_O3 (PyPI mmgpy)

Needs numpy, PyPI `triangle` (Shewchuk's Triangle 1.6) and PyPI `gmsh` (4.15). The
output is deterministic: the same versions write the same bytes.

What each .poly holds (thesis 2.2.7, 4.3.2: the topology is carried by tags):
- vertices: the geometry's points; a vertex whose boundary marker is not 0 is a
  topological point and the marker is its tag (leading and trailing edges, corners);
  every topological point is where two segments of different markers meet, so that the
  topology of any mesh of it recovers the point as a curve junction;
- segments: the boundary, each with a boundary marker = the tag of its topological curve;
- holes: one point inside each body;
- one region: a point of the fluid with attribute = the tag of the topological face.
The tag numbers and names are listed in the comments at the top of each .poly.

The starting meshes (`start.msh`, each < 200 KB) are constrained Delaunay meshes of the
.poly made by Triangle with `pq30Aa<area>` (minimum angle 30 degrees, regional
attributes, an area bound; the airfoils' then refined with `rpq30Aa` so that their
edges grow as 0.03 + 0.2 r with the distance r from mid-chord): segment markers become
physical curves, regional attributes the physical surface, topological points physical
points, each named as in the .poly.
Coordinates are rounded to 10 significant digits so that the files stay small.

Geometries (parameters are the constants below):
- naca0012-agard01 to -agard05, gamm-a7-viscous: the NACA 0012 airfoil from the analytic NACA
  4-digit thickness formula y = 0.6 (0.2969 sqrt(x) - 0.1260 x - 0.3516 x^2 + 0.2843 x^3
  - 0.1015 x^4), taken to its root x = 1.008930... where y = 0 so that the trailing edge
  closes (hence a chord of 1.00893, as thesis 6.2.4 says of the NACA 0012); cosine
  spacing from the leading edge; a circular far field.
- u-duct: a 180-degree bend of a channel of width 1 (thesis 6.1): two straight legs of
  length 4 and a half annulus of inner radius 0.5.
- distributor: a stay vane and a guide vane in one periodic pitch of a hydraulic turbine
  distributor unrolled into a 2D cascade (thesis 6.3.1 and appendix A.1.6); three
  variants of the guide vane, same topology and tags.
"""
import math
import os
import sys

import gmsh
import numpy as np
import triangle

HERE = os.path.dirname(os.path.abspath(__file__))


def rnd(v):
    """Rounds to 10 significant digits (what the files hold)."""
    return float("%.10g" % v)


class Geometry:
    """A planar straight line graph with tagged points, curves and one face."""

    def __init__(self, title):
        self.title = title
        self.vertices = []      # (x, y)
        self.vmarkers = []      # point tag or 0
        self.segments = []      # (a, b)
        self.smarkers = []      # curve tag
        self.holes = []
        self.region = None      # (x, y, face tag)
        self.names = {}         # (dim, tag) -> name
        self.notes = []         # comment lines

    def add_vertex(self, x, y, tag=0):
        self.vertices.append((rnd(x), rnd(y)))
        self.vmarkers.append(tag)
        return len(self.vertices) - 1

    def add_point(self, x, y, tag, name):
        self.names[(0, tag)] = name
        return self.add_vertex(x, y, tag)

    def add_curve(self, tag, name, start, pts, end):
        """A curve from vertex `start` through the coordinates `pts` to vertex `end`."""
        self.names[(1, tag)] = name
        ids = [start] + [self.add_vertex(x, y) for x, y in pts] + [end]
        for a, b in zip(ids, ids[1:]):
            self.segments.append((a, b))
            self.smarkers.append(tag)

    def add_closed_curve(self, tag, name, pts):
        self.names[(1, tag)] = name
        ids = [self.add_vertex(x, y) for x, y in pts]
        for k in range(len(ids)):
            self.segments.append((ids[k], ids[(k + 1) % len(ids)]))
            self.smarkers.append(tag)

    def set_face(self, x, y, tag, name):
        self.region = (rnd(x), rnd(y), tag)
        self.names[(2, tag)] = name

    def check(self):
        """Every vertex where curves of different tags meet is a tagged point."""
        curves = {}
        for (a, b), m in zip(self.segments, self.smarkers):
            curves.setdefault(a, set()).add(m)
            curves.setdefault(b, set()).add(m)
        for v, ms in curves.items():
            if len(ms) > 1 and self.vmarkers[v] == 0:
                raise SystemExit("%s: vertex %d at %s joins curves %s but is no tagged point" % (self.title, v, self.vertices[v], sorted(ms)))

    def write_poly(self, path, extra_notes=()):
        self.check()
        kind = {0: "point", 1: "curve", 2: "face"}
        lines = ["# " + self.title, "# Written by examples/make_examples.py (do not edit by hand)."]
        lines += ["# " + n for n in list(self.notes) + list(extra_notes)]
        lines.append("# Tags (topological entity: tag = name):")
        for (dim, tag), name in sorted(self.names.items()):
            lines.append("#   %s %d = %s" % (kind[dim], tag, name))
        lines.append("# Vertex markers are point tags (0: not a topological point); segment markers")
        lines.append("# are curve tags; the region's attribute is the face tag.")
        lines.append("%d 2 0 1" % len(self.vertices))
        for i, ((x, y), m) in enumerate(zip(self.vertices, self.vmarkers)):
            lines.append("%d %.10g %.10g %d" % (i + 1, x, y, m))
        lines.append("%d 1" % len(self.segments))
        for i, ((a, b), m) in enumerate(zip(self.segments, self.smarkers)):
            lines.append("%d %d %d %d" % (i + 1, a + 1, b + 1, m))
        lines.append("%d" % len(self.holes))
        for i, (x, y) in enumerate(self.holes):
            lines.append("%d %.10g %.10g" % (i + 1, x, y))
        x, y, tag = self.region
        lines.append("1")
        lines.append("1 %.10g %.10g %d -1" % (x, y, tag))
        with open(path, "w") as f:
            f.write("\n".join(lines) + "\n")

    def triangulate(self, max_area, min_angle=30):
        data = {
            "vertices": np.array(self.vertices, dtype=float),
            "vertex_markers": np.array(self.vmarkers, dtype=np.int32).reshape(-1, 1),
            "segments": np.array(self.segments, dtype=np.int32),
            "segment_markers": np.array(self.smarkers, dtype=np.int32).reshape(-1, 1),
            "regions": np.array([[self.region[0], self.region[1], self.region[2], -1.0]]),
        }
        if self.holes:
            data["holes"] = np.array(self.holes, dtype=float)
        opts = "pq%gAa%s" % (min_angle, ("%.10f" % max_area).rstrip("0"))
        return triangle.triangulate(data, opts)

    def write_msh(self, path, max_area, min_angle=30, grade=None):
        t = self.triangulate(max_area, min_angle)
        if grade is not None:
            # Refine until every triangle is below the area of an equilateral triangle
            # of edge grade(centroid): a mesh that coarsens away from the body.
            for _ in range(8):
                c = t["vertices"][t["triangles"]].mean(axis=1)
                h = np.array([grade(x, y) for x, y in c])
                bound = math.sqrt(3) / 4 * h * h
                v = t["vertices"][t["triangles"]]
                area = 0.5 * np.abs((v[:, 1, 0] - v[:, 0, 0]) * (v[:, 2, 1] - v[:, 0, 1]) - (v[:, 1, 1] - v[:, 0, 1]) * (v[:, 2, 0] - v[:, 0, 0]))
                if np.all(area <= bound):
                    break
                t = triangle.triangulate(dict(t, triangle_max_area=bound.reshape(-1, 1)), "rpq%gAa" % min_angle)
        return self.write_triangulation(t, path)

    def write_triangulation(self, t, path):
        """Writes a Triangle output `t` of this geometry as MSH 4.1 ASCII."""
        verts = t["vertices"]
        tris = t["triangles"]
        segs = t["segments"]
        smark = t["segment_markers"].ravel()
        attrs = t["triangle_attributes"].ravel()
        face = self.region[2]
        assert np.all(attrs == face), "one region"
        n = len(verts)
        # Where each vertex lies: a topological point, a curve, or the face.
        point_tag = {}
        for i, m in enumerate(self.vmarkers):
            if m:
                point_tag[i] = m   # Triangle keeps the input vertices first, in order
        curve_of = {}
        for (a, b), m in zip(segs, smark):
            for v in (int(a), int(b)):
                curve_of.setdefault(v, set()).add(int(m))
        gmsh.model.add(os.path.basename(os.path.dirname(path)))
        for tag in sorted(set(point_tag.values())):
            gmsh.model.addDiscreteEntity(0, tag)
        curve_tags = sorted(set(int(m) for m in smark))
        for tag in curve_tags:
            gmsh.model.addDiscreteEntity(1, tag)
        gmsh.model.addDiscreteEntity(2, face, curve_tags)
        where = {}
        for v in range(n):
            if v in point_tag:
                where.setdefault((0, point_tag[v]), []).append(v)
            elif v in curve_of:
                cs = curve_of[v]
                if len(cs) > 1:
                    raise SystemExit("%s: mesh vertex %d joins curves %s" % (self.title, v, sorted(cs)))
                where.setdefault((1, next(iter(cs))), []).append(v)
            else:
                where.setdefault((2, face), []).append(v)
        for (dim, tag), vs in sorted(where.items()):
            coords = []
            for v in vs:
                coords += [rnd(verts[v][0]), rnd(verts[v][1]), 0.0]
            gmsh.model.mesh.addNodes(dim, tag, [v + 1 for v in vs], coords)
        etag = 1
        for v, tag in sorted(point_tag.items(), key=lambda kv: kv[1]):
            gmsh.model.mesh.addElementsByType(tag, 15, [etag], [v + 1])
            etag += 1
        for tag in curve_tags:
            sel = [k for k in range(len(segs)) if smark[k] == tag]
            nodes = [int(segs[k][j]) + 1 for k in sel for j in (0, 1)]
            gmsh.model.mesh.addElementsByType(tag, 1, list(range(etag, etag + len(sel))), nodes)
            etag += len(sel)
        nodes = [int(v) + 1 for tri in tris for v in tri]
        gmsh.model.mesh.addElementsByType(face, 2, list(range(etag, etag + len(tris))), nodes)
        for (dim, tag), name in sorted(self.names.items()):
            gmsh.model.addPhysicalGroup(dim, [tag], tag, name)
        gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
        gmsh.option.setNumber("Mesh.Binary", 0)
        gmsh.write(path)
        gmsh.model.remove()
        return n, len(tris)


# ---------------------------------------------------------------------------------------
# NACA 0012

NACA_T = 0.12                    # thickness / chord of the 4-digit formula
NACA_A = (0.2969, -0.1260, -0.3516, 0.2843, -0.1015)   # the standard coefficients


def naca_half_thickness(x, t=NACA_T):
    a0, a1, a2, a3, a4 = NACA_A
    return 5.0 * t * (a0 * math.sqrt(x) + a1 * x + a2 * x * x + a3 * x ** 3 + a4 * x ** 4)


def naca_closed_chord():
    """The root of the thickness beyond x = 1: where the profile closes (1.008930...)."""
    lo, hi = 1.0, 1.1
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if naca_half_thickness(mid) > 0:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


def naca0012(title, per_side, far_radius, far_points, notes):
    """The airfoil (upper curve 1, lower curve 2, leading edge point 11, trailing edge
    point 12) in a circular far field (curve 3) centred at mid-chord; face 100."""
    g = Geometry(title)
    c = naca_closed_chord()
    g.notes += [
        "NACA 0012: y = +-0.6 (0.2969 sqrt(x) - 0.1260 x - 0.3516 x^2 + 0.2843 x^3 - 0.1015 x^4),",
        "0 <= x <= %.6f (the root of y: closed trailing edge); %d vertices a side, cosine spacing" % (c, per_side + 1),
        "x = c (1 - cos b) / 2, b uniform in [0, pi]. Far field: circle of radius %g about (%g, 0), %d vertices." % (far_radius, c / 2, far_points),
    ] + list(notes)
    le = g.add_point(0.0, 0.0, 11, "LeadingEdge")
    te = g.add_point(c, 0.0, 12, "TrailingEdge")
    xs = [c * (1 - math.cos(math.pi * k / per_side)) / 2 for k in range(1, per_side)]
    g.add_curve(1, "Upper", le, [(x, naca_half_thickness(x)) for x in xs], te)
    g.add_curve(2, "Lower", le, [(x, -naca_half_thickness(x)) for x in xs], te)
    g.add_closed_curve(3, "FarField", [(c / 2 + far_radius * math.cos(2 * math.pi * k / far_points), far_radius * math.sin(2 * math.pi * k / far_points)) for k in range(far_points)])
    g.holes.append((rnd(c / 2), 0.0))
    g.set_face(c / 2, far_radius / 2, 100, "Fluid")
    return g


def naca0012_agard01():
    return naca0012(
        "NACA 0012 airfoil in a far field of radius 25 chords: AGARD01 (M = 0.80, alpha = 1.25 deg)",
        per_side=100, far_radius=25.0, far_points=48,
        notes=["The chord lies on the x axis; the free stream comes at alpha = 1.25 deg (see recipe.toml)."],
    )


# AGARD02-05 (thesis 6.2.3-6.2.6, table 6.1): the same airfoil; AGARD03 in a far field of
# radius 75 as the thesis used (its trailing-edge shocks reach 35 chords), the others 25.
AGARD = {
    "02": (0.85, 1.00, 25.0, 48),
    "03": (0.95, 0.00, 75.0, 96),
    "04": (1.20, 0.00, 25.0, 48),
    "05": (1.20, 7.00, 25.0, 48),
}


def naca0012_agard(case):
    mach, alpha, radius, points = AGARD[case]
    return naca0012(
        "NACA 0012 airfoil in a far field of radius %g chords: AGARD%s (M = %.2f, alpha = %g deg)" % (radius, case, mach, alpha),
        per_side=100, far_radius=radius, far_points=points,
        notes=["The chord lies on the x axis; the free stream comes at alpha = %g deg (see recipe.toml)." % alpha],
    )


def gamm_a7_viscous():
    return naca0012(
        "NACA 0012 airfoil in a far field of radius 50 chords: a GAMM A7-like viscous case (M = 0.85, alpha = 0, Re = 5000)",
        per_side=100, far_radius=50.0, far_points=64,
        notes=["The chord lies on the x axis, the free stream along +x."],
    )


# ---------------------------------------------------------------------------------------
# U-duct

UDUCT_WIDTH = 1.0       # channel width
UDUCT_RIN = 0.5         # inner radius of the bend
UDUCT_LEG = 4.0         # length of each straight leg
UDUCT_H = 0.05          # boundary vertex spacing


def straight(p, q, h):
    n = max(1, int(math.ceil(math.dist(p, q) / h)))
    return [(p[0] + (q[0] - p[0]) * k / n, p[1] + (q[1] - p[1]) * k / n) for k in range(1, n)]


def arc(cx, cy, r, a0, a1, h):
    n = max(2, int(math.ceil(abs(a1 - a0) * r / h)))
    return [(cx + r * math.cos(a0 + (a1 - a0) * k / n), cy + r * math.sin(a0 + (a1 - a0) * k / n)) for k in range(1, n)]


def u_duct():
    """A channel bent by 180 degrees, legs pointing down (an upside-down U): the flow
    enters at the bottom of the left leg, turns over the top and leaves at the bottom
    of the right leg. Tags as in the thesis' figure 5.1: points 1, 2 (inlet corners),
    3, 4 (outlet corners); curves 11 (Inlet), 12 (Outlet), 13 (OuterWall, over the top
    from the inlet's outer corner to the outlet's outer corner), 14 (InnerWall, under
    the bend); face 100."""
    g = Geometry("U-duct: a channel of width 1 bent by 180 degrees (thesis 6.1)")
    ri, ro, L, h = UDUCT_RIN, UDUCT_RIN + UDUCT_WIDTH, UDUCT_LEG, UDUCT_H
    g.notes += [
        "Channel width %g, bend: half annulus about (0, 0) of radii %g and %g, legs of length %g" % (UDUCT_WIDTH, ri, ro, L),
        "down to y = -%g; inlet at the bottom of the left leg, outlet at the bottom of the right leg." % L,
        "Boundary vertices every %g or less." % h,
    ]
    p1 = g.add_point(-ro, -L, 1, "InletOuterCorner")
    p2 = g.add_point(-ri, -L, 2, "InletInnerCorner")
    p3 = g.add_point(ro, -L, 3, "OutletOuterCorner")
    p4 = g.add_point(ri, -L, 4, "OutletInnerCorner")
    g.add_curve(11, "Inlet", p1, straight((-ro, -L), (-ri, -L), h), p2)
    g.add_curve(12, "Outlet", p4, straight((ri, -L), (ro, -L), h), p3)
    outer = straight((-ro, -L), (-ro, 0), h) + [(-ro, 0.0)] + arc(0, 0, ro, math.pi, 0, h) + [(ro, 0.0)] + straight((ro, 0), (ro, -L), h)
    g.add_curve(13, "OuterWall", p1, outer, p3)
    inner = straight((-ri, -L), (-ri, 0), h) + [(-ri, 0.0)] + arc(0, 0, ri, math.pi, 0, h) + [(ri, 0.0)] + straight((ri, 0), (ri, -L), h)
    g.add_curve(14, "InnerWall", p2, inner, p4)
    g.set_face(-(ri + ro) / 2, -L / 2, 100, "Fluid")
    return g


# ---------------------------------------------------------------------------------------
# Distributor

PITCH = 30.0
# Lower periodic side (inlet to outlet); the upper one is the same shifted by PITCH.
PERIODIC = [(-100.0, -16.0), (-72.0, -22.0), (-24.0, -36.0), (0.0, -44.0)]
# Stay vane: a round nose, straight flanks, circular arcs tapering to a blunt trailing
# edge; its trailing edge centre is the start of the wake polyline of appendix A.1.6.
SV_TE = (-50.0, -12.8)
SV_CHORD = 20.0
SV_STAGGER = -13.5        # degrees, chord from the leading to the trailing edge
SV_NOSE = 1.6             # nose radius
SV_TE_HALF = 0.3          # half thickness of the blunt trailing edge
SV_FLANK = (9.0, -2.0, 8.0, 3.0)   # upper flank length, angle (deg), lower flank length, angle
# Guide vane: camber line and a NACA 4-digit thickness with a blunt trailing edge; the
# trailing edge stays at GV_TE in every variant.
GV_TE = (-26.0, -20.0)
GV_TE_HALF = 0.2
GV_VARIANTS = {
    # name: (leading edge, thickness / chord, camber kind, camber / chord, title)
    "1-narrow": ((-42.0, -14.2), 0.06, "arc", 0.04, "a narrow guide vane: strong curvature at its leading edge (thesis 6.3.1.1)"),
    "2-thick": ((-38.5, -15.8), 0.22, "arc", 0.03, "a thick guide vane and a larger gap to the stay vane (thesis 6.3.1.2)"),
    "3-s-shaped": ((-46.5, -13.6), 0.08, "s", 0.05, "a thin S-shaped guide vane and a very small gap to the stay vane (thesis 6.3.1.3)"),
}
DIST_H = 1.5              # vertex spacing on the periodic sides, inlet and outlet
BLADE_H = 0.25            # largest vertex spacing on the blades


def rotate(p, ang, origin=(0.0, 0.0)):
    c, s = math.cos(ang), math.sin(ang)
    return (origin[0] + c * p[0] - s * p[1], origin[1] + s * p[0] + c * p[1])


def tangent_arc(s, t, e, h):
    """Points strictly between s and e on the circle tangent to direction t at s that
    passes through e."""
    n_ = (-t[1], t[0])
    d = (e[0] - s[0], e[1] - s[1])
    rho = (d[0] ** 2 + d[1] ** 2) / (2 * (d[0] * n_[0] + d[1] * n_[1]))
    cx, cy = s[0] + rho * n_[0], s[1] + rho * n_[1]
    a0 = math.atan2(s[1] - cy, s[0] - cx)
    a1 = math.atan2(e[1] - cy, e[0] - cx)
    da = (a1 - a0 + math.pi) % (2 * math.pi) - math.pi
    return arc(cx, cy, abs(rho), a0, a0 + da, h)


def stay_vane_local(h):
    """The stay vane in its chord frame (leading edge at 0, trailing edge at SV_CHORD):
    the seven points and the seven curves between them, in order around the vane."""
    a, L, b = SV_NOSE, SV_CHORD, SV_TE_HALF
    lu, au, ll, al = SV_FLANK
    au, al = math.radians(au), math.radians(al)
    tu = (math.cos(au), math.sin(au))
    tl = (math.cos(al), math.sin(al))
    # Tangent points on the nose circle (centre (a, 0)) of the flank lines.
    p2 = (a - a * tu[1], a * tu[0])
    p7 = (a + a * tl[1], -a * tl[0])
    p3 = (p2[0] + lu * tu[0], p2[1] + lu * tu[1])
    p6 = (p7[0] + ll * tl[0], p7[1] + ll * tl[1])
    p1, p4, p5 = (0.0, 0.0), (L, b), (L, -b)
    ang2 = math.atan2(p2[1], p2[0] - a)
    ang7 = math.atan2(p7[1], p7[0] - a)
    curves = [
        (101, "StayVaneNoseUpper", arc(a, 0, a, math.pi, ang2, h / 4)),
        (102, "StayVaneUpperFlank", straight(p2, p3, h)),
        (103, "StayVaneUpperTail", tangent_arc(p3, tu, p4, h)),
        (104, "StayVaneTrailingEdge", straight(p4, p5, h / 4)),
        (105, "StayVaneLowerTail", list(reversed(tangent_arc(p6, tl, p5, h)))),
        (106, "StayVaneLowerFlank", list(reversed(straight(p7, p6, h)))),
        (107, "StayVaneNoseLower", arc(a, 0, a, ang7, -math.pi, h / 4)),
    ]
    points = [p1, p2, p3, p4, p5, p6, p7]
    return points, curves


def guide_vane_local(chord, thick, camber_kind, camber, n):
    """Upper and lower sides from the leading edge (0, 0) to the trailing edge
    corners, in the chord frame; x from the leading edge, cosine spacing."""
    up, lo = [], []
    for k in range(n + 1):
        s = (1 - math.cos(math.pi * k / n)) / 2
        if camber_kind == "arc":
            yc, dyc = 4 * camber * s * (1 - s), 4 * camber * (1 - 2 * s)
        else:   # S-shaped: positive camber in front, negative behind
            yc, dyc = 6 * camber * s * (1 - s) * (1 - 2 * s) * 1.3, 6 * camber * 1.3 * (1 - 6 * s + 6 * s * s)
        yt = naca_half_thickness(s, thick) + s * (GV_TE_HALF / chord - naca_half_thickness(1.0, thick))
        th = math.atan(dyc)
        up.append((chord * (s - yt * math.sin(th)), chord * (yc + yt * math.cos(th))))
        lo.append((chord * (s + yt * math.sin(th)), chord * (yc - yt * math.cos(th))))
    return up, lo


def distributor(variant):
    le, thick, ckind, camber, what = GV_VARIANTS[variant]
    g = Geometry("Distributor %s: a stay vane and %s" % (variant[0], what))
    # Periodic channel: curves 301 (Inlet), 302-304 (lower periodic side), 305 (Outlet),
    # 306-308 (upper periodic side), counter-clockwise.
    low = PERIODIC
    up = [(x, y + PITCH) for x, y in PERIODIC]
    c_in_up = g.add_point(*up[0], 21, "InletUpper")
    c_in_lo = g.add_point(*low[0], 22, "InletLower")
    c_lo1 = g.add_point(*low[1], 23, "LowerPeriodic1")
    c_lo2 = g.add_point(*low[2], 24, "LowerPeriodic2")
    c_out_lo = g.add_point(*low[3], 25, "OutletLower")
    c_out_up = g.add_point(*up[3], 26, "OutletUpper")
    c_up2 = g.add_point(*up[2], 27, "UpperPeriodic2")
    c_up1 = g.add_point(*up[1], 28, "UpperPeriodic1")
    h = DIST_H
    g.add_curve(301, "Inlet", c_in_up, straight(up[0], low[0], h), c_in_lo)
    g.add_curve(302, "LowerPeriodic1", c_in_lo, straight(low[0], low[1], h), c_lo1)
    g.add_curve(303, "LowerPeriodic2", c_lo1, straight(low[1], low[2], h), c_lo2)
    g.add_curve(304, "LowerPeriodic3", c_lo2, straight(low[2], low[3], h), c_out_lo)
    g.add_curve(305, "Outlet", c_out_lo, straight(low[3], up[3], h), c_out_up)
    g.add_curve(306, "UpperPeriodic3", c_out_up, straight(up[3], up[2], h), c_up2)
    g.add_curve(307, "UpperPeriodic2", c_up2, straight(up[2], up[1], h), c_up1)
    g.add_curve(308, "UpperPeriodic1", c_up1, straight(up[1], up[0], h), c_in_up)

    # Stay vane: points 1..7, curves 101..107.
    ang = math.radians(SV_STAGGER)
    sv_le = (SV_TE[0] - SV_CHORD * math.cos(ang), SV_TE[1] - SV_CHORD * math.sin(ang))
    pts, curves = stay_vane_local(BLADE_H)
    place = lambda p: rotate(p, ang, sv_le)
    sv_names = ["StayVaneLeadingEdge", "StayVaneUpperNoseEnd", "StayVaneUpperTailStart", "StayVaneTrailingEdgeUpper",
                "StayVaneTrailingEdgeLower", "StayVaneLowerTailStart", "StayVaneLowerNoseEnd"]
    ids = [g.add_point(*place(p), k + 1, sv_names[k]) for k, p in enumerate(pts)]
    for k, (tag, name, inner) in enumerate(curves):
        g.add_curve(tag, name, ids[k], [place(p) for p in inner], ids[(k + 1) % 7])
    mid = place(((pts[2][0] + pts[5][0]) / 2, (pts[2][1] + pts[5][1]) / 2))
    g.holes.append((rnd(mid[0]), rnd(mid[1])))

    # Guide vane: points 13 (leading edge), 11, 12 (trailing edge corners), curves 201
    # (upper side, 13 -> 11), 202 (trailing edge, 11 -> 12), 203 (lower side, 12 -> 13).
    chord = math.dist(le, GV_TE)
    gang = math.atan2(GV_TE[1] - le[1], GV_TE[0] - le[0])
    n = 80
    upl, lol = guide_vane_local(chord, thick, ckind, camber, n)
    gp = lambda p: rotate(p, gang, le)
    g13 = g.add_point(*gp(upl[0]), 13, "GuideVaneLeadingEdge")
    g11 = g.add_point(*gp(upl[-1]), 11, "GuideVaneTrailingEdgeUpper")
    g12 = g.add_point(*gp(lol[-1]), 12, "GuideVaneTrailingEdgeLower")
    g.add_curve(201, "GuideVaneUpperSide", g13, [gp(p) for p in upl[1:-1]], g11)
    g.add_curve(202, "GuideVaneTrailingEdge", g11, straight(gp(upl[-1]), gp(lol[-1]), BLADE_H / 4), g12)
    g.add_curve(203, "GuideVaneLowerSide", g12, [gp(p) for p in reversed(lol[1:-1])], g13)
    gm = gp(((upl[n // 2][0] + lol[n // 2][0]) / 2, (upl[n // 2][1] + lol[n // 2][1]) / 2))
    g.holes.append((rnd(gm[0]), rnd(gm[1])))

    g.set_face(-90.0, 0.0, 1000, "Fluid")
    g.notes += [
        "One pitch (%g) of a distributor unrolled into a 2D cascade, flow along +x. Periodic sides:" % PITCH,
        "lower %s, upper the same shifted by %g in y." % (" ".join("(%g, %g)" % p for p in PERIODIC), PITCH),
        "Stay vane: chord %g, stagger %g deg, trailing edge centre (%g, %g), nose radius %g, flanks" % (SV_CHORD, SV_STAGGER, SV_TE[0], SV_TE[1], SV_NOSE),
        "(length, angle) upper (%g, %g deg), lower (%g, %g deg), tangent circular arcs to a blunt" % SV_FLANK,
        "trailing edge of half thickness %g." % SV_TE_HALF,
        "Guide vane: leading edge (%g, %g), trailing edge (%g, %g), NACA thickness %g, %s camber %g," % (le[0], le[1], GV_TE[0], GV_TE[1], thick, "circular-arc" if ckind == "arc" else "S-shaped (cubic)", camber),
        "blunt trailing edge of half thickness %g." % GV_TE_HALF,
    ]
    return g


# ---------------------------------------------------------------------------------------

def airfoil_grading(x, y):
    """Edge length of the airfoils' starting meshes: 0.03 + 0.2 r, r the distance
    from mid-chord, so that the shocks and the wake have vertices to start from."""
    return 0.03 + 0.2 * math.hypot(x - 0.5, y)


# name -> (folder, geometry builder, Triangle area bound of the starting mesh, grading)
EXAMPLES = {
    "naca0012-agard01": ("naca0012-agard01", naca0012_agard01, 40.0, airfoil_grading),
    "gamm-a7-viscous": ("gamm-a7-viscous", gamm_a7_viscous, 150.0, airfoil_grading),
    "naca0012-agard02": ("naca0012-agard02", lambda: naca0012_agard("02"), 40.0, airfoil_grading),
    "naca0012-agard03": ("naca0012-agard03", lambda: naca0012_agard("03"), 400.0, airfoil_grading),
    "naca0012-agard04": ("naca0012-agard04", lambda: naca0012_agard("04"), 40.0, airfoil_grading),
    "naca0012-agard05": ("naca0012-agard05", lambda: naca0012_agard("05"), 40.0, airfoil_grading),
    "u-duct": ("u-duct", u_duct, 0.01, None),
}
for _v in GV_VARIANTS:
    EXAMPLES["distributor-" + _v] = (os.path.join("distributor", _v), (lambda v: lambda: distributor(v))(_v), 20.0, None)


def make(name, root=HERE):
    folder, build, area, grade = EXAMPLES[name]
    d = os.path.join(root, folder)
    os.makedirs(d, exist_ok=True)
    g = build()
    g.write_poly(os.path.join(d, "geometry.poly"))
    nv, nt = g.write_msh(os.path.join(d, "start.msh"), area, grade=grade)
    size = os.path.getsize(os.path.join(d, "start.msh"))
    print("%-28s geometry.poly: %d vertices, %d segments; start.msh: %d vertices, %d triangles, %d bytes" % (name, len(g.vertices), len(g.segments), nv, nt, size))


def recipe_of(name):
    folder = EXAMPLES[name][0]
    d = os.path.join(HERE, folder if not folder.startswith("distributor") else "distributor")
    for r in ("recipe.toml", "recipe.cfg"):
        if os.path.exists(os.path.join(d, r)):
            return os.path.join(d, r)
    raise SystemExit("%s: no recipe.toml or recipe.cfg in %s" % (name, d))


def estimate(name, smartmesh, rounds=6):
    """Estimates how many triangles a mesh that conforms to the recipe's field has: the
    starting mesh is refined by Triangle (isotropically) until every triangle is
    smaller than its vertices' h1 h2 asks, then N = sum of 4 area / (sqrt(3) h1 h2) over
    the triangles (the metric area over the area of a unit equilateral triangle). An
    estimate of what `smartmesh adapt` will produce, not a count of an adapted mesh."""
    import subprocess
    import tempfile
    import meshio
    folder, build, area, _ = EXAMPLES[name]
    g = build()
    recipe = recipe_of(name)
    t = g.triangulate(area)
    history = []
    with tempfile.TemporaryDirectory() as tmp:
        msh, vtu = os.path.join(tmp, "m.msh"), os.path.join(tmp, "f.vtu")
        for k in range(rounds + 1):
            g.write_triangulation(t, msh)
            out = subprocess.run([smartmesh, "size", msh, "--recipe", recipe, "-o", vtu, "--json"], check=True, capture_output=True, text=True)
            m = meshio.read(vtu)
            h1, h2 = m.point_data["h1"], m.point_data["h2"]
            tri = m.cells_dict["triangle"]
            p = m.points[:, :2]
            u, w = p[tri[:, 1]] - p[tri[:, 0]], p[tri[:, 2]] - p[tri[:, 0]]
            a = 0.5 * np.abs(u[:, 0] * w[:, 1] - u[:, 1] * w[:, 0])
            density = (1.0 / (h1 * h2))[tri].mean(axis=1)
            n_est = float(np.sum(a * density) * 4 / math.sqrt(3))
            history.append(n_est)
            if k == rounds:
                break
            # Isotropic refinement to edges of about sqrt(h1 h2), enough to integrate
            # the density 1 / (h1 h2), which varies on the scale of the distance to the
            # sources, not on the scale of the smaller size.
            bound = math.sqrt(3) / 4 * (h1 * h2)[tri].min(axis=1)
            t = triangle.triangulate(dict(t, triangle_max_area=bound.reshape(-1, 1)), "rpq30Aa")
        keep = os.environ.get("EXAMPLES_KEEP")
        if keep:   # a folder where to keep the integration mesh and its field
            import shutil
            shutil.copy(vtu, os.path.join(keep, name + ".vtu"))
        import json
        j = json.loads(out.stdout)
        print("%-28s %s: estimated %.0f triangles (integration mesh: %d vertices; rounds %s); sizes [%.4g, %.4g], largest anisotropy %.1f"
              % (name, os.path.relpath(recipe, HERE), n_est, len(p), " ".join("%.0f" % x for x in history), j["smallest_size"], j["largest_size"], j["largest_anisotropy"]))


def mmg_passes(name, smartmesh, passes=4):
    """Adapts the example's start.msh to its recipe with MMG: `passes` times, the field
    of the recipe on the current mesh (`smartmesh size ... -o m.mesh`, Medit mesh and
    .sol), then `mmg2d_O3 -hgrad -1` (MMG's own gradation off: the recipe has its own).
    MMG keeps the curve and face references and the vertices where curves meet; the
    topological points are tagged again by their coordinates after each pass. A check of
    the recipe's sizes with an external remesher, until `smartmesh adapt` exists."""
    import json
    import subprocess
    import tempfile
    import time
    import meshio
    import mmgpy
    mmg = os.path.join(os.path.dirname(mmgpy.__file__), "bin", "mmg2d_O3")
    folder, build, _, _ = EXAMPLES[name]
    g = build()
    recipe = recipe_of(name)
    points = [(i, m) for i, m in enumerate(g.vmarkers) if m]
    msh = os.path.join(HERE, folder, "start.msh")
    counts = []
    with tempfile.TemporaryDirectory() as tmp:
        t0 = time.time()
        for k in range(passes):
            subprocess.run([smartmesh, "size", msh, "--recipe", recipe, "-o", os.path.join(tmp, "m.mesh")], check=True, capture_output=True)
            o = subprocess.run([mmg, "-in", os.path.join(tmp, "m.mesh"), "-sol", os.path.join(tmp, "m.sol"), "-out", os.path.join(tmp, "a.mesh"), "-v", "0", "-hgrad", "-1"], capture_output=True, text=True)
            if o.returncode != 0:
                raise SystemExit("%s: mmg2d_O3 failed: %s%s" % (name, o.stdout, o.stderr))
            m = meshio.read(os.path.join(tmp, "a.mesh"))
            tri, lines = m.cells_dict["triangle"], m.cells_dict["line"]
            tref, lref = m.cell_data_dict["medit:ref"]["triangle"], m.cell_data_dict["medit:ref"]["line"]
            p = m.points[:, :2]
            tagged = {}
            for i, tag in points:
                x, y = g.vertices[i]
                j = int(np.argmin(np.hypot(p[:, 0] - x, p[:, 1] - y)))
                if math.hypot(p[j, 0] - x, p[j, 1] - y) > 1e-8:
                    raise SystemExit("%s: mmg2d_O3 moved point %d" % (name, tag))
                tagged[j] = tag
            # Tagged points first: write_triangulation takes them as the input vertices.
            order = list(tagged) + [v for v in range(len(p)) if v not in tagged]
            inv = np.empty(len(p), dtype=int)
            inv[order] = np.arange(len(p))
            h = Geometry(g.title)
            h.names, h.region, h.vmarkers = g.names, g.region, list(tagged.values())
            msh = os.path.join(tmp, "pass%d.msh" % (k + 1))
            h.write_triangulation({"vertices": p[order], "triangles": inv[tri], "segments": inv[lines],
                                   "segment_markers": lref.reshape(-1, 1), "triangle_attributes": tref.reshape(-1, 1).astype(float)}, msh)
            counts.append(len(tri))
        elapsed = time.time() - t0
        keep = os.environ.get("EXAMPLES_KEEP")
        if keep:
            import shutil
            shutil.copy(msh, os.path.join(keep, name + "-mmg.msh"))
    print("%-28s size + mmg2d_O3, %d passes: %s triangles (%.1f s)" % (name, passes, " ".join(str(c) for c in counts), elapsed))


if __name__ == "__main__":
    gmsh.initialize(["-noenv"])
    gmsh.option.setNumber("General.Terminal", 0)
    args = sys.argv[1:]
    exe = os.environ.get("SMARTMESH", os.path.join(HERE, "..", "target", "release", "smartmesh"))
    if args[:1] == ["--estimate"]:
        for name in args[1:] or list(EXAMPLES):
            estimate(name, exe)
    elif args[:1] == ["--mmg"]:
        for name in args[1:] or list(EXAMPLES):
            mmg_passes(name, exe)
    else:
        root = HERE
        if args[:1] == ["--out"]:   # write elsewhere (the tests compare with the committed files)
            root, args = args[1], args[2:]
        for name in args or list(EXAMPLES):
            make(name, root)
    gmsh.finalize()
