#!/usr/bin/env bash
# The UGAWG 3D cases (unit cube with the linear metric; cube-cylinder with polar-1 and
# polar-2) driven through mmg3d_O3 by benches/ugawg3d.py, then the pictures of this folder:
# `smartmesh report --cut` of the last adapted meshes with the analytic metric's ellipses
# restricted to the plane.
#
#   bash examples/ugawg3d/make.sh /path/to/adapt-benchmarks [WORK]
#   bash examples/ugawg3d/make.sh --update-pictures /path/to/adapt-benchmarks [WORK]
#
# ADAPT: a checkout of github.com/UGAWG/adapt-benchmarks (start meshes); WORK: where the
# meshes, the figures (ugawg3d.json) and the pictures go (default target/ugawg3d). The
# committed pictures of this folder are rewritten only with --update-pictures. Needs
# numpy, meshio and mmgpy (mmg3d_O3).
set -euo pipefail
cd "$(dirname "$0")/../.."
update=false
if [ "${1:-}" = "--update-pictures" ]; then
    update=true
    shift
fi
adapt=${1:?"usage: make.sh [--update-pictures] /path/to/adapt-benchmarks [WORK]"}
work=${2:-target/ugawg3d}
mkdir -p "$work"
cargo build --quiet
bin="$PWD/target/debug/smartmesh"
python3 benches/ugawg3d.py --ugawg "$adapt" --cycles 5 --work "$work" --smartmesh "$bin" --json "$work/ugawg3d.json"
# The analytic metric at the last meshes' vertices (the bench writes it for cycles 0-4).
python3 - "$work" <<'PY'
import sys
sys.path.insert(0, "benches")
import meshio
import ugawg3d
work = sys.argv[1]
for case in ["linear", "polar-1", "polar-2"]:
    m = meshio.read(f"{work}/{case}-05.mesh")
    ugawg3d.write_sol(f"{work}/{case}-05.sol", ugawg3d.metric(case, m.points[:, :3].astype(float)))
PY
"$bin" report "$work/linear-05.mesh" --metric "$work/linear-05.sol" --cut x=0.5 --width 1000 --palette -o "$work/linear-cut-x0.5.png"
"$bin" report "$work/polar-2-05.mesh" --metric "$work/polar-2-05.sol" --cut z=0.5 --width 1000 --palette -o "$work/polar-2-cut-z0.5.png"
if $update; then
    cp "$work/linear-cut-x0.5.png" "$work/polar-2-cut-z0.5.png" examples/ugawg3d/
fi
