"""The figures of the DFG 2D-1 example from the solver's log (one JSON line per solve,
written by solve.py): a Markdown table on stdout (iteration, vertices, cells, drag and
lift coefficients, pressure difference, their errors against Schäfer & Turek's values,
SIMPLE iterations, seconds) and a plot of drag and lift per iteration beside the
reference values.

    python3 figures.py dfg.jsonl drag-lift.png > table.md
"""

import json
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

CD, CL, DP = 5.57953523384, 0.010618948146, 0.11752016697


def main(argv):
    rows = [json.loads(l) for l in open(argv[1]) if l.strip()]
    print("| iteration | vertices | cells | c_D | error | c_L | error | Δp | error | SIMPLE its | s |")
    print("|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for k, r in enumerate(rows):
        print(f"| {k} | {r['vertices']} | {r['cells']} | {r['cd']:.4f} | "
              f"{100 * (r['cd'] / CD - 1):+.2f} % | {r['cl']:.4f} | {100 * (r['cl'] / CL - 1):+.0f} % | "
              f"{r['dp']:.4f} | {100 * (r['dp'] / DP - 1):+.2f} % | {r['iterations']} | {r['seconds']:.1f} |")
    print(f"| reference | | | {CD:.4f} | | {CL:.4f} | | {DP:.4f} | | | |")
    its = list(range(len(rows)))
    fig, (a, b) = plt.subplots(1, 2, figsize=(10, 3.6))
    a.plot(its, [r["cd"] for r in rows], "o-", label="smartmesh + simpleFoam")
    a.axhline(CD, color="k", ls="--", label=f"Schäfer & Turek {CD:.4f}")
    a.axhspan(0.99 * CD, 1.01 * CD, color="0.9", label="±1 %")
    a.set_title("drag coefficient c_D")
    b.plot(its, [r["cl"] for r in rows], "o-", label="smartmesh + simpleFoam")
    b.axhline(CL, color="k", ls="--", label=f"Schäfer & Turek {CL:.4f}")
    b.set_title("lift coefficient c_L")
    for ax in (a, b):
        ax.set_xlabel("iteration (vertices)")
        ax.set_xticks(its, [f"{k}\n({r['vertices']})" for k, r in zip(its, rows)], fontsize=7)
        ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(argv[2], dpi=90)


if __name__ == "__main__":
    main(sys.argv)
