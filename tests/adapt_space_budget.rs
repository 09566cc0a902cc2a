//! `adapt --complexity N` on tetrahedral meshes through `mmg3d_O3`: the final mesh has N
//! vertices within 5 %, for a recipe alone (the public box-cylinder with a wall layer on
//! its cylinder) and for a solution intersected into a recipe (examples/poisson3d-skfem:
//! a scikit-fem P1 solver in the loop). The history says the budget and what each field
//! was normalised to. On a surface in space (no volume cell) the budget and the solver
//! are refused, saying why.
//!
//! Needs `mmg3d_O3` on PATH and the public fixtures, and for the solver Python's meshio,
//! numpy and scikit-fem (each test skips with a message without them, mandatory under
//! CI). The whole example is `bash examples/poisson3d-skfem/run.sh`.

use std::path::Path;

use smartmesh_test_support::formats::{public_fixture, python_with};
use smartmesh_test_support::require_public_fixtures;
use smartmesh_test_support::space::{box_cyl_path, cylinder_wall_recipe};

#[path = "support/cli.rs"]
#[allow(dead_code)]
mod support;
use support::{program, run, streams};

/// A wall layer on the cylinder of box_cyl (across the wall 0.02 growing to 0.15 at 0.3
/// away, along it 0.06 to 0.15; h_max 0.15) with a gradation of 1.5 (inside the budget).
fn wall() -> String {
    cylinder_wall_recipe("gradation = 1.5\n")
}

/// Runs `adapt` with `args` after the input, `-o DIR/out.vtu`; the history, checked to
/// be mmg3d's with the 3D measures, and the best iteration's vertex count.
fn adapt(dir: &Path, args: &[&str]) -> (serde_json::Value, f64) {
    let out = dir.join("out.vtu");
    let mut all: Vec<&str> = vec!["adapt"];
    all.extend(args);
    all.extend(["-o", out.to_str().unwrap()]);
    let o = run(&all);
    assert_eq!(o.status.code(), Some(0), "{}", streams(&o));
    let h: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.join("out.history.json")).unwrap()).unwrap();
    assert_eq!(h["adapter"], "mmg3d", "{h}");
    let best = h["best_iteration"].as_u64().unwrap() as usize;
    let rows = h["iterations"].as_array().unwrap();
    for row in rows {
        assert_eq!(row["space"]["cell"], "tetrahedron", "{row}");
    }
    let normalised = h["budget"]["normalised_to"].as_array().unwrap();
    assert_eq!(normalised.len(), rows.len(), "{h}");
    let v = rows[best]["vertices"].as_f64().unwrap();
    let mesh = smartmesh::read_path(&out, None).unwrap();
    assert_eq!(mesh.points.len() as f64, v);
    (h, v)
}

/// The vertex counts of the iterations, for messages.
fn counts(h: &serde_json::Value) -> Vec<u64> {
    h["iterations"].as_array().unwrap().iter().map(|r| r["vertices"].as_u64().unwrap()).collect()
}

#[test]
fn a_recipe_alone_meets_the_budget_within_five_percent() {
    require_public_fixtures!();
    if program("mmg3d_O3").is_none() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let recipe = dir.path().join("wall.toml");
    std::fs::write(&recipe, wall()).unwrap();
    let input = box_cyl_path();
    let n = 3000.0;
    let (h, v) = adapt(
        dir.path(),
        &[
            input.to_str().unwrap(),
            "-r",
            recipe.to_str().unwrap(),
            "--complexity",
            "3000",
            "--max-iterations",
            "6",
        ],
    );
    eprintln!("box_cyl, --complexity 3000: {:?}, best {v}", counts(&h));
    assert!((v / n - 1.0).abs() <= 0.05, "asked {n}, got {v}: {h}");
    assert_eq!(h["budget"]["vertices"].as_f64(), Some(n));
    assert!(h["budget"]["from"].as_str().unwrap().contains("--complexity"), "{h}");
}

#[test]
fn a_solution_and_a_recipe_meet_the_budget_within_five_percent() {
    if program("mmg3d_O3").is_none() {
        return;
    }
    let Some(py) = python_with(&["meshio", "numpy", "skfem"]) else { return };
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/poisson3d-skfem");
    let dir = tempfile::tempdir().unwrap();
    let solver = format!("{py} '{}' {{mesh}} {{solution}}", root.join("solve.py").display());
    let n = 2500.0;
    let (h, v) = adapt(
        dir.path(),
        &[
            root.join("start.msh").to_str().unwrap(),
            "--recipe",
            root.join("recipe.toml").to_str().unwrap(),
            "--solver",
            &solver,
            "--field",
            "u",
            "--complexity",
            "2500",
            "--max-iterations",
            "6",
        ],
    );
    eprintln!("poisson3d, --complexity 2500: {:?}, best {v}", counts(&h));
    assert!((v / n - 1.0).abs() <= 0.05, "asked {n}, got {v}: {h}");
    // Every iteration ran the solver and asked the budget of the solution's metric.
    for row in h["iterations"].as_array().unwrap() {
        assert_eq!(row["solver"]["field"], "u", "{row}");
        assert_eq!(row["solver"]["complexity_asked"].as_f64(), Some(n), "{row}");
    }
}

#[test]
fn a_surface_in_space_refuses_the_budget_and_the_solver_saying_why() {
    require_public_fixtures!();
    let dir = tempfile::tempdir().unwrap();
    let recipe = dir.path().join("wall.toml");
    std::fs::write(&recipe, wall()).unwrap();
    let surface = public_fixture("3d/box_cyl_surf_input.mesh");
    let out = dir.path().join("out.mesh");
    let (s, r, o) = (surface.to_str().unwrap(), recipe.to_str().unwrap(), out.to_str().unwrap());
    for (extra, why) in [
        (&["--complexity", "3000"][..], "integral of √det M over volume cells"),
        (&["--solver", "true {mesh} {solution}", "--complexity", "300"][..], "volume cells"),
        (&["--solver", "true {mesh} {solution}", "--error", "0.01"][..], "recovered on tetrahedra"),
    ] {
        let mut args = vec!["adapt", s, "-r", r, "-o", o];
        args.extend(extra);
        let res = run(&args);
        assert_eq!(res.status.code(), Some(2), "{extra:?}: {}", streams(&res));
        let e = String::from_utf8_lossy(&res.stderr);
        assert!(e.contains("a surface in space") && e.contains(why), "{extra:?}: {e}");
        assert!(!out.exists(), "{extra:?} wrote {o}");
    }
    // On tetrahedra, a solver with neither a budget nor a recipe's steps is refused as in
    // the plane, before any work.
    let tets = box_cyl_path();
    let res =
        run(&["adapt", tets.to_str().unwrap(), "--solver", "true {mesh} {solution}", "-o", o]);
    assert_eq!(res.status.code(), Some(2), "{}", streams(&res));
    assert!(String::from_utf8_lossy(&res.stderr).contains("--solver needs --complexity N"));
}
