#!/usr/bin/env bash
# Runs two builds of smartmesh on the same inputs and compares what they write, byte for
# byte: what it prints, `size` to every metric format, `remesh` (from a .vtu and a .pos metric), `adapt`
# (native, its mesh and its history less the timings), `info --metric --json` and `mesh`.
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
    } 2>"$out/messages.txt"
    # The messages, less their timings.
    sed -E -i 's/[0-9.]+ s$//; s/ in [0-9.]+ s / /' "$out/messages.txt"
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
