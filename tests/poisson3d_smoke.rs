//! The 3D Poisson example's loop in short (examples/poisson3d-skfem): two adaptation
//! iterations through `mmg3d_O3` from the example's start, its scikit-fem P1 solver in
//! the loop with a small budget. The solver's own errors against the exact solution
//! (`solve.py --log`) must fall as the layer is found: measured 0.141 (L2) and 3.03 (H1
//! seminorm) on the 235-vertex start, 0.034 and 1.39 after one iteration (1320
//! vertices), 0.0097 and 0.67 after two (2570: early iterations overshoot the budget
//! while the layer is found; the budget itself is `tests/adapt_space_budget.rs`'s); the
//! bounds here allow for another mmg3d build. Skips, saying so, without `mmg3d_O3` or Python's meshio, numpy and
//! scikit-fem (mandatory under CI). The whole loop to 8000 vertices is
//! `bash examples/poisson3d-skfem/run.sh` (release build, minutes).

#[path = "support/cli.rs"]
#[allow(dead_code)]
mod support;

use std::path::Path;

use smartmesh_test_support::formats::python_with;
use support::{program, run, streams};

#[test]
fn two_iterations_of_the_poisson3d_loop_with_scikit_fem() {
    if program("mmg3d_O3").is_none() {
        return;
    }
    let Some(py) = python_with(&["meshio", "numpy", "skfem"]) else { return };
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/poisson3d-skfem");
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("adapted.vtu");
    let log = dir.path().join("errors.jsonl");
    let solver = format!(
        "{py} '{}' {{mesh}} {{solution}} --log '{}'",
        root.join("solve.py").display(),
        log.display()
    );
    let o = run(&[
        "adapt",
        root.join("start.msh").to_str().unwrap(),
        "--recipe",
        root.join("recipe.toml").to_str().unwrap(),
        "--solver",
        &solver,
        "--field",
        "u",
        "--complexity-start",
        "1000",
        "--complexity",
        "1500",
        "--max-iterations",
        "2",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.code().is_some_and(|c| c == 0), "{}", streams(&o));
    let rows = std::fs::read_to_string(&log)
        .unwrap_or_else(|e| panic!("no errors.jsonl ({e}): {}", streams(&o)));
    let rows: Vec<serde_json::Value> =
        rows.lines().map(|l| serde_json::from_str(l).unwrap()).collect();
    assert_eq!(rows.len(), 3, "{rows:?}");
    let f = |r: &serde_json::Value, k: &str| r[k].as_f64().unwrap();
    let (first, last) = (&rows[0], &rows[2]);
    eprintln!("poisson3d smoke: {rows:?}");
    assert_eq!(f(first, "vertices"), 235.0, "{first}");
    assert!((f(first, "l2") - 0.1413).abs() < 2e-3, "{first}");
    // After two iterations: a finer mesh, a quarter of the L2 error, a half of H1.
    assert!((1200.0..=4000.0).contains(&f(last, "vertices")), "{last}");
    assert!(f(last, "l2") < 0.25 * f(first, "l2"), "{last}");
    assert!(f(last, "h1") < 0.5 * f(first, "h1"), "{last}");
    // The history: the solver on every iteration, the budget, the 3D measures.
    let h: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.path().join("adapted.history.json")).unwrap())
            .unwrap();
    assert_eq!(h["budget"]["vertices"].as_f64(), Some(1500.0), "{h}");
    for row in h["iterations"].as_array().unwrap() {
        assert_eq!(row["solver"]["field"], "u", "{row}");
        assert_eq!(row["space"]["cell"], "tetrahedron", "{row}");
    }
}
