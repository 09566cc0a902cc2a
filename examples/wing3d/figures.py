#!/usr/bin/env python3
"""The figures of the wing3d example from its run (run.sh leaves them in RUN_DIR):

- per iteration, from the loop's history (adapted.history.json): vertices, tetrahedra,
  boundary triangles, the UGAWG measures of the mesh against the recipe's field on it
  (share of edges of metric length in [1/sqrt 2, sqrt 2], shortest and longest metric
  length, least and mean mean-ratio quality), the seconds of sizing, remeshing
  (mmg3d_O3) and measuring;
- the best mesh's UGAWG line as `smartmesh info --metric --json` prints it (info.json);
- the wall: on every Wing triangle of the best mesh (adapted.vtu), the height of its
  tetrahedron over it (the first cell's size across the wall) against the size the
  field asks along the triangle's normal there, 1 / sqrt(n^T M n) with M the arithmetic
  mean of its three corners' metrics.

    python3 examples/wing3d/figures.py RUN_DIR            # the Markdown README prints
    python3 examples/wing3d/figures.py RUN_DIR --wall     # the wall figures as JSON

Needs numpy and meshio.
"""
import json
import os
import sys

import meshio
import numpy as np


WING = 1  # the physical tag of the surface Wing (geometry.py)


def wall(mesh_path):
    """Heights of the tetrahedra on the Wing triangles and the sizes asked across them,
    on the best mesh as a .vtu (`smartmesh convert adapted.msh adapted.vtu`: meshio 5.3
    reads the points of an MSH 4.1 file in block order but its $NodeData in tag order,
    which differ)."""
    m = meshio.read(mesh_path)
    wing = WING
    tris, tets = [], []
    for block, phys in zip(m.cells, m.cell_data["gmsh:physical"]):
        if block.type == "triangle":
            tris.append(block.data[phys == wing])
        elif block.type == "tetra":
            tets.append(block.data)
    tris, tets = np.concatenate(tris), np.concatenate(tets)
    # Each face of a tetrahedron (its sorted corners) -> the corner off it.
    face_of = {}
    for t in tets:
        for k in range(4):
            f = tuple(sorted(np.delete(t, k)))
            face_of.setdefault(f, []).append(t[k])
    p = m.points
    metric = m.point_data["metric"].reshape(-1, 3, 3)
    heights, asked = [], []
    for tri in tris:
        opposite = face_of.get(tuple(sorted(tri)))
        if opposite is None or len(opposite) != 1:
            raise SystemExit(f"{mesh_path}: wing triangle {tri} is not the face of one tetrahedron")
        a, b, c = p[tri]
        n = np.cross(b - a, c - a)
        n /= np.linalg.norm(n)
        heights.append(abs(np.dot(p[opposite[0]] - a, n)))
        mm = metric[tri].mean(axis=0)
        asked.append(1.0 / np.sqrt(n @ mm @ n))
    h, s = np.array(heights), np.array(asked)
    r = h / s
    q = lambda x, f: float(np.quantile(x, f))
    return {
        "triangles": len(h),
        "height": {"min": float(h.min()), "p10": q(h, 0.1), "median": q(h, 0.5), "p90": q(h, 0.9)},
        "asked": {"min": float(s.min()), "median": q(s, 0.5), "max": float(s.max())},
        "ratio": {"p10": q(r, 0.1), "median": q(r, 0.5), "p90": q(r, 0.9)},
    }


def main(argv):
    run = argv[1]
    if len(argv) > 2 and argv[2] == "--wall":
        print(json.dumps(wall(os.path.join(run, "adapted.vtu")), indent=1))
        return
    h = json.load(open(os.path.join(run, "adapted.history.json")))
    info = json.load(open(os.path.join(run, "info.json")))["metric"]["ugawg"]
    w = wall(os.path.join(run, "adapted.vtu"))
    print("| iteration | vertices | tetrahedra | boundary triangles | edges in [1/√2, √2] "
          "| length min | length max | mean ratio min | mean ratio mean | s size | s mmg3d | s measure |")
    print("|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for r in h["iterations"]:
        sp, sec = r["space"], r["seconds"]
        lo, hi = sp["edge_length_range"]
        best = " (best)" if r["iteration"] == h["best_iteration"] else ""
        print(f"| {r['iteration']}{best} | {r['vertices']} | {sp['cells']} | {r['triangles']} | "
              f"{100 * r['conforming_share']:.1f} % | {lo:.3f} | {hi:.2f} | "
              f"{r['min_quality']:.3f} | {r['mean_quality']:.3f} | {sec['size']:.1f} | "
              f"{sec['remesh']:.1f} | {sec['measure']:.1f} |")
    end = "converged" if h["converged"] else h["stopped"]
    print(f"\nStopped: {end}; the best mesh is iteration {h['best_iteration']}.\n")
    lo, hi = info["edge_length_range"]
    print("`smartmesh info adapted.msh --metric`: "
          f"{info['edges']} edges, {100 * info['conforming_share']:.1f} % of metric length in "
          f"[1/√2, √2], lengths {lo:.3f} to {hi:.2f} (geometric mean "
          f"{info['geometric_mean_edge_length']:.3f}); {info['cells']} tetrahedra, mean ratio "
          f"{info['min_quality']:.3f} min, {info['mean_quality']:.3f} mean, "
          f"{info['non_positive']} of non-positive volume.\n")
    ht, a, ra = w["height"], w["asked"], w["ratio"]
    print(f"Wall: on the {w['triangles']} Wing triangles, the first tetrahedron's height across "
          f"the wall is {ht['median']:.4f} (median; 10 % below {ht['p10']:.4f}, 90 % below "
          f"{ht['p90']:.4f}, least {ht['min']:.4f}) where the field asks {a['median']:.4f} "
          f"(median; {a['min']:.4f} to {a['max']:.4f}): height / asked {ra['median']:.2f} "
          f"(median; 10 % below {ra['p10']:.2f}, 90 % below {ra['p90']:.2f}).")


if __name__ == "__main__":
    main(sys.argv)
