#!/usr/bin/env python3
"""smartmesh remesh against MMG's mmg2d_O3 on the same input mesh and metric.

The input is the bundled cylinder (fixtures/cylinder.msh) with the metric of its recipe
(fixtures/cylinder.toml), written by `smartmesh size` as a Medit .mesh + .sol, then scaled
by a factor s (every metric tensor times s, so every size divided by sqrt(s)) so that the
adapted meshes have about 10^4, 10^5, 10^6 triangles. Both tools read the same files:

    smartmesh remesh in.mesh -o ours.mesh --json           (the metric is in.sol)
    mmg2d_O3 in.mesh -sol in.sol -out mmg.mesh -hgrad -1 -hausd 10 -v -1

MMG options: `-hgrad -1` switches off MMG's gradation so that it adapts to the metric as
given (smartmesh never alters the metric); `-hausd 10` switches off its geometric
refinement of curved boundaries (smartmesh has none; MMG's default 0.01 adds boundary
points the metric does not ask for). MMG keeps its default smooth boundary reconstruction;
smartmesh runs with its default boundary placement (`--boundary smooth` since 2026-12-06,
`polyline` before; --smooth adds a run with `--boundary smooth` named). MMG is timed through its real executable (the one in the mmgpy package's bin/
folder), not the Python wrapper on PATH.

Both outputs are measured by the same code, `smartmesh remesh OUT --measure --json`:
against the metric each tool wrote (its .sol), and against the input field interpolated at
the output's vertices (`--background in.mesh`), which is the same yardstick for both.

    python3 benches/compare_mmg.py                      # 1e4 1e5 1e6
    python3 benches/compare_mmg.py --sizes 1e4,1e5 --repeat 3

Coarse inputs with strongly anisotropic metrics (`--coarse`, sizes 1e4,1e5 unless
--sizes): a boundary layer (across 0.0005 at the wall to 0.05 at distance 0.2, along
0.05: aspect ratio up to 100) and a shock band (across 0.001 on an oblique line to 0.05
at distance 0.05, along 0.05), each on the unit square (the layer on its bottom side) and
on the unit square with a hole of radius 0.15 in its middle (the layer around the hole,
the shock crossing beside it). The input is the coarse mesh `smartmesh mesh --size 0.1`
makes of each (about 250 triangles), the metric evaluated at its vertices only, so the
remeshers interpolate it from a few vertices. Each tool runs under `/usr/bin/time -v`
(peak resident memory), the tools alternating, `--repeat` times each; the median time
is kept.

    python3 benches/compare_mmg.py --coarse --sizes 1e4,1e5 --repeat 3
    python3 benches/compare_mmg.py --coarse --sizes 1e6 --one-thread
"""

import math

import argparse
import json
import os
import shutil
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def real_mmg():
    try:
        import mmgpy  # noqa: F401

        p = Path(mmgpy.__file__).parent / "bin" / "mmg2d_O3"
        if p.exists():
            return str(p)
    except ImportError:
        pass
    return shutil.which("mmg2d_O3")


def run(cmd):
    t = time.perf_counter()
    r = subprocess.run(cmd, capture_output=True, text=True)
    dt = time.perf_counter() - t
    if r.returncode != 0:
        sys.exit(f"failed ({r.returncode}): {' '.join(cmd)}\n{r.stdout[-2000:]}\n{r.stderr[-2000:]}")
    return dt, r.stdout


def scale_sol(src, dst, s):
    lines = Path(src).read_text().splitlines()
    out = []
    i = 0
    # Header up to the "1 3" type line, then one tensor per line until End.
    while i < len(lines):
        out.append(lines[i])
        if lines[i].strip() == "1 3":
            i += 1
            break
        i += 1
    for line in lines[i:]:
        parts = line.split()
        if len(parts) == 3:
            out.append(" ".join(repr(float(x) * s) for x in parts))
        else:
            out.append(line)
    Path(dst).write_text("\n".join(out) + "\n")


def measure(sm, mesh, background=None):
    cmd = [sm, "remesh", str(mesh), "--measure", "--json"]
    if background:
        cmd += ["--background", str(background)]
    _, out = run(cmd)
    c = json.loads(out)
    return {k: c[k] for k in ("triangles", "edges", "conforming_share", "mean_quality", "min_quality")}


def coarse_polys(work):
    """The unit square (corners 1-4, sides 11-14, face 100) and the same with a hole of
    radius 0.15 about (0.5, 0.5) (curve 15), as Triangle .poly files."""
    n = 10
    pts = [(k / n, 0.0) for k in range(n)] + [(1.0, k / n) for k in range(n)] + [(1 - k / n, 1.0) for k in range(n)] + [(0.0, 1 - k / n) for k in range(n)]
    marks = [1 if i == 0 else 2 if i == n else 3 if i == 2 * n else 4 if i == 3 * n else 0 for i in range(4 * n)]
    segs = [(i, (i + 1) % (4 * n), 11 + i // n) for i in range(4 * n)]
    out = {}
    for name, hole in (("square", False), ("holed", True)):
        v, m, sg = list(pts), list(marks), list(segs)
        holes = []
        if hole:
            base, k = len(v), 32
            v += [(0.5 + 0.15 * math.cos(2 * math.pi * j / k), 0.5 + 0.15 * math.sin(2 * math.pi * j / k)) for j in range(k)]
            m += [5] + [0] * (k - 1)
            sg += [(base + j, base + (j + 1) % k, 15) for j in range(k)]
            holes = [(0.5, 0.5)]
        lines = ["%d 2 0 1" % len(v)] + ["%d %.17g %.17g %d" % (i + 1, x, y, mk) for i, ((x, y), mk) in enumerate(zip(v, m))]
        lines += ["%d 1" % len(sg)] + ["%d %d %d %d" % (i + 1, a + 1, b + 1, t) for i, (a, b, t) in enumerate(sg)]
        lines += ["%d" % len(holes)] + ["%d %g %g" % (i + 1, x, y) for i, (x, y) in enumerate(holes)]
        lines += ["1", "1 0.05 0.05 100 -1"]
        path = work / f"{name}.poly"
        path.write_text("\n".join(lines) + "\n")
        out[name] = path
    return out


def coarse_metric(case, domain, x, y):
    """(m11, m12, m22) of a case at (x, y): sizes across and along a source."""
    if case == "layer":
        if domain == "square":
            d, nx, ny = y, 0.0, 1.0
        else:
            r = math.hypot(x - 0.5, y - 0.5)
            d, nx, ny = max(r - 0.15, 0.0), (x - 0.5) / max(r, 1e-12), (y - 0.5) / max(r, 1e-12)
        h0, hmax, delta = 0.0005, 0.05, 0.2
    else:
        # The line x = 0.25 + 0.3 y; its unit normal.
        l = math.hypot(1.0, 0.3)
        nx, ny = 1.0 / l, -0.3 / l
        d = abs((x - 0.25 - 0.3 * y) / l)
        h0, hmax, delta = 0.001, 0.05, 0.05
    hn = h0 + (hmax - h0) * min(1.0, d / delta)
    ht = hmax
    a, b = 1 / (hn * hn), 1 / (ht * ht)
    # M = a n n^T + b t t^T, t = (-ny, nx).
    return (a * nx * nx + b * ny * ny, (a - b) * nx * ny, a * ny * ny + b * nx * nx)


def write_sol(mesh_path, sol_path, case, domain, scale):
    """A Medit .sol (type 3) of the case's metric times `scale` at the vertices of the
    Medit mesh `mesh_path`."""
    lines = Path(mesh_path).read_text().split("\n")
    i = next(k for k, l in enumerate(lines) if l.strip() == "Vertices")
    n = int(lines[i + 1])
    out = ["MeshVersionFormatted 2", "", "Dimension 2", "", "SolAtVertices", str(n), "1 3"]
    for l in lines[i + 2:i + 2 + n]:
        x, y = (float(t) for t in l.split()[:2])
        out.append(" ".join(repr(c * scale) for c in coarse_metric(case, domain, x, y)))
    out += ["", "End"]
    Path(sol_path).write_text("\n".join(out) + "\n")


def timed_memory(cmd):
    """Wall seconds and peak resident memory (MB) of a command under /usr/bin/time -v."""
    t = time.perf_counter()
    r = subprocess.run(["/usr/bin/time", "-v"] + cmd, capture_output=True, text=True)
    dt = time.perf_counter() - t
    if r.returncode != 0:
        sys.exit(f"failed ({r.returncode}): {' '.join(cmd)}\n{r.stdout[-2000:]}\n{r.stderr[-2000:]}")
    kb = next(int(l.split(":")[1]) for l in r.stderr.splitlines() if "Maximum resident set size" in l)
    return dt, kb / 1024.0


def coarse(a, sm, work):
    import statistics
    polys = coarse_polys(work)
    results = []
    for domain, poly in polys.items():
        base = work / f"{domain}.mesh"
        run([sm, "mesh", str(poly), "-o", str(base), "--size", "0.1", "-q"])
        for case in ("layer", "shock"):
            # Calibration: MMG's triangle count at scale 1.
            write_sol(base, work / f"{domain}.sol", case, domain, 1.0)
            run([a.mmg, str(base), "-sol", str(work / f"{domain}.sol"), "-out", str(work / "calib.mesh"), "-hgrad", "-1", "-hausd", "10", "-v", "-1"])
            n1 = measure(sm, work / "calib.mesh")["triangles"]
            for target in [float(x) for x in a.sizes.split(",")]:
                s = target / n1
                tag = f"{domain}-{case}-{int(target):d}"
                inp = work / f"in-{tag}.mesh"
                shutil.copy(base, inp)
                write_sol(base, inp.with_suffix(".sol"), case, domain, s)
                tools = [
                    ("smartmesh", lambda out: [sm, "remesh", str(inp), "-o", str(out)]),
                ] + ([("smartmesh, 1 thread", lambda out: [sm, "remesh", str(inp), "-o", str(out), "--threads", "1"])] if a.one_thread else []) + [
                    ("mmg2d_O3", lambda out: [a.mmg, str(inp), "-sol", str(inp.with_suffix(".sol")), "-out", str(out), "-hgrad", "-1", "-hausd", "10", "-v", "-1"]),
                ]
                runs = {name: [] for name, _ in tools}
                # A tool's output file: its name with the spaces and commas made dashes.
                out_of = {name: work / f"{name.replace(', ', '-').replace(' ', '-')}-{tag}.mesh" for name, _ in tools}
                for _ in range(a.repeat):
                    for name, cmd in tools:
                        runs[name].append(timed_memory(cmd(out_of[name])))
                for name, _ in tools:
                    out = out_of[name]
                    own = measure(sm, out)
                    bg = measure(sm, out, background=inp)
                    r = {"domain": domain, "case": case, "target": int(target), "tool": name,
                         "seconds": statistics.median(x[0] for x in runs[name]), "all_seconds": [x[0] for x in runs[name]],
                         "peak_mb": max(x[1] for x in runs[name]), "own_sol": own, "input_field": bg}
                    results.append(r)
                    print(json.dumps(r), file=sys.stderr, flush=True)
    print("| case | target | tool | triangles | time vs MMG | wall s (median) | in band (input field) | mean q | min q | peak MB | MB per 10^6 triangles |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for r in results:
        mmg = next(x for x in results if x["tool"] == "mmg2d_O3" and (x["domain"], x["case"], x["target"]) == (r["domain"], r["case"], r["target"]))
        b = r["input_field"]
        ratio = "1" if r["tool"] == "mmg2d_O3" else "%.2fx" % (r["seconds"] / mmg["seconds"])
        print(f"| {r['case']} on {r['domain']} | {r['target']:.0e} | {r['tool']} | {b['triangles']} | {ratio} | {r['seconds']:.2f} | "
              f"{b['conforming_share']:.4f} | {b['mean_quality']:.4f} | {b['min_quality']:.4f} | {r['peak_mb']:.0f} | {r['peak_mb'] / b['triangles'] * 1e6:.0f} |")
    (work / "coarse-results.json").write_text(json.dumps(results, indent=1))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--sizes", default="1e4,1e5,1e6", help="target output triangle counts")
    ap.add_argument("--work", default=str(ROOT / "target" / "compare-mmg"))
    ap.add_argument("--smartmesh", default=str(ROOT / "target" / "release" / "smartmesh"))
    ap.add_argument("--mmg", default=real_mmg())
    ap.add_argument("--repeat", type=int, default=1, help="runs per tool and size (best time kept)")
    ap.add_argument("--smooth", action="store_true", help="also run smartmesh --boundary smooth")
    ap.add_argument("--coarse", action="store_true", help="the coarse anisotropic cases instead (see above)")
    ap.add_argument("--one-thread", action="store_true", help="coarse cases: also run smartmesh with --threads 1 (it uses every core by default; mmg2d_O3 uses one)")
    a = ap.parse_args()
    if not a.mmg:
        sys.exit("mmg2d_O3 not found (pip install mmgpy)")
    work = Path(a.work)
    work.mkdir(parents=True, exist_ok=True)
    sm = a.smartmesh
    if a.coarse:
        if a.sizes == "1e4,1e5,1e6" and "--sizes" not in sys.argv:
            a.sizes = "1e4,1e5"
        return coarse(a, sm, work)
    run([sm, "size", str(ROOT / "fixtures" / "cylinder.msh"), "--recipe", str(ROOT / "fixtures" / "cylinder.toml"), "-o", str(work / "base.mesh")])
    # Calibration: MMG's triangle count at s = 1.
    run([a.mmg, str(work / "base.mesh"), "-sol", str(work / "base.sol"), "-out", str(work / "calib.mesh"), "-hgrad", "-1", "-hausd", "10", "-v", "-1"])
    n1 = measure(sm, work / "calib.mesh")["triangles"]
    results = []
    for target in [float(x) for x in a.sizes.split(",")]:
        s = target / n1
        tag = f"{int(target):d}"
        inp = work / f"in{tag}.mesh"
        shutil.copy(work / "base.mesh", inp)
        scale_sol(work / "base.sol", inp.with_suffix(".sol"), s)
        tools = [("smartmesh", lambda out: [sm, "remesh", str(inp), "-o", str(out)])]
        if a.smooth:
            tools.append(("smartmesh smooth", lambda out: [sm, "remesh", str(inp), "-o", str(out), "--boundary", "smooth"]))
        tools.append(("mmg2d_O3", lambda out: [a.mmg, str(inp), "-sol", str(inp.with_suffix(".sol")), "-out", str(out), "-hgrad", "-1", "-hausd", "10", "-v", "-1"]))
        for name, cmd in tools:
            out = work / f"{name.replace(' ', '_')}{tag}.mesh"
            best = min(run(cmd(out))[0] for _ in range(a.repeat))
            own = measure(sm, out)
            bg = measure(sm, out, background=inp)
            r = {"target": int(target), "scale": s, "tool": name, "seconds": best, "own_sol": own, "input_field": bg}
            results.append(r)
            print(json.dumps(r), file=sys.stderr, flush=True)
    print("| target | tool | triangles | wall (s) | in band (own .sol) | mean q | min q | in band (input field) | mean q | min q |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for r in results:
        o, b = r["own_sol"], r["input_field"]
        print(
            f"| {r['target']:.0e} | {r['tool']} | {o['triangles']} | {r['seconds']:.2f} | {o['conforming_share']:.4f} | {o['mean_quality']:.4f} | "
            f"{o['min_quality']:.4f} | {b['conforming_share']:.4f} | {b['mean_quality']:.4f} | {b['min_quality']:.4f} |"
        )
    (work / "results.json").write_text(json.dumps(results, indent=1))


if __name__ == "__main__":
    main()
