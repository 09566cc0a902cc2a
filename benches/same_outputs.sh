#!/usr/bin/env bash
# Runs two builds of smartmesh on the same inputs and compares what they write, byte for
# byte: what it prints, `size` to every metric format, `remesh` (from a .vtu and a .pos metric), `adapt`
# (native, its mesh and its history less the timings), `info --metric --json`, `mesh`, and
# `adapt` with a LAYER skin and periodic sides, `layer`, `recipe check` and `batch`.
# For changes that must not change anything a user sees.
#
#   bash benches/same_outputs.sh /tmp/smartmesh-before target/release/smartmesh
#
# Everything goes to target/same-outputs/{a,b}/; the script ends with one line per
# output, "same" or "DIFFERS", and exits 1 when anything differs.
set -euo pipefail
cd "$(dirname "$0")/.."
[ $# -eq 2 ] || { echo "usage: $0 BEFORE AFTER (two smartmesh binaries)" >&2; exit 2; }
bins=("$(realpath "$1")" "$(realpath "$2")")
root=target/same-outputs
rm -rf "$root"
# name, starting mesh (for size/remesh/info), adapt input, recipe
cases=(
    "cylinder fixtures/cylinder.msh fixtures/cylinder.msh fixtures/cylinder.toml"
    "agard01 examples/naca0012-agard01/start.msh examples/naca0012-agard01/geometry.poly examples/naca0012-agard01/recipe.toml"
    "u-duct examples/u-duct/start.msh examples/u-duct/geometry.poly examples/u-duct/recipe.cfg"
)
for side in a b; do
    bin=${bins[0]}
    [ "$side" = b ] && bin=${bins[1]}
    # Both sides write to the same paths (messages name them), then move aside.
    out="$root/run"
    mkdir -p "$out"
    {
    for c in "${cases[@]}"; do
        read -r name mesh start recipe <<<"$c"
        for ext in sol vtu vtk pos msh mesh; do
            "$bin" size "$mesh" --recipe "$recipe" -o "$out/$name-field.$ext" >/dev/null
        done
        "$bin" size "$mesh" --recipe "$recipe" -o "$out/$name-field.solb" --json >"$out/$name-size.json"
        "$bin" remesh "$mesh" --metric "$out/$name-field.vtu" -o "$out/$name-remeshed.vtu" \
            --json >"$out/$name-remesh.json"
        "$bin" remesh "$mesh" --metric "$out/$name-field.pos" -o "$out/$name-remeshed-pos.msh" >/dev/null
        "$bin" remesh "$mesh" --metric "$out/$name-field.vtu" -o "$out/$name-parts.msh" \
            --partition-above 0 --threads 2 >/dev/null
        "$bin" info "$mesh" --metric "$out/$name-field.vtu" --json >"$out/$name-info.json"
        "$bin" info "$mesh" --metric "$out/$name-field.pos" --json >"$out/$name-info-pos.json"
        "$bin" info "$out/$name-remeshed.vtu" --json >"$out/$name-info-remeshed.json"
        "$bin" adapt "$start" --recipe "$recipe" -o "$out/$name-adapted.msh" \
            --history "$out/$name-adapted.history.json" --json >"$out/$name-adapt.json"
    done
    "$bin" mesh fixtures/square_hole.poly --size 0.05 -o "$out/square_hole.msh" >/dev/null
    # A solver in the loop, and a field sized from a solution (the complexity's other users).
    poisson=examples/solution-poisson
    "$bin" mesh $poisson/geometry.poly --size 0.1 -o "$out/poisson-start.vtu" >/dev/null
    "$bin" adapt "$out/poisson-start.vtu" --recipe $poisson/recipe.toml \
        --solver "python3 $poisson/solve.py {mesh} {solution}" --field u --complexity-start 500 \
        --complexity-growth 1.6 --complexity 4000 --max-iterations 3 -o "$out/poisson-adapted.vtu" \
        --history "$out/poisson-adapted.history.json" >/dev/null
    "$bin" size "$out/poisson-adapted.vtu" --field u --complexity 8000 -o "$out/poisson-finer.sol" \
        --json >"$out/poisson-size.json"
    # The recipe's global values over the command line's, a recipe with LAYER and
    # PERIODIC (the skin after the loop, the sides kept), `layer`, `recipe check` and
    # `batch` (its manifest's options become adapt's).
    "$bin" size fixtures/cylinder.msh --recipe fixtures/cylinder.toml --hmin 0.004 --hmax 0.1 \
        --hgrad -1 -o "$out/cylinder-controls.sol" --json >"$out/cylinder-controls.json"
    "$bin" adapt fixtures/cylinder.msh --recipe fixtures/cylinder.toml --hmin 0.004 --hgrad 1.2 \
        --max-iterations 2 -o "$out/cylinder-controls.msh" --json >"$out/cylinder-controls-adapt.json"
    distributor=examples/distributor
    "$bin" recipe check $distributor/recipe.cfg $distributor/1-narrow/start.msh >"$out/distributor-check.txt"
    "$bin" recipe check $distributor/recipe.cfg $distributor/1-narrow/start.msh --json \
        >"$out/distributor-check.json"
    "$bin" adapt $distributor/1-narrow/start.msh --recipe $distributor/recipe.cfg --max-iterations 2 \
        -o "$out/distributor-adapted.msh" --json >"$out/distributor-adapt.json"
    "$bin" adapt examples/gamm-a7-viscous/start.msh --recipe examples/gamm-a7-viscous/recipe.toml \
        --max-iterations 2 -o "$out/gamm-adapted.vtu" --json >"$out/gamm-adapt.json"
    "$bin" layer fixtures/cylinder.msh --curves Cylinder --first-height 0.002 --ratio 1.2 --layers 8 \
        --curve-ratio Cylinder=1.15 -o "$out/cylinder-skin.msh" --json >"$out/cylinder-skin.json"
    "$bin" layer fixtures/cylinder.msh --curves Cylinder --y-plus 1 --reynolds 5000 --ref-length 1 \
        --layers 6 --metric "$out/cylinder-field.vtu" -o "$out/cylinder-skin-metric.vtu" >/dev/null
    "$bin" layer $distributor/1-narrow/start.msh --curves 101,102,103,104,105,106,107 --first-height 0.01 \
        --ratio 1.2 --layers 4 --recipe $distributor/recipe.cfg -o "$out/distributor-skin.msh" >/dev/null
    manifest="$out/manifest.jsonl"
    printf '%s\n' \
        "{\"name\": \"cyl\", \"input\": \"$PWD/fixtures/cylinder.msh\", \"recipe\": \"$PWD/fixtures/cylinder.toml\", \"options\": {\"max_iterations\": 1, \"hmin\": 0.004, \"hgrad\": -1, \"format\": \"vtu\", \"vtu_encoding\": \"ascii\"}}" \
        "{\"name\": \"narrow\", \"input\": \"$PWD/$distributor/1-narrow/start.msh\", \"recipe\": \"$PWD/$distributor/recipe.cfg\", \"options\": {\"max_iterations\": 1, \"binary\": true, \"adapter_args\": []}}" \
        >"$manifest"
    "$bin" batch "$manifest" -o "$out/batch" >/dev/null
    rm "$out/batch/"*.log "$out/batch/".*.lock
    for f in "$out/batch/"*.history.json; do mv "$f" "$out/batch-$(basename "$f")"; done
    python3 - "$out/batch/results.jsonl" >"$out/batch-results.json" <<'PY'
import json, sys
print(json.dumps(sorted((json.loads(l) for l in open(sys.argv[1])), key=lambda r: r["name"])))
PY
    rm "$out/batch/results.jsonl" "$manifest"
    } 2>"$out/messages.txt"
    # The messages, less their timings.
    sed -E -i 's/[0-9.]+ s$//; s/ in [0-9.]+ s / /; s/; [0-9.]+ s with /; with /' "$out/messages.txt"
    mv "$out" "$root/$side"
done
# Timings differ from run to run: dropped from the JSON before comparing.
strip() {
    python3 - "$1" <<'PY'
import json, sys
def drop(x):
    if isinstance(x, dict):
        return {k: drop(v) for k, v in x.items() if "seconds" not in k and k != "phases"}
    if isinstance(x, list):
        return [drop(v) for v in x]
    return x
print(json.dumps(drop(json.load(open(sys.argv[1]))), indent=1, sort_keys=True))
PY
}
status=0
for f in "$root"/a/*; do
    g="$root/b/$(basename "$f")"
    if [ -d "$f" ]; then
        if diff -rq "$f" "$g" >/dev/null; then r=same; else r=DIFFERS; status=1; fi
    elif [[ "$f" == *.json ]]; then
        if [ "$(strip "$f")" = "$(strip "$g")" ]; then r=same; else r=DIFFERS; status=1; fi
    elif cmp -s "$f" "$g"; then r=same; else r=DIFFERS; status=1; fi
    printf '%-8s %s (%s bytes)\n' "$r" "$(basename "$f")" "$(stat -c %s "$f")"
done
exit $status
