"""Times Shewchuk's Triangle (PyPI `triangle`) on the graph that benches/mesher.rs
meshes, with the same switches: minimum angle 30 and the same area bounds (`pq30Aa<area>a`),
and prints count, smallest angle, mean quality (4*sqrt(3)*area / sum of squared edges, as
benches/mesher.rs) and the best of three times.

Run after `cargo bench -p smartmesh --bench mesher` (which writes the .poly):
    python3 benches/compare_triangle.py target/bench-meshes/mesher-naca256.poly
    python3 benches/compare_triangle.py fixtures/square_hole.poly 0.000001
Area bounds after the file replace the default ones. `A` and a bare `a` make Triangle
honour regional attributes and regional area bounds, as smartmesh always does.
"""
import math
import sys
import time

import numpy as np
import triangle

AREAS = ["0.002", "0.0002", "0.00002"]  # Triangle wants plain decimals


def read_poly(path):
    rows = [l.split("#")[0].split() for l in open(path)]
    rows = [r for r in rows if r]
    i = 0
    nv = int(rows[i][0]); i += 1
    base = int(rows[i][0])
    verts = [[float(r[1]), float(r[2])] for r in rows[i:i + nv]]; i += nv
    ns = int(rows[i][0]); i += 1
    segs = [[int(r[1]) - base, int(r[2]) - base] for r in rows[i:i + ns]]
    marks = [int(r[3]) if len(r) > 3 else 0 for r in rows[i:i + ns]]; i += ns
    nh = int(rows[i][0]); i += 1
    holes = [[float(r[1]), float(r[2])] for r in rows[i:i + nh]]; i += nh
    regions = []
    if i < len(rows):
        nr = int(rows[i][0]); i += 1
        regions = [[float(x) for x in r[1:5]] for r in rows[i:i + nr]]
    d = dict(vertices=np.array(verts), segments=np.array(segs), segment_markers=np.array(marks))
    if holes:
        d["holes"] = np.array(holes)
    if regions:
        d["regions"] = np.array(regions)
    return d


def stats(t):
    v, tri = t["vertices"], t["triangles"]
    a, b, c = v[tri[:, 0]], v[tri[:, 1]], v[tri[:, 2]]
    def ang(p, q, r):
        u, w = q - p, r - p
        return np.degrees(np.arctan2(np.abs(u[:, 0] * w[:, 1] - u[:, 1] * w[:, 0]), (u * w).sum(1)))
    amin = np.minimum(np.minimum(ang(a, b, c), ang(b, c, a)), ang(c, a, b)).min()
    area = 0.5 * ((b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0]))
    s = ((a - b) ** 2).sum(1) + ((b - c) ** 2).sum(1) + ((c - a) ** 2).sum(1)
    return len(tri), amin, float((4 * math.sqrt(3) * area / s).mean())


def main():
    d = read_poly(sys.argv[1])
    print("| area bound | Triangle triangles | smallest angle | mean quality | time (s) | triangles/s |")
    print("|---|---|---|---|---|---|")
    for a in sys.argv[2:] or AREAS:
        best = math.inf
        for _ in range(3):
            t0 = time.perf_counter()
            t = triangle.triangulate(d, "pq30Aa" + a + "a")
            best = min(best, time.perf_counter() - t0)
        n, amin, q = stats(t)
        print(f"| {a} | {n} | {amin:.3f} | {q:.4f} | {best:.3f} | {n / best:,.0f} |")


if __name__ == "__main__":
    main()
