#!/usr/bin/env python3
"""The figures of the examples' runs, as the READMEs print them.

A figure in a README sits between two HTML comments, invisible once rendered:

    <!--fig:naca0012-agard01:triangles-->15 773<!--/fig-->

and a block of result lines (a fenced block: the comments on lines of their own)

    <!--fig:distributor/1-narrow,distributor/2-thick:line-->
    ```
    distributor/1-narrow ...
    ```
    <!--/fig-->

Fields: vertices, triangles (grouped by thousands from 10 000: `15 773`, `9749`),
conforming (the share of edges of metric length in [1/sqrt 2, sqrt 2], in %, one decimal),
quality-mean, quality-min (three decimals), iterations, seconds (one decimal: the only
figure that depends on the machine) and line (run.sh's result line).

    python3 examples/figures.py line RUN_DIR NAME      # run.sh's result line of one example
    python3 examples/figures.py update RUN_DIR NAME,… FILE…   # rewrite these examples' figures

RUN_DIR is where run.sh leaves each example: RUN_DIR/<name>/<name>.history.json and
<name>.seconds, <name> being the example's folder with `/` as `-`. `update` rewrites the
figures of the examples named (those just run) and leaves the others as they are.
tests/adapt_examples.rs checks every figure but the seconds against its own run.
"""
import json
import os
import re
import sys

MARKER = re.compile(r"<!--fig:([^:>]+):([a-z-]+)-->(.*?)<!--/fig-->", re.S)


def grouped(n):
    return f"{n:,}".replace(",", " ") if n >= 10000 else str(n)


def load(run_dir, example):
    name = example.replace("/", "-")
    path = os.path.join(run_dir, name, name + ".history.json")
    if not os.path.exists(path):
        return None
    with open(path) as f:
        h = json.load(f)
    seconds = None
    sec_path = os.path.join(run_dir, name, name + ".seconds")
    if os.path.exists(sec_path):
        with open(sec_path) as f:
            seconds = float(f.read().strip())
    return h, seconds


def line(example, h, seconds, old=""):
    """run.sh's result line; without a time measured, the one `old` printed."""
    b = h["iterations"][h["best_iteration"]]
    end = "converged" if h["converged"] else h["stopped"]
    if seconds is None:
        m = re.search(r"([\d.]+) s  \(", old)
        seconds = float(m.group(1)) if m else 0.0
    return (f"{example:24} {b['vertices']:7} vertices {b['triangles']:7} triangles  "
            f"{100 * b['conforming_share']:.1f}% conforming  quality {b['mean_quality']:.3f} mean "
            f"{b['min_quality']:.3f} min  {len(h['iterations']) - 1} iterations  "
            f"{seconds:.1f} s  ({end})")


def field(example, what, h, seconds):
    b = h["iterations"][h["best_iteration"]]
    return {
        "vertices": lambda: grouped(b["vertices"]),
        "triangles": lambda: grouped(b["triangles"]),
        "conforming": lambda: f"{100 * b['conforming_share']:.1f}",
        "quality-mean": lambda: f"{b['mean_quality']:.3f}",
        "quality-min": lambda: f"{b['min_quality']:.3f}",
        "iterations": lambda: str(len(h["iterations"]) - 1),
        "seconds": lambda: f"{seconds:.1f}",
    }[what]()


def update(run_dir, only, files):
    runs = {}

    def run(example):
        if example not in only:
            return None
        if example not in runs:
            runs[example] = load(run_dir, example)
        return runs[example]

    for path in files:
        with open(path) as f:
            text = f.read()

        def replace(m):
            names, what, old = m.group(1).split(","), m.group(2), m.group(3)
            if what == "line":
                # One line per example; those not run this time keep theirs.
                kept = [l for l in old.splitlines() if l.strip() and not l.startswith("```")]
                kept += [""] * (len(names) - len(kept))
                lines = "\n".join(line(n, *run(n), k) if run(n) else k for n, k in zip(names, kept))
                new = f"\n```\n{lines}\n```\n"
            elif any(run(n) is None for n in names):
                return m.group(0)  # not run this time: left as it is
            elif what == "seconds" and run(names[0])[1] is None:
                return m.group(0)  # no time measured: the one printed stays
            elif len(names) == 1 and what in FIELDS:
                new = field(names[0], what, *run(names[0]))
            else:
                sys.exit(f"{path}: unknown figure `{m.group(0)[:60]}`")
            return f"<!--fig:{m.group(1)}:{what}-->{new}<!--/fig-->"

        new_text = MARKER.sub(replace, text)
        if new_text != text:
            with open(path, "w") as f:
                f.write(new_text)
            print(f"figures rewritten in {path}", file=sys.stderr)


FIELDS = {"vertices", "triangles", "conforming", "quality-mean", "quality-min", "iterations", "seconds"}

if __name__ == "__main__":
    if len(sys.argv) == 4 and sys.argv[1] == "line":
        loaded = load(sys.argv[2], sys.argv[3])
        if loaded is None:
            sys.exit(f"{sys.argv[3]}: no history under {sys.argv[2]}")
        print(line(sys.argv[3], *loaded))
    elif len(sys.argv) >= 4 and sys.argv[1] == "update":
        update(sys.argv[2], set(sys.argv[3].split(",")), sys.argv[4:])
    else:
        sys.exit(__doc__)
