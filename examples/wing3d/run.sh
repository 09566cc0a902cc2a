#!/usr/bin/env bash
# The wing3d example end to end: the starting mesh by Gmsh (geometry.py), `smartmesh
# adapt` through mmg3d_O3 with the recipe, the UGAWG measures of the best mesh
# (`smartmesh info --json`), two planar cuts with the metric's ellipses (`smartmesh
# report --cut`), ParaView's view (render.py) and the figures (figures.py). Everything goes to
# target/examples/wing3d/; `--update-figures` also copies the pictures here and rewrites
# the README's figures (between <!--figures--> and <!--/figures-->).
#
#   bash examples/wing3d/run.sh [--update-figures]
#
# Uses $SMARTMESH when set, else builds and uses target/release/smartmesh. Needs Python's
# gmsh, meshio and numpy, and mmg3d_O3 on PATH (PyPI mmgpy).
set -euo pipefail
cd "$(dirname "$0")/../.."
if [ -z "${SMARTMESH:-}" ]; then
    cargo build --release --quiet
    SMARTMESH="$PWD/target/release/smartmesh"
fi
out=target/examples/wing3d
rm -rf "$out"
mkdir -p "$out"
python3 examples/wing3d/geometry.py "$out/start.msh"
t0=$(date +%s.%N)
# MMG's own gradation off (-hgrad -1): the recipe's field is already graded, and
# anisotropically (MMG's is isotropic at a surface).
"$SMARTMESH" adapt "$out/start.msh" --recipe examples/wing3d/recipe.toml --hausd 0.001 \
    --adapter-arg=-hgrad --adapter-arg=-1 --max-iterations 4 -o "$out/adapted.msh"
t1=$(date +%s.%N)
echo "$t1 - $t0" | bc > "$out/seconds"
"$SMARTMESH" info "$out/adapted.msh" --json > "$out/info.json"
"$SMARTMESH" convert "$out/adapted.msh" "$out/adapted.vtu"
"$SMARTMESH" report "$out/adapted.msh" --cut y=0.75 -o "$out/cut-y0.75.png"
"$SMARTMESH" report "$out/adapted.msh" --cut x=2 -o "$out/cut-x2.png"
# ParaView's view of the wing and a cut, where ParaView is installed (Debian's renders
# under X only: xvfb-run).
if command -v pvpython >/dev/null && command -v xvfb-run >/dev/null; then
    xvfb-run -a pvpython examples/wing3d/render.py "$out/adapted.vtu" "$out/wing-paraview.png" \
        2> "$out/paraview.log" || echo "run.sh: ParaView's view failed (see $out/paraview.log)" >&2
fi
python3 examples/wing3d/figures.py "$out" > "$out/figures.md"
printf '\nThe whole adapt run: %.0f s.\n' "$(cat "$out/seconds")" >> "$out/figures.md"
cat "$out/figures.md"
if [ "${1:-}" = "--update-figures" ]; then
    cp "$out/cut-y0.75.png" "$out/cut-x2.png" examples/wing3d/
    [ ! -f "$out/wing-paraview.png" ] || cp "$out/wing-paraview.png" examples/wing3d/
    python3 - "$out/figures.md" <<'PY'
import re, sys
figures = open(sys.argv[1]).read()
path = "examples/wing3d/README.md"
text = open(path).read()
text = re.sub(r"<!--figures-->.*<!--/figures-->",
              lambda _: "<!--figures-->\n" + figures + "<!--/figures-->", text, flags=re.S)
open(path, "w").write(text)
PY
fi
