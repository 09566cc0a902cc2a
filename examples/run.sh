#!/usr/bin/env bash
# Runs every example end to end — the starting mesh from its geometry.poly, the
# adaptation loop with its recipe (native remesher), the report. Everything goes to
# target/examples/<name>/ (the mesh, its history, result.png); the committed pictures
# (examples/<name>/result.png) are rewritten only with --update-pictures, which also
# redraws the README's picture of the bundled cylinder (docs/report-cylinder.png), and
# the figures the READMEs print (between <!--fig:…--> comments, see examples/figures.py)
# only with --update-figures.
#
#   bash examples/run.sh                       # all examples
#   bash examples/run.sh u-duct                # one
#   bash examples/run.sh distributor           # the three variants of the distributor
#   bash examples/run.sh --update-pictures     # all, and refresh the committed pictures
#   bash examples/run.sh --update-figures      # all, and rewrite the READMEs' figures
set -euo pipefail
cd "$(dirname "$0")/.."
update=false
figures=false
names=()
for arg in "$@"; do
    case "$arg" in
        --update-pictures) update=true ;;
        --update-figures) figures=true ;;
        -*) echo "examples/run.sh: unknown option $arg (known: --update-pictures, --update-figures)" >&2; exit 2 ;;
        *) names+=("$arg") ;;
    esac
done
cargo build --release --quiet
bin="$PWD/target/release/smartmesh"
all=(naca0012-agard01 naca0012-agard02 naca0012-agard03 naca0012-agard04 naca0012-agard05 gamm-a7-viscous u-duct distributor/1-narrow distributor/2-thick distributor/3-s-shaped)
everything=false
[ ${#names[@]} -gt 0 ] || { names=("${all[@]}"); everything=true; }
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
    echo "$seconds" >"$out/$name.seconds"
    python3 examples/figures.py line target/examples "$example"
done
if $figures; then
    python3 examples/figures.py update target/examples "$(IFS=,; echo "${requested[*]}")" \
        README.md examples/README.md examples/*/README.md
fi
# The README's picture: the quick start's adapted cylinder, drawn 800 px wide.
if $update && $everything; then
    out=target/examples/cylinder
    mkdir -p "$out"
    "$bin" adapt fixtures/cylinder.msh --recipe fixtures/cylinder.toml -o "$out/cylinder-adapted.msh" >/dev/null
    (cd "$out" && "$bin" report cylinder-adapted.msh --recipe "$OLDPWD/fixtures/cylinder.toml" \
        --history cylinder-adapted.history.json -o report-cylinder.png --width 800 --palette 2>/dev/null)
    cp "$out/report-cylinder.png" docs/report-cylinder.png
fi
