#!/usr/bin/env bash
# Runs every example end to end — the starting mesh from its geometry.poly, the
# adaptation loop with its recipe (native remesher), the report — and refreshes the
# committed pictures (examples/<name>/result.png). Outputs go to target/examples/.
#
#   bash examples/run.sh            # all examples
#   bash examples/run.sh u-duct     # one
#   bash examples/run.sh distributor  # the three variants of the distributor
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release --quiet
bin="$PWD/target/release/smartmesh"
all=(naca0012-agard01 gamm-a7-viscous u-duct distributor/1-narrow distributor/2-thick distributor/3-s-shaped)
# A folder of variants (the distributor) stands for each of them.
requested=()
for example in "${@:-${all[@]}}"; do
    example=${example%/}
    if [ -f "examples/$example/geometry.poly" ]; then
        requested+=("$example")
    else
        for variant in examples/"$example"/*/geometry.poly; do
            [ -f "$variant" ] || { echo "examples/$example: no geometry.poly here or in its folders" >&2; exit 2; }
            variant=${variant#examples/}
            requested+=("${variant%/geometry.poly}")
        done
    fi
done
for example in "${requested[@]}"; do
    dir="examples/$example"
    # An example's own recipe, else the one its variants share (the distributor's).
    recipe=$(compgen -G "$dir/recipe.*" || compgen -G "$(dirname "$dir")/recipe.*")
    name=$(echo "$example" | tr / -)
    out="target/examples/$name"
    mkdir -p "$out"
    start=$(date +%s.%N)
    "$bin" adapt "$dir/geometry.poly" --recipe "$recipe" -o "$out/$name.msh" --history "$out/$name.history.json" >/dev/null
    seconds=$(echo "$(date +%s.%N) - $start" | bc)
    # The report runs where the mesh is, so that its title is the mesh's own name.
    (cd "$out" && "$bin" report "$name.msh" --recipe "$OLDPWD/$recipe" --history "$name.history.json" \
        -o "$OLDPWD/$dir/result.png" --width 900 --palette 2>/dev/null)
    python3 - "$out/$name.history.json" "$example" "$seconds" <<'PY'
import json, sys
h = json.load(open(sys.argv[1]))
b = h["iterations"][h["best_iteration"]]
print(f"{sys.argv[2]:24} {b['vertices']:7} vertices {b['triangles']:7} triangles  "
      f"{100 * b['conforming_share']:.1f}% conforming  quality {b['mean_quality']:.3f} mean {b['min_quality']:.3f} min  "
      f"{len(h['iterations']) - 1} iterations  {float(sys.argv[3]):.1f} s  ({'converged' if h['converged'] else h['stopped']})")
PY
done
