#!/usr/bin/env bash
# The DFG 2D-1 loop end to end (release build; a few minutes): from start.msh, six
# iterations of `smartmesh adapt` with OpenFOAM's simpleFoam as the solver (solve.py),
# the vertex count asked growing from 1500 by 1.6 up to 16000, then the figures
# (drag and lift per iteration against the benchmark's values) from the solver's log, and
# at each adapted mesh's vertex count a uniform mesh and the recipe alone solved the same
# way (compare.py). Everything goes to target/examples/dfg-2d-1/; `--update-figures` also
# rewrites the committed figure and the README's two tables.
#
#   bash examples/dfg-2d-1/run.sh [--update-figures]
set -euo pipefail
cd "$(dirname "$0")/../.."
cargo build --release --quiet
out=target/examples/dfg-2d-1
rm -rf "$out"
mkdir -p "$out"
export SMARTMESH="$PWD/target/release/smartmesh"
export WM_PROJECT_DIR="${WM_PROJECT_DIR:-/usr/share/openfoam}"
"$SMARTMESH" adapt examples/dfg-2d-1/start.msh --recipe examples/dfg-2d-1/recipe.toml \
    --solver 'python3 examples/dfg-2d-1/solve.py {mesh} {solution}' --field umag \
    --complexity-start 1500 --complexity-growth 1.6 --complexity 16000 --max-iterations 6 \
    -o "$out/adapted.msh"
python3 examples/dfg-2d-1/figures.py "$out/adapted.solver/dfg.jsonl" "$out/drag-lift.png" \
    > "$out/table.md"
cat "$out/table.md"
python3 examples/dfg-2d-1/compare.py "$SMARTMESH" "$out/adapted.solver/dfg.jsonl" "$out/compare" \
    > "$out/compare.md"
cat "$out/compare.md"
if [ "${1:-}" = "--update-figures" ]; then
    cp "$out/drag-lift.png" examples/dfg-2d-1/drag-lift.png
    python3 - "$out/table.md" "$out/compare.md" <<'PY'
import re, sys
path = "examples/dfg-2d-1/README.md"
text = open(path).read()
for marker, table in [("table", sys.argv[1]), ("compare", sys.argv[2])]:
    text = re.sub(f"<!--{marker}-->.*<!--/{marker}-->",
                  lambda _: f"<!--{marker}-->\n" + open(table).read() + f"<!--/{marker}-->",
                  text, flags=re.S)
open(path, "w").write(text)
PY
fi
