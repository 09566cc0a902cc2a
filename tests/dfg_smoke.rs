//! The DFG 2D-1 example's loop in short (examples/dfg-2d-1): one adaptation iteration
//! from the coarse starting mesh, OpenFOAM's `simpleFoam` as the solver through the
//! example's `solve.py`. Both solves must give the benchmark's figures roughly (Schäfer
//! & Turek 1996: drag coefficient 5.57953523384, pressure difference 0.11752016697): a
//! wrong reference area, inflow profile or pressure scaling is off by far more than the
//! bounds here (measured: 5.20 and 0.103 on the 515-vertex start, 5.61 and 0.114 after
//! one iteration, about 1600 vertices). Skips, saying so, without `simpleFoam` or
//! Python's meshio, numpy and scipy, unless `SMARTMESH_REQUIRE_INTEROP=1`. The whole
//! loop to 15 000+ vertices is `bash examples/dfg-2d-1/run.sh` (release build, minutes).
//!
//! In release mode (`cargo test --release --test dfg_smoke`, which CI runs) a second test
//! runs the loop to about 6000 vertices and, at each adapted mesh's vertex count, a
//! uniform mesh and the recipe alone (the example's `compare.py`), as the README's
//! second table: about a minute of `simpleFoam` on an idle machine.

#[path = "support/cli.rs"]
#[allow(dead_code)]
mod support;

use std::path::{Path, PathBuf};
use std::process::Command;

use smartmesh_test_support::formats::python_with;
use support::{command, program, stderr};

const DRAG: f64 = 5.57953523384;
const DP: f64 = 0.11752016697;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/dfg-2d-1")
}

fn f(r: &serde_json::Value, k: &str) -> f64 {
    r[k].as_f64().unwrap_or_else(|| panic!("no number `{k}` in {r}"))
}

fn json_lines(path: &Path) -> Vec<serde_json::Value> {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    text.lines().map(|l| serde_json::from_str(l).unwrap()).collect()
}

/// The example's loop in `dir` (as run.sh runs it, up to `complexity` vertices in
/// `iterations` iterations): the solver's log, one JSON object per solve.
fn dfg_loop(py: &str, dir: &Path, complexity: &str, iterations: &str) -> Vec<serde_json::Value> {
    let out = dir.join("adapted.msh");
    let solver = format!("{py} '{}' {{mesh}} {{solution}}", root().join("solve.py").display());
    let o = command(&[
        "adapt",
        root().join("start.msh").to_str().unwrap(),
        "--recipe",
        root().join("recipe.toml").to_str().unwrap(),
        "--solver",
        &solver,
        "--field",
        "umag",
        "--complexity-start",
        "1500",
        "--complexity-growth",
        "1.6",
        "--complexity",
        complexity,
        "--max-iterations",
        iterations,
        "-o",
        out.to_str().unwrap(),
    ])
    .env("SMARTMESH", env!("CARGO_BIN_EXE_smartmesh"))
    .output()
    .unwrap();
    let log = dir.join("adapted.solver/dfg.jsonl");
    assert!(log.exists(), "no dfg.jsonl: {}", stderr(&o));
    let rows = json_lines(&log);
    assert!(rows.len() >= 2, "{rows:?}\n{}", stderr(&o));
    rows
}

#[test]
fn one_iteration_of_the_dfg_loop_with_simple_foam() {
    if program("simpleFoam").is_none() {
        return;
    }
    let Some(py) = python_with(&["meshio", "numpy", "scipy"]) else { return };
    let dir = tempfile::tempdir().unwrap();
    let rows = dfg_loop(&py, dir.path(), "1500", "1");
    let (first, last) = (&rows[0], &rows[rows.len() - 1]);
    assert_eq!(f(first, "vertices"), 515.0, "{first}");
    // The coarse start: within 10 % of the drag, 15 % of the pressure difference.
    assert!((f(first, "cd") / DRAG - 1.0).abs() < 0.10, "{first}");
    assert!((f(first, "dp") / DP - 1.0).abs() < 0.15, "{first}");
    // After one iteration: more vertices, within 2 % and 6 %, a small lift.
    assert!(f(last, "vertices") > 1000.0, "{last}");
    assert!((f(last, "cd") / DRAG - 1.0).abs() < 0.02, "{last}");
    assert!((f(last, "dp") / DP - 1.0).abs() < 0.06, "{last}");
    assert!(f(last, "cl").abs() < 0.05, "{last}");
}

/// The loop to about 6000 vertices beside, at each adapted mesh's vertex count, a uniform
/// mesh (`smartmesh mesh --size H`), the recipe alone (`adapt --complexity N`, no
/// solution) and the recipe alone on the channel with the cylinder centred (lift 0), all
/// solved by the same script (compare.py). Measured (the README's second
/// table): drag errors +0.45, +0.77, +0.77, +0.71 % adapted; -8.3, -6.8, -4.1, -0.31 %
/// uniform; -1.4, -0.90, +0.49, -0.21 % recipe alone, at 1587, 2376, 3813 and 6110
/// vertices. Release mode only (the issue asks the example run in release mode in CI).
#[test]
#[cfg_attr(debug_assertions, ignore = "release mode: cargo test --release --test dfg_smoke")]
fn the_dfg_loop_beside_a_uniform_mesh_and_the_recipe_alone() {
    if program("simpleFoam").is_none() || program("gmsh").is_none() {
        return;
    }
    let Some(py) = python_with(&["meshio", "numpy", "scipy"]) else { return };
    let dir = tempfile::tempdir().unwrap();
    let rows = dfg_loop(&py, dir.path(), "6200", "4");
    assert_eq!(rows.len(), 5, "{rows:?}");
    let cmp = dir.path().join("compare");
    let o = Command::new(&py)
        .arg(root().join("compare.py"))
        .args([
            env!("CARGO_BIN_EXE_smartmesh").as_ref(),
            dir.path().join("adapted.solver/dfg.jsonl").as_os_str(),
            cmp.as_os_str(),
        ])
        .env(
            "WM_PROJECT_DIR",
            std::env::var("WM_PROJECT_DIR").unwrap_or("/usr/share/openfoam".into()),
        )
        .output()
        .unwrap();
    assert!(o.status.success(), "compare.py: {}", stderr(&o));
    let table = String::from_utf8_lossy(&o.stdout);
    let others = json_lines(&cmp.join("compare.jsonl"));
    assert_eq!(others.len(), 3 * (rows.len() - 1), "{others:?}");
    let err = |r: &serde_json::Value| (f(r, "cd") / DRAG - 1.0).abs();
    for (k, adapted) in rows.iter().enumerate().skip(1) {
        let n = f(adapted, "vertices");
        // From the first adapted mesh on, the drag is within 1 % and the lift small
        // (its sign and size are the meshes' asymmetry: see the README).
        assert!(err(adapted) < 0.01, "iteration {k}: {adapted}\n{table}");
        assert!(f(adapted, "cl").abs() < 0.05, "iteration {k}: {adapted}\n{table}");
        for kind in ["uniform", "recipe", "centred"] {
            let r = others
                .iter()
                .find(|r| r["kind"] == kind && r["iteration"] == k)
                .unwrap_or_else(|| panic!("no {kind} row for iteration {k}\n{table}"));
            // The same vertex count, within compare.py's 2 % (and a rounding's margin).
            assert!((f(r, "vertices") / n - 1.0).abs() < 0.025, "{kind} {k}: {r} vs {n}");
            if kind == "recipe" {
                assert!(err(r) < 0.02, "recipe {k}: {r}\n{table}");
            }
            // The centred cylinder's lift is exactly 0: what is solved is the meshes'
            // asymmetry, of the size of the benchmark's lift (measured 0.0114, -0.0067,
            // 0.0098, 0.0008 at 1611, 2370, 3846, 6202 vertices).
            if kind == "centred" {
                assert!(f(r, "cl").abs() < 0.03, "centred {k}: {r}\n{table}");
            }
        }
    }
    // Up to about 4000 vertices the adapted meshes' drag is 5 times closer than the
    // uniform meshes'; the uniform mesh catches up after (measured: -0.31 % at 6071).
    for (k, adapted) in rows.iter().enumerate().take(4).skip(1) {
        let u = others.iter().find(|r| r["kind"] == "uniform" && r["iteration"] == k).unwrap();
        assert!(err(adapted) * 5.0 < err(u), "iteration {k}: {adapted} vs {u}\n{table}");
    }
}
