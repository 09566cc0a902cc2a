"""The vertex budget of `adapt --complexity N` on every example and on the geometric
recipes of benches/solution_error.py: the final mesh (the history's best iteration) must
have N vertices within 5 %. Each case runs at two budgets, a quarter and twice the
vertex count the recipe gives alone (so the recipe's field is both coarsened and refined,
its hmin/hmax and gradation acting inside the scaling).

    python3 benches/budget.py [--smartmesh target/release/smartmesh] [--only NAME,...]
        [--counts quarter,twice] [--coarsen-geometry]

--counts picks the budgets (default both); --coarsen-geometry passes it to every budgeted
run (a .poly's vertices may then be removed). The "warned" column says whether smartmesh
warned before the loop that the .poly's kept vertices alone exceed the budget.

Prints one row per case and budget, and exits 1 if any is off by more than 5 %.
"""

import argparse
import glob
import json
import os
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)
import solution_error  # noqa: E402  (its square and recipes)


def cases(work):
    for poly in sorted(glob.glob(os.path.join(ROOT, "examples", "**", "geometry.poly"), recursive=True)):
        d = os.path.dirname(poly)
        recipe = (glob.glob(os.path.join(d, "recipe.*")) or glob.glob(os.path.join(os.path.dirname(d), "recipe.*")))
        if recipe:
            yield os.path.relpath(d, os.path.join(ROOT, "examples")), poly, recipe[0]
    square = os.path.join(work, "square.poly")
    with open(square, "w") as f:
        f.write(solution_error.SQUARE_POLY)
    for name, text in solution_error.RECIPES.items():
        r = os.path.join(work, f"{name}.toml")
        with open(r, "w") as f:
            f.write(text)
        yield f"solution_error/{name}", square, r


def adapt(sm, poly, recipe, out, extra):
    t = time.time()
    r = subprocess.run([sm, "adapt", poly, "--recipe", recipe, "-o", out, *extra], capture_output=True, text=True)
    if r.returncode not in (0,):
        return None, r.stderr.strip().splitlines()[-1:], time.time() - t
    h = json.load(open(out.replace(".vtu", ".history.json")))
    h["warned"] = "cannot hold" in r.stderr
    return h, None, time.time() - t


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--smartmesh", default=os.path.join(ROOT, "target/release/smartmesh"))
    ap.add_argument("--only", default="")
    ap.add_argument("--counts", default="quarter,twice")
    ap.add_argument("--coarsen-geometry", action="store_true")
    args = ap.parse_args()
    only = [s for s in args.only.split(",") if s]
    bad = 0
    counts = args.counts.split(",")
    extra = ["--coarsen-geometry"] if args.coarsen_geometry else []
    print("| case | recipe alone | N | final vertices | off | iterations | seconds | warned |")
    print("|---|---|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as work:
        for name, poly, recipe in cases(work):
            if only and not any(o in name for o in only):
                continue
            tag = name.replace("/", "-")
            h, err, _ = adapt(args.smartmesh, poly, recipe, os.path.join(work, f"{tag}.vtu"), [])
            if h is None:
                print(f"| {name} | failed: {err} | | | | | |")
                bad += 1
                continue
            own = h["iterations"][h["best_iteration"]]["vertices"]
            budgets = {"quarter": max(200, own // 4), "twice": 2 * own}
            for n in [budgets[c] for c in counts]:
                h, err, secs = adapt(args.smartmesh, poly, recipe, os.path.join(work, f"{tag}-{n}.vtu"),
                                     ["--complexity", str(n), *extra])
                if h is None:
                    print(f"| {name} | {own} | {n} | failed: {err} | | | |")
                    bad += 1
                    continue
                v = h["iterations"][h["best_iteration"]]["vertices"]
                off = v / n - 1
                bad += abs(off) > 0.05
                warned = "yes" if h["warned"] else ""
                print(f"| {name} | {own} | {n} | {v} | {100 * off:+.1f}% | {len(h['iterations']) - 1} | {secs:.1f} | {warned} |", flush=True)
    sys.exit(1 if bad else 0)


if __name__ == "__main__":
    main()
