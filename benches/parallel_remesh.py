#!/usr/bin/env python3
"""The partitioned remesher on 1 and on 2 threads, and the serial remesher, on one large mesh.

The input is the bundled cylinder (fixtures/cylinder.msh) with the metric of its recipe
(fixtures/cylinder.toml), written by `smartmesh size` as a Medit .mesh + .sol and scaled
(every tensor times s) so that the output has about the target triangle count, as
benches/compare_mmg.py does; s is calibrated by one serial remeshing at s = 10.

For each target size the runs alternate, `--repeat` times each:

    smartmesh remesh in.mesh -o t1.mesh --threads 1
    smartmesh remesh in.mesh -o t2.mesh --threads 2

each under /usr/bin/time -v (wall seconds, peak resident memory); the speed-up is the
median of the pair-by-pair ratios. On a machine other jobs load, the 2-thread run may not
get two cores: the "modelled on 2" column replays the 1-thread run's own per-part and
driver seconds (its `--json` `partitioned` times) on two workers, parts taken in order
by the first free one. The two outputs must be byte-identical (checked with
SHA-256, the script stops otherwise). Unless --no-serial, `--no-partition` (the serial
remesher) runs once beside them. Every output is measured by `smartmesh remesh OUT
--measure --json --background in.mesh`: edges in [1/sqrt 2, sqrt 2] and metric quality
against the input field.

    cargo build --release
    python3 benches/parallel_remesh.py --sizes 1e6 --repeat 3
    python3 benches/parallel_remesh.py --sizes 1e7 --repeat 1 --no-serial
"""

import argparse
import hashlib
import json
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "benches"))
from compare_mmg import scale_sol  # noqa: E402


def run(cmd):
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"failed ({r.returncode}): {' '.join(cmd)}\n{r.stdout[-2000:]}\n{r.stderr[-2000:]}")
    return r.stdout


def timed(cmd):
    """Wall seconds and peak resident memory (MB) under /usr/bin/time -v."""
    t = time.perf_counter()
    r = subprocess.run(["/usr/bin/time", "-v"] + cmd, capture_output=True, text=True)
    dt = time.perf_counter() - t
    if r.returncode != 0:
        sys.exit(f"failed ({r.returncode}): {' '.join(cmd)}\n{r.stderr[-3000:]}")
    kb = next(int(l.split(":")[1]) for l in r.stderr.splitlines() if "Maximum resident set size" in l)
    cpu = next(l.split(":")[1].strip() for l in r.stderr.splitlines() if "Percent of CPU" in l)
    print(f"  cpu {cpu}", file=sys.stderr, flush=True)
    return dt, kb / 1024.0, r.stdout


def sha(path):
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def measure(sm, mesh, background):
    c = json.loads(run([sm, "remesh", str(mesh), "--measure", "--json", "--background", str(background)]))
    return {k: c[k] for k in ("triangles", "conforming_share", "mean_quality", "min_quality")}


def modelled_speedup(stats, workers=2):
    """The 1-thread run's own times replayed on `workers`: per pass, the driver's seconds
    plus the parts list-scheduled in part order on the first free worker, as rayon's
    queue takes them; the whole run's seconds over that."""
    one = many = 0.0
    for p in stats.get("partitioned", []):
        free = [0.0] * workers
        for s in p["part_seconds"]:
            i = free.index(min(free))
            free[i] += s
        one += p["seconds"]
        many += p["driver_seconds"] + max(free)
    return one / many if many > 0 else float("nan")


def load():
    return open("/proc/loadavg").read().split()[0]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--sizes", default="1e6", help="target output triangle counts")
    ap.add_argument("--repeat", type=int, default=3, help="runs per thread count (alternating)")
    ap.add_argument("--no-serial", action="store_true", help="skip the serial remesher's run")
    ap.add_argument("--work", default=str(ROOT / "target" / "parallel-remesh"))
    ap.add_argument("--smartmesh", default=str(ROOT / "target" / "release" / "smartmesh"))
    a = ap.parse_args()
    sm = a.smartmesh
    work = Path(a.work)
    work.mkdir(parents=True, exist_ok=True)
    base = work / "base.mesh"
    run([sm, "size", str(ROOT / "fixtures" / "cylinder.msh"), "--recipe", str(ROOT / "fixtures" / "cylinder.toml"), "-o", str(base)])
    calib = work / "calib.mesh"
    (work / "calib.mesh").write_bytes(base.read_bytes())
    scale_sol(base.with_suffix(".sol"), calib.with_suffix(".sol"), 10.0)
    n10 = json.loads(run([sm, "remesh", str(calib), "-o", str(work / "calib-out.mesh"), "--json"]))["output"]["triangles"]
    rows = []
    for target in [float(x) for x in a.sizes.split(",")]:
        tag = f"{target:.0e}".replace("+0", "")
        inp = work / f"in{tag}.mesh"
        inp.write_bytes(base.read_bytes())
        scale_sol(base.with_suffix(".sol"), inp.with_suffix(".sol"), 10.0 * target / n10)
        common = [sm, "remesh", str(inp), "--json", "--max-vertices", str(int(target))]
        times = {1: [], 2: []}
        models = []
        peaks = {1: [], 2: []}
        print(f"{tag}: load {load()} at start", file=sys.stderr, flush=True)
        for _ in range(a.repeat):
            for threads in (1, 2):
                out = work / f"t{threads}-{tag}.mesh"
                dt, mb, stdout = timed(common + ["-o", str(out), "--threads", str(threads)])
                if threads == 1:
                    models.append(modelled_speedup(json.loads(stdout)))
                times[threads].append(dt)
                peaks[threads].append(mb)
                print(f"{tag} threads {threads}: {dt:.2f} s, {mb:.0f} MB, load {load()}", file=sys.stderr, flush=True)
        same = sha(work / f"t1-{tag}.mesh") == sha(work / f"t2-{tag}.mesh")
        if not same:
            sys.exit(f"{tag}: the outputs of 1 and 2 threads differ")
        ratios = [x / y for x, y in zip(times[1], times[2])]
        for threads in (1, 2):
            m = measure(sm, work / f"t{threads}-{tag}.mesh", inp)
            rows.append((tag, f"partitioned, {threads} thread{'s' if threads > 1 else ''}", m, statistics.median(times[threads]), max(peaks[threads]),
                         statistics.median(ratios) if threads == 2 else 1.0, statistics.median(models) if threads == 2 else None))
        if not a.no_serial:
            out = work / f"serial-{tag}.mesh"
            dt, mb, _ = timed(common + ["-o", str(out), "--no-partition"])
            m = measure(sm, out, inp)
            rows.append((tag, "serial (--no-partition)", m, dt, mb, statistics.median(times[1]) / dt, None))
        print(f"{tag}: load {load()} at end; outputs of 1 and 2 threads identical: {same}", file=sys.stderr, flush=True)
    print("| target | run | triangles | wall (s, median) | speed vs 1 thread | modelled on 2 | peak MB | in band (input field) | mean q | min q |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for tag, name, m, dt, mb, ratio, model in rows:
        model = f"{model:.2f}x" if model else ""
        print(f"| {tag} | {name} | {m['triangles']} | {dt:.1f} | {ratio:.2f}x | {model} | {mb:.0f} | {m['conforming_share']:.4f} | {m['mean_quality']:.4f} | {m['min_quality']:.4f} |")


if __name__ == "__main__":
    main()
