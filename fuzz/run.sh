#!/usr/bin/env bash
# Runs every reader's fuzz target for a fixed time each (default 60 s), seeded with the
# public fixtures. Not part of CI (slow); run before a release or after touching a reader:
#   fuzz/run.sh [seconds-per-target] [target...]   (default: every target)
# With cargo-fuzz (`cargo install cargo-fuzz`) it uses `cargo fuzz run` (AddressSanitizer),
# on the nightly toolchain when one is installed, otherwise with RUSTC_BOOTSTRAP=1 so that
# stable accepts the sanitizer flags cargo-fuzz passes. Without cargo-fuzz it builds the
# targets with plain `cargo build --release` and the coverage flags cargo-fuzz passes
# (`-s none`: no sanitizer, which the readers' `forbid(unsafe_code)` makes safe to leave
# out; debug assertions and overflow checks on) and runs the libFuzzer binaries directly.
# Each target's libFuzzer log goes to fuzz/logs/<target>.log and the closing summary
# (runs, seconds) is printed at the end, for fuzz/README.md.
set -euo pipefail
cd "$(dirname "$0")"
secs="${1:-60}"
shift || true
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(gmsh gmsh_pos vtk_legacy vtu triangle tetgen obj medit su2 stl fluent openfoam recipe_libconfig recipe_resolve)
toolchain=()
if rustup toolchain list 2>/dev/null | grep -q '^nightly'; then toolchain=(+nightly); fi
mkdir -p logs
fixtures="${SMARTMESH_PUBLIC_FIXTURES:-$(cd ../.. && pwd)/shared/fixtures/public}"
export RUSTC_BOOTSTRAP=1
triple="$(rustc -vV | sed -n 's/^host: //p')"
if ! cargo fuzz --version >/dev/null 2>&1; then
    export RUSTFLAGS="-Cpasses=sancov-module -Cllvm-args=-sanitizer-coverage-level=4 -Cllvm-args=-sanitizer-coverage-inline-8bit-counters -Cllvm-args=-sanitizer-coverage-pc-table -Cllvm-args=-sanitizer-coverage-trace-compares --cfg fuzzing -Cdebug-assertions -Coverflow-checks -Ccodegen-units=16"
    # FUZZ_PREBUILT=1: run the binaries a previous call built (the sources changed since).
    [ -n "${FUZZ_PREBUILT:-}" ] || cargo build --release --target "$triple" "${targets[@]/#/--bin=}"
fi
declare -A seeds=([gmsh]="gmsh/*.msh 3d/*.msh" [gmsh_pos]="" [vtk_legacy]="vtk/*.vtk 3d/*.vtk" [vtu]="vtk/*.vtu 3d/*.vtu" [triangle]="triangle/*.ele triangle/*.poly triangle/*.node" [obj]="obj/*.obj" [medit]="medit/*.mesh medit/*.meshb 3d/*.mesh 3d/*.meshb" [tetgen]="" [su2]="" [stl]="" [fluent]="" [openfoam]="" [recipe_libconfig]="" [recipe_resolve]="")
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
    # The formats no public fixture holds, seeded with what smartmesh writes of the 3D
    # fixtures (when a build of it is there: `cargo build --release`).
    sm=../target/release/smartmesh
    if [ -x "$sm" ] && [ -d "$fixtures/3d" ]; then
        seedtmp="$(mktemp -d)"
        for src in hex_prism_pyr.v41_ascii.msh box_cyl.v41_binary.msh; do
            base="${src%%.*}"
            case "$target" in
                stl) "$sm" convert -q "$fixtures/3d/$src" "$seedtmp/$base.stl" && cp "$seedtmp/$base.stl" "$corpus/" || true
                     "$sm" convert -q "$fixtures/3d/$src" "$seedtmp/${base}_b.stl" --binary && cp "$seedtmp/${base}_b.stl" "$corpus/" || true ;;
                su2) "$sm" convert -q "$fixtures/3d/$src" "$seedtmp/$base.su2" && cp "$seedtmp/$base.su2" "$corpus/" || true ;;
                fluent) "$sm" convert -q "$fixtures/3d/$src" "$seedtmp/$base.fluent.msh" && cp "$seedtmp/$base.fluent.msh" "$corpus/" || true ;;
                tetgen) if "$sm" convert -q "$fixtures/3d/$src" "$seedtmp/$base.ele" --to tetgen; then
                            { cat "$seedtmp/$base.ele"; printf '\0'; cat "$seedtmp/$base.node"; printf '\0'; cat "$seedtmp/$base.face" 2>/dev/null || true; } > "$corpus/$base.set"
                        fi ;;
                openfoam) if "$sm" convert -q "$fixtures/3d/$src" "$seedtmp/$base.foam"; then
                              pm="$(dirname "$(find "$seedtmp" -name points -path '*polyMesh*' | head -1)")"
                              { first=1; for f in points faces owner neighbour boundary cellZones faceZones; do
                                  [ $first = 1 ] || printf '\0'; first=0; cat "$pm/$f" 2>/dev/null || true; done; } > "$corpus/$base.case"
                          fi ;;
            esac
        done
        rm -rf "$seedtmp"
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
    if [ "$target" = vtk_legacy ]; then
        # No public fixture of the other legacy datasets: one of each, small.
        printf '# vtk DataFile Version 4.2\nt\nASCII\nDATASET POLYDATA\nPOINTS 6 float\n0 0 0 1 0 0 2 0 0 0 1 0 1 1 0 2 2 0\nVERTICES 1 3\n2 0 5\nLINES 1 4\n3 0 1 2\nPOLYGONS 2 10\n5 0 1 2 5 3\n3 1 4 3\nTRIANGLE_STRIPS 1 5\n4 3 0 4 1\nCELL_DATA 5\nSCALARS c int\nLOOKUP_TABLE default\n1 2 3 4 5\n' > "$corpus/polydata.vtk"
        printf '# vtk DataFile Version 4.2\nt\nASCII\nDATASET STRUCTURED_POINTS\nDIMENSIONS 3 2 2\nORIGIN 0 0 0\nSPACING 1 2 3\nPOINT_DATA 12\nSCALARS f float\nLOOKUP_TABLE default\n0 1 2 3 4 5 6 7 8 9 10 11\n' > "$corpus/structured_points.vtk"
        printf '# vtk DataFile Version 4.2\nt\nASCII\nDATASET RECTILINEAR_GRID\nDIMENSIONS 2 2 1\nX_COORDINATES 2 float\n0 1\nY_COORDINATES 2 float\n0 3\nZ_COORDINATES 1 float\n0\n' > "$corpus/rectilinear.vtk"
        printf '# vtk DataFile Version 4.2\nt\nASCII\nDATASET STRUCTURED_GRID\nDIMENSIONS 2 1 2\nPOINTS 4 float\n0 0 0 1 0 0 0 0 1 1 0 1\n' > "$corpus/structured_grid.vtk"
    fi
    if [ "$target" = vtu ]; then
        printf '<VTKFile type="PolyData" version="1.0"><PolyData><Piece NumberOfPoints="4" NumberOfVerts="1" NumberOfLines="1" NumberOfPolys="1" NumberOfStrips="1"><Points><DataArray type="Float64" NumberOfComponents="3" format="ascii">0 0 0 1 0 0 1 1 0 0 1 0</DataArray></Points><Verts><DataArray type="Int64" Name="connectivity" format="ascii">0</DataArray><DataArray type="Int64" Name="offsets" format="ascii">1</DataArray></Verts><Lines><DataArray type="Int64" Name="connectivity" format="ascii">0 1 2</DataArray><DataArray type="Int64" Name="offsets" format="ascii">3</DataArray></Lines><Polys><DataArray type="Int64" Name="connectivity" format="ascii">0 1 2 3</DataArray><DataArray type="Int64" Name="offsets" format="ascii">4</DataArray></Polys><Strips><DataArray type="Int64" Name="connectivity" format="ascii">0 1 3 2</DataArray><DataArray type="Int64" Name="offsets" format="ascii">4</DataArray></Strips></Piece><Piece NumberOfPoints="1" NumberOfVerts="1"><Points><DataArray type="Float32" NumberOfComponents="3" format="ascii">5 5 5</DataArray></Points><Verts><DataArray type="Int32" Name="connectivity" format="ascii">0</DataArray><DataArray type="Int32" Name="offsets" format="ascii">1</DataArray></Verts></Piece></PolyData></VTKFile>' > "$corpus/pieces.vtp"
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
    flags=(-max_total_time="$secs" -rss_limit_mb=2048 -max_len=400000)
    if cargo fuzz --version >/dev/null 2>&1; then
        run=(cargo "${toolchain[@]}" fuzz run "$target" "$corpus" -- "${flags[@]}")
    else
        mkdir -p "artifacts/$target"
        run=("target/$triple/release/$target" "$corpus" "${flags[@]}" -artifact_prefix="artifacts/$target/")
    fi
    if ! "${run[@]}" 2>&1 | tee "logs/$target.log"; then
        echo "!! $target failed: a crash (see fuzz/artifacts/$target) or a build error (see fuzz/logs/$target.log)" >&2
        status=1
    fi
done
echo "== summary"
for target in "${targets[@]}"; do
    echo "$target: $(grep -E '^Done [0-9]+ runs' "logs/$target.log" || echo 'no summary (crash or build failure)')"
done
exit $status
