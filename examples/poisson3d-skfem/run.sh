#!/usr/bin/env bash
# The 3D Poisson wave-front loop end to end (release build; a few minutes): from
# start.msh, `smartmesh adapt` through mmg3d_O3 with the scikit-fem solver (solve.py),
# the vertex count asked growing from 1000 by 1.6 up to 8000; then the same solver on
# a uniform Gmsh mesh of about as many vertices, and the picture (the cut z = 0.5).
# Everything goes to target/examples/poisson3d-skfem/; `--update-picture` also rewrites
# the committed result.png.
#
#   bash examples/poisson3d-skfem/run.sh [--update-picture]
#
# Needs Python's gmsh, meshio, numpy, scikit-fem and mmgpy (mmg3d_O3).
set -euo pipefail
cd "$(dirname "$0")/../.."
cargo build --release --quiet
here=examples/poisson3d-skfem
out=target/examples/poisson3d-skfem
rm -rf "$out"
mkdir -p "$out"
bin="$PWD/target/release/smartmesh"
"$bin" adapt "$here/start.msh" --recipe "$here/recipe.toml" \
    --solver "python3 $here/solve.py {mesh} {solution} --log $out/errors.jsonl" --field u \
    --complexity-start 1000 --complexity-growth 1.6 --complexity 8000 --max-iterations 8 \
    -o "$out/adapted.vtu"
echo "per iteration (the solver's errors on each mesh):"
cat "$out/errors.jsonl"
python3 "$here/geometry.py" "$out/uniform.msh" 0.0503
echo "uniform mesh:"
python3 "$here/solve.py" "$out/uniform.msh" "$out/uniform.vtu" --error
"$bin" report "$out/adapted.vtu" --cut z=0.5 --width 700 -o "$out/result.png"
if [ "${1:-}" = "--update-picture" ]; then
    cp "$out/result.png" "$here/result.png"
fi
