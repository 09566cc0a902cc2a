"""The nearest-segment query a Python user would write for DISTANCE_TO_BORDER, timed
on the meshes of benches/sizing.rs: scipy's cKDTree over the segment midpoints, the k
nearest midpoints of every vertex, exact projection on those k segments, then the two
sizes (perpendicular and parallel distance functions) as the Rust bench computes them.

Unlike the Rust engine this is not exact: the closest segment is not always among the
k nearest midpoints (the script counts the vertices where k midpoints missed it, against
a brute-force check on a sample).

Inputs: the files `cargo bench --bench sizing` writes when SMARTMESH_BENCH_DUMP=dir is
set (points: x y pairs; segments: ax ay bx by; little-endian f64). Without them the
script rebuilds the same points from the same formula.

Run:
    SMARTMESH_BENCH_DUMP=/tmp/sizing_dump cargo bench -p smartmesh --bench sizing
    python3 benches/compare_ckdtree.py /tmp/sizing_dump
"""

import os
import sys
import time

import numpy as np
from scipy.spatial import cKDTree

CASES = [(2000, 5), (10_000, 10), (10_000, 100), (10_000, 400)]
K = 8
# Vertices per query batch: numpy's k-wide temporaries stay a few hundred MB on the
# 4·10^6-vertex mesh (the time per vertex is the same as in one batch).
CHUNK = 1 << 19
MAX_VERTICES = int(os.environ.get("SMARTMESH_BENCH_MAX_VERTICES", "4000000"))


def o_mesh(around, layers):
    a = 2.0 * np.pi * np.arange(around) / around
    rings = [1.0 + 0.1 * np.cos(5.0 * a) + j * 0.004 for j in range(layers)]
    pts = np.concatenate([np.stack([r * np.cos(a), r * np.sin(a)], axis=1) for r in rings])
    border = pts[:around]
    segs = np.concatenate([border, np.roll(border, -1, axis=0)], axis=1)
    return pts, segs


def load(folder, around, layers):
    base = os.path.join(folder, f"o_mesh_{around}x{layers}")
    if folder and os.path.exists(base + ".points.f64"):
        pts = np.fromfile(base + ".points.f64", dtype="<f8").reshape(-1, 2)
        segs = np.fromfile(base + ".segments.f64", dtype="<f8").reshape(-1, 4)
        return pts, segs
    return o_mesh(around, layers)


def graded(s0, s1, dmax, e, d):
    t = np.clip(d / dmax, 0.0, 1.0)
    return s0 + t**e * (s1 - s0)


def nearest_segment(pts, segs, tree, k):
    _, idx = tree.query(pts, k=k, workers=1)
    a = segs[idx, 0:2]
    b = segs[idx, 2:4]
    ab = b - a
    ap = pts[:, None, :] - a
    t = np.clip(np.einsum("nkj,nkj->nk", ap, ab) / np.einsum("nkj,nkj->nk", ab, ab), 0.0, 1.0)
    foot = a + t[..., None] * ab
    d2 = np.einsum("nkj,nkj->nk", pts[:, None, :] - foot, pts[:, None, :] - foot)
    best = np.argmin(d2, axis=1)
    rows = np.arange(len(pts))
    return np.sqrt(d2[rows, best]), foot[rows, best], idx[rows, best]


def brute(p, segs):
    a, b = segs[:, 0:2], segs[:, 2:4]
    ab = b - a
    t = np.clip(((p - a) * ab).sum(1) / (ab * ab).sum(1), 0.0, 1.0)
    foot = a + t[:, None] * ab
    return np.sqrt(((p - foot) ** 2).sum(1)).min()


def main():
    folder = sys.argv[1] if len(sys.argv) > 1 else ""
    rng = np.random.default_rng(1)
    for around, layers in CASES:
        if around * layers > MAX_VERTICES:
            continue
        pts, segs = load(folder, around, layers)
        n = len(pts)
        best = float("inf")
        best_wall = float("inf")
        for _ in range(3):
            # CPU time of the process, as the Rust bench's single-thread figures (the
            # machine is shared); wall time beside it.
            start, start_wall = time.process_time(), time.perf_counter()
            mid = 0.5 * (segs[:, 0:2] + segs[:, 2:4])
            tree = cKDTree(mid)
            parts = [nearest_segment(pts[i : i + CHUNK], segs, tree, K) for i in range(0, n, CHUNK)]
            d = np.concatenate([p[0] for p in parts])
            foot = np.concatenate([p[1] for p in parts])
            del parts
            normal = pts - foot
            norm = np.hypot(normal[:, 0], normal[:, 1])
            normal = normal / np.where(norm > 0, norm, 1.0)[:, None]
            h_perp = graded(0.001, 0.1, 1.0, 1.5, d)
            h_par = graded(0.01, 0.2, 1.0, 1.0, d)
            best = min(best, time.process_time() - start)
            best_wall = min(best_wall, time.perf_counter() - start_wall)
        sample = rng.choice(n, size=min(n, 2000), replace=False)
        missed = sum(abs(brute(pts[i], segs) - d[i]) > 1e-12 * max(d[i], 1e-300) for i in sample)
        print(
            f"o_mesh {around}x{layers}: {n} vertices, {len(segs)} segments, k = {K}: "
            f"{best * 1e3:.1f} ms CPU ({best_wall * 1e3:.1f} ms wall), {n / best / 1e6:.2f} M vertex evaluations/s per core (1 thread); "
            f"closest segment missed on {missed} of {len(sample)} sampled vertices"
        )
        del h_perp, h_par


if __name__ == "__main__":
    main()
