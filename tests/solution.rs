//! Metrics from a solution field: the SOLUTION_HESSIAN step in recipes (every reader,
//! intersected with the geometric steps in recipe order) and `smartmesh size --field`
//! end to end, with its refusals of bad solution input.

use std::path::Path;

use smartmesh::formats::{read_path, write_path, DataArray, TaggedMesh, WriteOptions};
use smartmesh::recipe::model::SpecValue;
use smartmesh::recipe::{AlgorithmSpec, Global, RecipeFormat};
use smartmesh::sizing::{size_mesh, SizeMeshError, SizingError};
use smartmesh::{Recipe, SizeTensor};

#[path = "support/cli.rs"]
#[allow(dead_code)]
mod cli;
use cli::{bad, bundled, ok, smartmesh};

/// The cylinder channel with u = tanh(12 (y − 0.3 − 0.1 x)), a front the recipe does not
/// know, as point data `u`.
fn cylinder_with_front() -> TaggedMesh {
    let mut mesh = read_path(Path::new(&bundled("cylinder.msh")), None).unwrap();
    let u = mesh.points.iter().map(|p| (12.0 * (p[1] - 0.3 - 0.1 * p[0])).tanh()).collect();
    mesh.point_data.insert("u".into(), DataArray::new(1, u));
    mesh
}

fn solution_step(complexity: f64) -> AlgorithmSpec {
    AlgorithmSpec::new(
        "SOLUTION_HESSIAN",
        [
            ("field", SpecValue::Name("u".into())),
            ("complexity", SpecValue::Size(complexity)),
            ("p", SpecValue::Size(2.0)),
        ],
    )
    .unwrap()
}

#[test]
fn a_recipe_intersects_the_solution_with_its_geometric_steps_in_every_direction() {
    let mesh = cylinder_with_front();
    let mut geometric = Recipe::from_path(Path::new(&bundled("cylinder.toml"))).unwrap();
    // No clamp and no gradation: the three fields are then the steps' intersections alone.
    geometric.global = Global::default();
    let mut both = geometric.clone();
    both.algorithms.push(solution_step(3000.0));
    let mut alone = Recipe::default();
    alone.algorithms.push(solution_step(3000.0));
    let field = |r: &Recipe| size_mesh(&mesh, r, &mut |_| {}).unwrap().field;
    let (g, s, b) = (field(&geometric), field(&alone), field(&both));
    assert!(s.reached.iter().all(|&r| r) && b.reached.iter().all(|&r| r));
    assert_eq!(b.steps.last().unwrap().label, "algorithm 5 (SOLUTION_HESSIAN of \"u\")");
    let mut finer_than_geometry = 0;
    let mut checked = 0;
    for v in (0..mesh.points.len()).filter(|&v| g.reached[v]) {
        let (gt, st, bt) = (g.tensors[v], s.tensors[v], b.tensors[v]);
        // Recipe order: the solution is intersected last, into the geometric field.
        assert_eq!(bt, gt.intersection(&st), "vertex {v}");
        for k in 0..36 {
            let a = k as f64 * std::f64::consts::PI / 36.0;
            let d = [a.cos(), a.sin()];
            let smaller = gt.size_along(d).min(st.size_along(d));
            assert!(bt.size_along(d) <= smaller * (1.0 + 1e-9), "vertex {v}, direction {a}");
        }
        if st.h_min() < 0.5 * gt.h_min() {
            finer_than_geometry += 1;
        }
        checked += 1;
    }
    // The front is where the solution, not the recipe, decides.
    assert!(checked > 1000 && finer_than_geometry > 50, "{checked} {finer_than_geometry}");
    let iso = |t: &SizeTensor| t.aspect_ratio();
    assert!(s.tensors.iter().map(iso).fold(1.0, f64::max) > 5.0, "the front is anisotropic");
}

#[test]
fn the_step_reads_in_every_recipe_format_and_names_a_missing_field() {
    let cfg = r#"
CREATE_ALGORITHMS = (
  { TYPE = "SOLUTION_HESSIAN"; FIELD = "u"; COMPLEXITY = 2000; P = 2; }
);
"#;
    let r = Recipe::from_str(cfg, RecipeFormat::Libconfig, Path::new("s.cfg")).unwrap();
    let toml =
        "[[algorithms]]\ntype = \"solution_hessian\"\nfield = \"u\"\ncomplexity = 2000\np = 2\n";
    let t = Recipe::from_str(toml, RecipeFormat::Toml, Path::new("s.toml")).unwrap();
    assert_eq!(r, t);
    let json = r.to_format(RecipeFormat::Json);
    assert_eq!(Recipe::from_str(&json, RecipeFormat::Json, Path::new("s.json")).unwrap(), r);
    let mut mesh = cylinder_with_front();
    size_mesh(&mesh, &r, &mut |_| {}).unwrap();
    mesh.point_data.remove("u");
    mesh.point_data.insert("w".into(), DataArray::new(3, vec![0.0; 3 * mesh.points.len()]));
    let e = size_mesh(&mesh, &r, &mut |_| {}).unwrap_err();
    assert!(matches!(e, SizeMeshError::Sizing(SizingError::Field { step: 0, .. })), "{e}");
    let text = e.to_string();
    assert!(text.contains("no point data `u`") && text.contains("its arrays: w"), "{text}");
}

fn write(mesh: &TaggedMesh, path: &Path) {
    write_path(path, mesh, None, &WriteOptions::default()).unwrap();
}

#[test]
fn size_field_writes_a_metric_of_the_asked_complexity_and_refuses_bad_solutions() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = cylinder_with_front();
    let with_u = dir.path().join("u.vtu");
    write(&mesh, &with_u);
    let plain = dir.path().join("plain.vtu");
    let mut bare = mesh.clone();
    bare.point_data.clear();
    write(&bare, &plain);
    let out = dir.path().join("m.sol");
    let (u, o, p) = (with_u.to_str().unwrap(), out.to_str().unwrap(), plain.to_str().unwrap());

    let json = ok(&smartmesh(
        &["size", u, "--field", "u", "--complexity", "2500", "-o", o, "--json"],
        None,
    ));
    let summary: serde_json::Value = serde_json::from_str(&json).unwrap();
    let expected = summary["solution"]["expected_vertices"].as_f64().unwrap();
    assert!((expected / 2500.0 - 1.0).abs() < 0.01, "{expected}");
    assert_eq!(summary["recipe"], "none");

    // With the recipe, from a separate file on the same vertices: finer than either.
    let cyl = bundled("cylinder.toml");
    let json = ok(&smartmesh(
        &[
            "size",
            p,
            "-r",
            &cyl,
            "--solution-file",
            u,
            "--field",
            "u",
            "--complexity",
            "2500",
            "-o",
            o,
            "--json",
        ],
        None,
    ));
    let summary: serde_json::Value = serde_json::from_str(&json).unwrap();
    assert!(summary["solution"]["expected_vertices"].as_f64().unwrap() > 2500.0, "{json}");

    // Refusals, exit 2, naming the file and what is wrong.
    let e = bad(&smartmesh(&["size", u, "--field", "u", "-o", o], None));
    assert!(e.contains("--complexity N or --error E"), "{e}");
    let e = bad(&smartmesh(&["size", p, "-o", o], None));
    assert!(e.contains("missing --recipe"), "{e}");
    let e = bad(&smartmesh(&["size", p, "--field", "u", "--complexity", "100", "-o", o], None));
    assert!(e.contains("no point data `u`"), "{e}");
    let mut short = mesh.clone();
    short.points.truncate(10);
    short.point_data.insert("u".into(), DataArray::new(1, vec![0.0; 10]));
    short.blocks.clear();
    let short_path = dir.path().join("short.vtu");
    write(&short, &short_path);
    let s = short_path.to_str().unwrap();
    let e =
        bad(&smartmesh(&["size", p, "--solution-file", s, "--complexity", "100", "-o", o], None));
    assert!(
        e.contains("short.vtu")
            && e.contains(&format!("10 values of `u` for the {} vertices", mesh.points.len())),
        "{e}"
    );
    let mut nan = mesh.clone();
    nan.point_data.get_mut("u").unwrap().values[7] = f64::NAN;
    let nan_path = dir.path().join("nan.vtu");
    write(&nan, &nan_path);
    let n = nan_path.to_str().unwrap();
    let e =
        bad(&smartmesh(&["size", p, "--solution-file", n, "--complexity", "100", "-o", o], None));
    // The VTU reader refuses it first (the solution's own check is the same for formats
    // that hold NaN).
    assert!(e.contains("nan.vtu") && e.contains("value 7 of `u` is not a finite number"), "{e}");
}
