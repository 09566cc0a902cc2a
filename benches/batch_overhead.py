"""What `smartmesh batch` costs over running `smartmesh adapt` by hand, and what
`--jobs 2` gains over `--jobs 1`, on a family of NACA 4-digit variants.

    cargo build --release
    python3 benches/batch_overhead.py                      # 200 variants, 2 rounds
    python3 benches/batch_overhead.py --variants 40 --rounds 1 --log benches/results/x.md

The family is written by `smartmesh variants naca` (thickness x camber x camber position,
20 members per thickness) with the recipe of examples/naca0012-agard01, each variant
adapted to convergence. Three ways of running all of them are timed, whole, from outside
(wall clock around the command, CPU seconds of the finished children):

- alone: `smartmesh adapt INPUT --recipe R -o NAME.msh --history NAME.history.json`
  for each variant in turn, its messages to NAME.log, as a shell loop would;
- batch-1: `smartmesh batch manifest.jsonl -o DIR --jobs 1`;
- batch-2: the same with `--jobs 2`.

Each round runs the three, in an order rotated from round to round, so that a drift of
the machine's speed (other work on it) falls on each alike; ratios are taken within a
round and the median over rounds is reported, beside the load average before each run.
The meshes of the three must be the same bytes (batch promises outputs that depend on
the variant alone), which the script checks. Needs only python3 and the release binary
(SMARTMESH names another).
"""
import argparse
import json
import os
import resource
import shutil
import statistics
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def children_cpu():
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def timed(fn):
    load = os.getloadavg()[0]
    c0, t0 = children_cpu(), time.perf_counter()
    fn()
    return time.perf_counter() - t0, children_cpu() - c0, load


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--variants", type=int, default=200, help="a multiple of 20 (default 200)")
    ap.add_argument("--rounds", type=int, default=2)
    ap.add_argument("--out", default=os.path.join(ROOT, "target", "bench-batch"))
    ap.add_argument("--log", help="also write the table (markdown) to this file")
    a = ap.parse_args()
    if a.variants % 20 or a.variants <= 0:
        sys.exit("--variants: a positive multiple of 20")
    exe = os.environ.get("SMARTMESH", os.path.join(ROOT, "target", "release", "smartmesh"))
    if not os.path.exists(exe):
        sys.exit("%s: missing; run cargo build --release first" % exe)
    recipe = os.path.join(ROOT, "examples", "naca0012-agard01", "recipe.toml")
    shutil.rmtree(a.out, ignore_errors=True)
    family = os.path.join(a.out, "family")
    nt = a.variants // 20
    subprocess.run([exe, "variants", "naca", "--thickness", "0.08:%g:%d" % (0.08 + 0.01 * (nt - 1), nt) if nt > 1 else "0.08",
                    "--camber", "0.01:0.05:5", "--camber-position", "0.3:0.6:4", "--recipe", recipe,
                    "-o", family, "-q"], check=True)
    manifest = os.path.join(family, "manifest.jsonl")
    variants = [json.loads(l) for l in open(manifest)]
    assert len(variants) == a.variants, len(variants)

    def alone(d):
        os.makedirs(d)
        for v in variants:
            name = v["name"]
            with open(os.path.join(d, name + ".log"), "wb") as log:
                subprocess.run([exe, "adapt", os.path.join(family, v["input"]), "--recipe", os.path.join(family, v["recipe"]),
                                "-o", os.path.join(d, name + ".msh"), "--history", os.path.join(d, name + ".history.json")],
                               stdout=log, stderr=log, check=True)

    def batch(jobs):
        def run(d):
            o = subprocess.run([exe, "batch", manifest, "-o", d, "--jobs", str(jobs), "-q"], capture_output=True, text=True)
            if o.returncode != 0:
                sys.exit("batch --jobs %d failed: %s" % (jobs, o.stderr))
        return run

    modes = [("alone", alone), ("batch-1", batch(1)), ("batch-2", batch(2))]
    rows = []   # (round, mode, wall, cpu, load)
    for r in range(a.rounds):
        order = modes[r % 3:] + modes[:r % 3]
        for name, fn in order:
            d = os.path.join(a.out, "%s-%d" % (name, r))
            wall, cpu, load = timed(lambda: fn(d))
            rows.append((r, name, wall, cpu, load))
            print("round %d %-8s %8.1f s wall %8.1f s cpu  load %.2f" % (r + 1, name, wall, cpu, load), flush=True)
        # Same meshes whatever ran them.
        for v in variants:
            ref = open(os.path.join(a.out, "alone-%d" % r, v["name"] + ".msh"), "rb").read()
            for name in ("batch-1", "batch-2"):
                got = open(os.path.join(a.out, "%s-%d" % (name, r), v["name"] + ".msh"), "rb").read()
                if got != ref:
                    sys.exit("%s: %s gives other bytes than adapt alone" % (v["name"], name))
        for name in ("batch-1", "batch-2"):
            recs = [json.loads(l) for l in open(os.path.join(a.out, "%s-%d" % (name, r), "results.jsonl"))]
            bad = [x["name"] for x in recs if x["status"] != "ok"]
            if len(recs) != a.variants or bad:
                sys.exit("%s: %d records, not ok: %s" % (name, len(recs), bad))

    def of(r, name, k):
        return next(x[k] for x in rows if x[0] == r and x[1] == name)

    overhead = [of(r, "batch-1", 2) / of(r, "alone", 2) - 1 for r in range(a.rounds)]
    speedup = [of(r, "batch-1", 2) / of(r, "batch-2", 2) for r in range(a.rounds)]
    per_variant_ms = [(of(r, "batch-1", 2) - of(r, "alone", 2)) / a.variants * 1000 for r in range(a.rounds)]
    med = statistics.median
    lines = [
        "%d NACA 4-digit variants (`smartmesh variants naca`, recipe of examples/naca0012-agard01), %d rounds, %d cores, `python3 benches/batch_overhead.py --variants %d --rounds %d`"
        % (a.variants, a.rounds, os.cpu_count(), a.variants, a.rounds),
        "",
        "| run | wall s (median) | wall s per round | CPU s (median) | load average before |",
        "|---|---|---|---|---|",
    ]
    for name, _ in modes:
        walls = [x[2] for x in rows if x[1] == name]
        cpus = [x[3] for x in rows if x[1] == name]
        loads = [x[4] for x in rows if x[1] == name]
        lines.append("| %s | %.1f | %s | %.1f | %s |" % (name, med(walls), ", ".join("%.1f" % w for w in walls), med(cpus),
                                                        ", ".join("%.2f" % l for l in loads)))
    lines += [
        "",
        "batch --jobs 1 over adapt alone: %+.1f %% (median; rounds %s), %+.1f ms per variant"
        % (100 * med(overhead), ", ".join("%+.1f %%" % (100 * o) for o in overhead), med(per_variant_ms)),
        "batch --jobs 2 speed-up over --jobs 1: %.2fx (median; rounds %s)"
        % (med(speedup), ", ".join("%.2fx" % s for s in speedup)),
        "every mesh the same bytes in the three runs of each round; every record ok",
    ]
    text = "\n".join(lines) + "\n"
    print(text)
    if a.log:
        with open(a.log, "a") as f:
            f.write(text)


if __name__ == "__main__":
    main()
