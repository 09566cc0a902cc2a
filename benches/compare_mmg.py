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
smartmesh runs with its default `--boundary polyline` (and `--boundary smooth` with
--smooth). MMG is timed through its real executable (the one in the mmgpy package's bin/
folder), not the Python wrapper on PATH.

Both outputs are measured by the same code, `smartmesh remesh OUT --measure --json`:
against the metric each tool wrote (its .sol), and against the input field interpolated at
the output's vertices (`--background in.mesh`), which is the same yardstick for both.

    python3 benches/compare_mmg.py                      # 1e4 1e5 1e6
    python3 benches/compare_mmg.py --sizes 1e4,1e5 --repeat 3
"""

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


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--sizes", default="1e4,1e5,1e6", help="target output triangle counts")
    ap.add_argument("--work", default=str(ROOT / "target" / "compare-mmg"))
    ap.add_argument("--smartmesh", default=str(ROOT / "target" / "release" / "smartmesh"))
    ap.add_argument("--mmg", default=real_mmg())
    ap.add_argument("--repeat", type=int, default=1, help="runs per tool and size (best time kept)")
    ap.add_argument("--smooth", action="store_true", help="also run smartmesh --boundary smooth")
    a = ap.parse_args()
    if not a.mmg:
        sys.exit("mmg2d_O3 not found (pip install mmgpy)")
    work = Path(a.work)
    work.mkdir(parents=True, exist_ok=True)
    sm = a.smartmesh
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
