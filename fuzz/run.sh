#!/usr/bin/env bash
# Runs every reader's fuzz target for a fixed time each (default 60 s), seeded with the
# public fixtures. Not part of CI (slow); run before a release or after touching a reader:
#   fuzz/run.sh [seconds-per-target] [target...]   (default: every target)
# Needs cargo-fuzz (`cargo install cargo-fuzz`). Uses the nightly toolchain when one is
# installed; otherwise RUSTC_BOOTSTRAP=1 lets stable accept the sanitizer flags cargo-fuzz
# passes. Each target's libFuzzer log goes to fuzz/logs/<target>.log and the closing
# summary (runs, seconds) is printed at the end, for fuzz/README.md.
set -euo pipefail
cd "$(dirname "$0")"
secs="${1:-60}"
shift || true
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(gmsh gmsh_pos vtk_legacy vtu triangle tetgen obj medit su2 stl openfoam recipe_libconfig recipe_resolve)
toolchain=()
if rustup toolchain list 2>/dev/null | grep -q '^nightly'; then toolchain=(+nightly); fi
mkdir -p logs
fixtures="${SMARTMESH_PUBLIC_FIXTURES:-$(cd ../.. && pwd)/shared/fixtures/public}"
export RUSTC_BOOTSTRAP=1
declare -A seeds=([gmsh]="gmsh/*.msh 3d/*.msh" [gmsh_pos]="" [vtk_legacy]="vtk/*.vtk" [vtu]="vtk/*.vtu" [triangle]="triangle/*.ele triangle/*.poly triangle/*.node" [obj]="obj/*.obj" [medit]="medit/*.mesh medit/*.meshb 3d/*.mesh 3d/*.meshb" [tetgen]="" [su2]="" [stl]="" [openfoam]="" [recipe_libconfig]="" [recipe_resolve]="")
status=0
for target in "${targets[@]}"; do
    corpus="corpus/$target"
    mkdir -p "$corpus"
    for pattern in ${seeds[$target]}; do
        for f in $fixtures/$pattern; do
            [ -f "$f" ] && [ "$(stat -c %s "$f")" -lt 300000 ] && cp -f "$f" "$corpus/"
        done
    done
    if [ "$target" = triangle ]; then
        # The triangle target reads `.ele NUL .node [NUL .poly]` as one set.
        for ele in $fixtures/triangle/*.ele; do
            base="${ele%.ele}"
            [ -f "$base.node" ] || continue
            { cat "$ele"; printf '\0'; cat "$base.node"; if [ -f "$base.poly" ]; then printf '\0'; cat "$base.poly"; fi; } > "$corpus/$(basename "$base").set"
        done
    fi
    if [ "$target" = tetgen ]; then
        # No public TetGen file: a tetrahedron set (`.ele NUL .node NUL .face`) and a
        # .smesh with a region seed, as smartmesh writes them.
        { printf '1 4 1\n1 1 2 3 4 10\n'; printf '\0'; printf '4 3 0 1\n1 0 0 0 1\n2 1 0 0 1\n3 0 1 0 1\n4 0 0 1 2\n'; printf '\0'; printf '1 1\n1 1 3 2 5\n'; } > "$corpus/tet.set"
        printf '4 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n4 1\n3 1 3 2 1\n3 1 2 4 2\n3 2 3 4 3\n3 1 4 3 4\n0\n1\n1 0.2 0.2 0.2 10 -1\n' > "$corpus/tet.smesh"
    fi
    if [ "$target" = gmsh_pos ]; then
        # No public .pos fixture: a tensor view as `smartmesh size -o X.pos` writes it,
        # and a view of the other records (scalar, vector, text) with comments.
        printf 'View "metric" {\nTT(0,0,0,1,0,0,0,1,0){4,0,0,0,4,0,0,0,1,16,0,0,0,16,0,0,0,1,4,1,0,1,4,0,0,0,1};\nTQ(0,0,0,1,0,0,1,1,0,0,1,0){1,0,0,0,1,0,0,0,1,1,0,0,0,1,0,0,0,1,1,0,0,0,1,0,0,0,1,1,0,0,0,1,0,0,0,1};\n};\n' > "$corpus/metric.pos"
        printf '// scalar\nView("s") {\nSP(0.5,0.5,0){3,4};\nVL(0,0,0,1,0,0){1,0,0,0,1,0};\n/* text */ T2(10,20,0){"label"};\nST(0,0,0,1,0,0,0,1,0){1,2,3};\n};\n' > "$corpus/views.pos"
    fi
    if [ "$target" = recipe_libconfig ]; then
        # The project's own recipes (without their cpp directives, which the target refuses).
        for r in ../fixtures/*.cfg ../examples/*/recipe.cfg; do
            grep -v '^[[:space:]]*#[[:space:]]*[a-z]' "$r" > "$corpus/$(basename "$(dirname "$r")")-$(basename "$r")" || true
        done
    fi
    if [ "$target" = recipe_resolve ]; then
        # The first byte chooses the format: '0' libconfig, '1' TOML, '2' JSON.
        for r in ../fixtures/*.cfg ../examples/*/recipe.cfg; do
            { printf 0; grep -v '^[[:space:]]*#[[:space:]]*[a-z]' "$r" || true; } > "$corpus/$(basename "$(dirname "$r")")-$(basename "$r")"
        done
        for r in ../fixtures/*.toml ../examples/*/recipe.toml; do
            { printf 1; cat "$r"; } > "$corpus/$(basename "$(dirname "$r")")-$(basename "$r")"
        done
    fi
    echo "== $target for ${secs}s"
    if ! cargo "${toolchain[@]}" fuzz run "$target" "$corpus" -- -max_total_time="$secs" -rss_limit_mb=2048 -max_len=400000 2>&1 | tee "logs/$target.log"; then
        echo "!! $target failed: a crash (see fuzz/artifacts/$target) or a build error (see fuzz/logs/$target.log)" >&2
        status=1
    fi
done
echo "== summary"
for target in "${targets[@]}"; do
    echo "$target: $(grep -E '^Done [0-9]+ runs' "logs/$target.log" || echo 'no summary (crash or build failure)')"
done
exit $status
