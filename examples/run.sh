#!/usr/bin/env bash
# Runs every example end to end — the starting mesh from its geometry.poly, the
# adaptation loop with its recipe (native remesher), the report. Everything goes to
# target/examples/<name>/ (the mesh, its history, result.png); the committed pictures
# (examples/<name>/result.png) are rewritten only with --update-pictures, which also
# redraws the README's picture of the bundled cylinder (docs/report-cylinder.png).
#
#   bash examples/run.sh                       # all examples
#   bash examples/run.sh u-duct                # one
#   bash examples/run.sh distributor           # the three variants of the distributor
#   bash examples/run.sh --update-pictures     # all, and refresh the committed pictures
set -euo pipefail
cd "$(dirname "$0")/.."
update=false
names=()
for arg in "$@"; do
    case "$arg" in
        --update-pictures) update=true ;;
        -*) echo "examples/run.sh: unknown option $arg (known: --update-pictures)" >&2; exit 2 ;;
        *) names+=("$arg") ;;
    esac
done
cargo build --release --quiet
bin="$PWD/target/release/smartmesh"
all=(naca0012-agard01 naca0012-agard02 naca0012-agard03 naca0012-agard04 naca0012-agard05 gamm-a7-viscous u-duct distributor/1-narrow distributor/2-thick distributor/3-s-shaped)
[ ${#names[@]} -gt 0 ] || names=("${all[@]}")
# A folder of variants (the distributor) stands for each of them.
requested=()
for example in "${names[@]}"; do
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
        -o result.png --width 900 --palette 2>/dev/null)
    if $update; then
        cp "$out/result.png" "$dir/result.png"
    fi
    python3 - "$out/$name.history.json" "$example" "$seconds" <<'PY'
import json, sys
h = json.load(open(sys.argv[1]))
b = h["iterations"][h["best_iteration"]]
print(f"{sys.argv[2]:24} {b['vertices']:7} vertices {b['triangles']:7} triangles  "
      f"{100 * b['conforming_share']:.1f}% conforming  quality {b['mean_quality']:.3f} mean {b['min_quality']:.3f} min  "
      f"{len(h['iterations']) - 1} iterations  {float(sys.argv[3]):.1f} s  ({'converged' if h['converged'] else h['stopped']})")
PY
done
# The README's picture: the quick start's adapted cylinder, drawn 800 px wide.
if $update && [ $# -eq 1 ]; then
    out=target/examples/cylinder
    mkdir -p "$out"
    "$bin" adapt fixtures/cylinder.msh --recipe fixtures/cylinder.toml -o "$out/cylinder-adapted.msh" >/dev/null
    (cd "$out" && "$bin" report cylinder-adapted.msh --recipe "$OLDPWD/fixtures/cylinder.toml" \
        --history cylinder-adapted.history.json -o report-cylinder.png --width 800 --palette 2>/dev/null)
    cp "$out/report-cylinder.png" docs/report-cylinder.png
fi
