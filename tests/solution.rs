//! Metrics from a solution field: the SOLUTION_HESSIAN step in recipes (every reader,
//! intersected with the geometric steps in recipe order) and `smartmesh size --field`
//! end to end, with its refusals of bad solution input.

use std::path::Path;

use smartmesh::formats::{read_path, write_path, CellKind, DataArray, TaggedMesh, WriteOptions};
use smartmesh::recipe::model::SpecValue;
use smartmesh::recipe::{size_mesh, SizeMeshError};
use smartmesh::recipe::{AlgorithmSpec, Global, RecipeFormat};
use smartmesh::sizing::solution::{recover, vertices_of, Method, P1Mesh};
use smartmesh::sizing::SizingError;
use smartmesh::{MeshGraph, Recipe, SizeTensor, Topology};

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

/// A recipe of one SOLUTION_HESSIAN step of `u` with the TOML keys `keys`.
fn hessian_recipe(keys: &str) -> Recipe {
    let text = format!("[[algorithms]]\ntype = \"solution_hessian\"\nfield = \"u\"\n{keys}\n");
    Recipe::from_str(&text, RecipeFormat::Toml, Path::new("s.toml")).unwrap()
}

/// The tensors of `recipe` on `mesh` and the vertex count a mesh conforming to them has.
fn sized(mesh: &TaggedMesh, recipe: &Recipe) -> (Vec<SizeTensor>, f64) {
    let field = size_mesh(mesh, recipe, &mut |_| {}).unwrap().field;
    assert!(field.reached.iter().all(|&r| r));
    let graph = MeshGraph::from_topology(&Topology::from_mesh(mesh), mesh).unwrap();
    let p1 = P1Mesh::new(graph.points(), graph.cells()).unwrap();
    let n = vertices_of(&p1, &field.tensors);
    (field.tensors, n)
}

#[test]
fn each_recipe_option_of_the_step_changes_the_metric_as_it_says() {
    let mesh = cylinder_with_front();
    let wide = "hmin = 1e-9\nhmax = 100\n";
    // COMPLEXITY: the vertex count asked (bounds that do not act).
    let (_, n) = sized(&mesh, &hessian_recipe(&format!("complexity = 2000\n{wide}")));
    assert!((n / 2000.0 - 1.0).abs() < 0.01, "{n}");
    // ERROR instead: in 2D the Lp error of the optimal metric goes as 1/N, so halving the
    // error doubles the vertices.
    let (_, n1) = sized(&mesh, &hessian_recipe(&format!("error = 0.002\n{wide}")));
    let (_, n2) = sized(&mesh, &hessian_recipe(&format!("error = 0.001\n{wide}")));
    assert!((n2 / n1 / 2.0 - 1.0).abs() < 0.05, "{n1} {n2}");

    // P: left out is 2; p = 1 spreads the vertices more evenly than p = 2 (the smallest
    // tensor area over the largest is larger), at the same count.
    let area = |t: &[SizeTensor]| {
        let a: Vec<f64> = t.iter().map(|t| t.sizes()[0] * t.sizes()[1]).collect();
        a.iter().copied().fold(f64::INFINITY, f64::min) / a.iter().copied().fold(0.0, f64::max)
    };
    let (two, _) = sized(&mesh, &hessian_recipe(&format!("complexity = 2000\np = 2\n{wide}")));
    let (default, _) = sized(&mesh, &hessian_recipe(&format!("complexity = 2000\n{wide}")));
    let (one, n) = sized(&mesh, &hessian_recipe(&format!("complexity = 2000\np = 1\n{wide}")));
    assert_eq!(two, default);
    assert!((n / 2000.0 - 1.0).abs() < 0.01, "{n}");
    assert!(area(&one) > 2.0 * area(&two), "{} {}", area(&one), area(&two));

    // RECOVERY: left out is the quadratic fit; the L2 projection gives another field.
    let (fit, _) = sized(
        &mesh,
        &hessian_recipe(&format!("complexity = 2000\nrecovery = \"quadratic-fit\"\n{wide}")),
    );
    let (l2, _) = sized(
        &mesh,
        &hessian_recipe(&format!("complexity = 2000\nrecovery = \"l2-projection\"\n{wide}")),
    );
    assert_eq!(fit, default);
    assert_ne!(l2, fit);

    // HMIN, HMAX: every size within them, and both reached on this field.
    let (t, _) = sized(&mesh, &hessian_recipe("complexity = 2000\nhmin = 0.02\nhmax = 0.05"));
    let (lo, hi) = t
        .iter()
        .fold((f64::INFINITY, 0.0f64), |(lo, hi), t| (lo.min(t.h_min()), hi.max(t.h_max())));
    assert!(lo >= 0.02 * (1.0 - 1e-9) && hi <= 0.05 * (1.0 + 1e-9), "{lo} {hi}");
    assert!(lo < 0.02 * (1.0 + 1e-6) && hi > 0.05 * (1.0 - 1e-6), "{lo} {hi}");
    let (free, _) = sized(&mesh, &hessian_recipe("complexity = 2000"));
    assert!(free.iter().any(|t| t.h_min() < 0.02) && free.iter().any(|t| t.h_max() > 0.05));

    // MAX_ANISOTROPY: the front's tensors are stretched past 3 without it, not with it.
    let aspect = |t: &[SizeTensor]| t.iter().map(SizeTensor::aspect_ratio).fold(1.0, f64::max);
    let (capped, _) =
        sized(&mesh, &hessian_recipe(&format!("complexity = 2000\nmax_anisotropy = 3\n{wide}")));
    assert!(aspect(&default) > 5.0, "{}", aspect(&default));
    assert!(aspect(&capped) <= 3.0 * (1.0 + 1e-9), "{}", aspect(&capped));
    assert!(aspect(&capped) > 2.9, "{}", aspect(&capped));
}

/// P = infinity (the density |H| the H1 seminorm asks for, as `--p inf` on the command
/// line) reads in every recipe format, the same metric from each, round-trips through
/// `recipe convert`, and is the limit of large finite P.
#[test]
fn an_infinite_p_reads_in_every_format_and_round_trips() {
    let cfg = "CREATE_ALGORITHMS = (\n  { TYPE = \"SOLUTION_HESSIAN\"; FIELD = \"u\"; COMPLEXITY = 2000; P = \"inf\"; }\n);\n";
    let json = r#"{"algorithms": [{"type": "solution_hessian", "field": "u", "complexity": 2000, "p": "Infinity"}]}"#;
    let from_cfg = Recipe::from_str(cfg, RecipeFormat::Libconfig, Path::new("s.cfg")).unwrap();
    let from_json = Recipe::from_str(json, RecipeFormat::Json, Path::new("s.json")).unwrap();
    let from_toml = hessian_recipe("complexity = 2000\np = inf");
    let from_toml_word = hessian_recipe("complexity = 2000\np = \"inf\"");
    assert_eq!(from_cfg, from_toml);
    assert_eq!(from_json, from_toml);
    assert_eq!(from_toml_word, from_toml);
    for format in [RecipeFormat::Libconfig, RecipeFormat::Toml, RecipeFormat::Json] {
        let text = from_cfg.to_format(format);
        assert!(text.contains("\"inf\""), "{text}");
        assert_eq!(Recipe::from_str(&text, format, Path::new("s")).unwrap(), from_cfg, "{text}");
    }
    let dir = tempfile::tempdir().unwrap();
    let mut from = dir.path().join("inf.cfg");
    std::fs::write(&from, cfg).unwrap();
    for ext in ["json", "toml", "cfg"] {
        let to = dir.path().join(format!("converted-{ext}.{ext}"));
        ok(&smartmesh(&["recipe", "convert", from.to_str().unwrap(), to.to_str().unwrap()], None));
        assert_eq!(Recipe::from_path(&to).unwrap(), from_cfg, "{ext}");
        from = to;
    }
    // The metric: the same from every format, not that of p = 2, and the limit of a
    // large finite P.
    let mesh = cylinder_with_front();
    let wide = "hmin = 1e-9\nhmax = 100\n";
    let (inf, n) = sized(&mesh, &hessian_recipe(&format!("complexity = 2000\np = inf\n{wide}")));
    let (word, _) =
        sized(&mesh, &hessian_recipe(&format!("complexity = 2000\np = \"infinity\"\n{wide}")));
    let (two, _) = sized(&mesh, &hessian_recipe(&format!("complexity = 2000\np = 2\n{wide}")));
    let (large, _) = sized(&mesh, &hessian_recipe(&format!("complexity = 2000\np = 1e12\n{wide}")));
    assert_eq!(inf, word);
    assert_ne!(inf, two);
    assert!((n / 2000.0 - 1.0).abs() < 0.01, "{n}");
    for (a, b) in inf.iter().zip(&large) {
        for (x, y) in a.sizes().iter().zip(b.sizes()) {
            assert!((x / y - 1.0).abs() < 1e-6, "{x} {y}");
        }
    }
    // Words that are not infinity, and NaN, are refused naming the key.
    let e = Recipe::from_str(
        &cfg.replace("\"inf\"", "\"large\""),
        RecipeFormat::Libconfig,
        Path::new("s.cfg"),
    )
    .unwrap_err();
    assert!(e.to_string().contains("P must be a number or \"inf\""), "{e}");
    assert_eq!(e.line, Some(2), "{e}");
    let e = Recipe::from_str(
        "[[algorithms]]\ntype = \"solution_hessian\"\nfield = \"u\"\ncomplexity = 9\np = nan\n",
        RecipeFormat::Toml,
        Path::new("s.toml"),
    )
    .unwrap_err();
    assert!(
        e.to_string().contains("p = NaN is out of range: expected a number >= 1 or \"inf\""),
        "{e}"
    );
    // HMIN stays a size: infinity is refused there.
    let e = Recipe::from_str(
        "[[algorithms]]\ntype = \"solution_hessian\"\nfield = \"u\"\ncomplexity = 9\nhmax = inf\n",
        RecipeFormat::Toml,
        Path::new("s.toml"),
    )
    .unwrap_err();
    assert!(e.to_string().contains("hmax = inf is out of range"), "{e}");
}

#[test]
fn the_step_options_round_trip_and_bad_ones_are_refused_at_their_line() {
    let full = r#"CREATE_ALGORITHMS = (
  { TYPE = "SOLUTION_HESSIAN"; FIELD = "u"; ERROR = 0.001; P = 1.5; RECOVERY = "l2-projection";
    HMIN = 0.001; HMAX = 0.2; MAX_ANISOTROPY = 50; }
);
"#;
    let r = Recipe::from_str(full, RecipeFormat::Libconfig, Path::new("s.cfg")).unwrap();
    let toml = hessian_recipe(
        "error = 0.001\np = 1.5\nrecovery = \"l2-projection\"\nhmin = 0.001\nhmax = 0.2\nmax_anisotropy = 50",
    );
    assert_eq!(r, toml);
    for format in [RecipeFormat::Libconfig, RecipeFormat::Toml, RecipeFormat::Json] {
        let text = r.to_format(format);
        assert_eq!(Recipe::from_str(&text, format, Path::new("s")).unwrap(), r, "{text}");
    }
    // `recipe convert` through every format and back to libconfig keeps every option.
    let dir = tempfile::tempdir().unwrap();
    let mut from = dir.path().join("full.cfg");
    std::fs::write(&from, full).unwrap();
    for ext in ["toml", "json", "cfg"] {
        let to = dir.path().join(format!("converted-{ext}.{ext}"));
        ok(&smartmesh(&["recipe", "convert", from.to_str().unwrap(), to.to_str().unwrap()], None));
        assert_eq!(Recipe::from_path(&to).unwrap(), r, "{ext}");
        from = to;
    }
    let back = std::fs::read_to_string(&from).unwrap();
    assert!(back.contains("RECOVERY = \"l2-projection\"") && back.contains("MAX_ANISOTROPY = 50"));
    // Only FIELD and COMPLEXITY: the others stay out of every written form.
    let minimal = hessian_recipe("complexity = 300");
    for format in [RecipeFormat::Libconfig, RecipeFormat::Toml, RecipeFormat::Json] {
        let text = minimal.to_format(format);
        let lower = text.to_ascii_lowercase();
        assert!(!lower.contains("recovery") && !lower.contains("hmin") && !lower.contains(" p "));
        assert_eq!(Recipe::from_str(&text, format, Path::new("s")).unwrap(), minimal, "{text}");
    }
    let refused = |keys: &str| {
        let text = format!(
            "CREATE_ALGORITHMS = (\n  {{ TYPE = \"SOLUTION_HESSIAN\"; FIELD = \"u\";\n {keys} }}\n);\n"
        );
        Recipe::from_str(&text, RecipeFormat::Libconfig, Path::new("s.cfg")).unwrap_err()
    };
    for (keys, says, line) in [
        ("COMPLEXITY = 100; ERROR = 0.1;", "ERROR: give COMPLEXITY or ERROR, not both", 3),
        ("P = 2;", "SOLUTION_HESSIAN: give a vertex count (COMPLEXITY) or ERROR", 2),
        ("COMPLEXITY = 100; P = 0.5;", "P: 0.5 is not a norm", 3),
        ("COMPLEXITY = 100; MAX_ANISOTROPY = 0.5;", "MAX_ANISOTROPY: 0.5 is not an aspect", 3),
        ("COMPLEXITY = 100; HMIN = 0.2; HMAX = 0.1;", "HMIN: 0.2 is larger than HMAX 0.1", 3),
        (
            "COMPLEXITY = 100; RECOVERY = \"quadratik-fit\";",
            "RECOVERY = \"quadratik-fit\" is none of",
            3,
        ),
        ("COMPLEXITY = 100; HMAX = -1;", "HMAX = -1 is out of range", 3),
    ] {
        let e = refused(keys);
        let text = e.to_string();
        assert!(text.contains(says), "{keys}: {text}");
        assert_eq!(e.line, Some(line), "{keys}: {text}");
    }
    let e = refused("COMPLEXITY = 100; RECOVERY = \"quadratik-fit\";");
    assert_eq!(e.suggestion.as_deref(), Some("\"quadratic-fit\""), "{e}");
    let e = Recipe::from_str(
        "[[algorithms]]\ntype = \"solution_hessian\"\nfield = \"u\"\ncomplexity = 9\nerror = 0.1\n",
        RecipeFormat::Toml,
        Path::new("s.toml"),
    )
    .unwrap_err();
    assert!(e.to_string().contains("error: give COMPLEXITY or ERROR"), "{e}");
    assert_eq!(e.line, Some(5), "{e}");
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
    // The VTU reader keeps it (a data array may hold NaN); the solution's check refuses
    // it where it is used.
    assert!(e.contains("nan.vtu") && e.contains("`u` at vertex 7 (0-based) is NaN"), "{e}");
}

/// `size --field u,p`: the two fields' metrics normalised together to the vertex count
/// (by an integral independent of the one normalising), intersected, each finer than it
/// would be alone at a share of the count; a missing one among several is named with the
/// file's fields, exit 2.
#[test]
fn size_with_several_fields_intersects_them_at_the_asked_complexity() {
    let dir = tempfile::tempdir().unwrap();
    let mut mesh = cylinder_with_front();
    // A second field of other units and magnitude: a layer along y = 0.8.
    let p: Vec<f64> =
        mesh.points.iter().map(|q| 1e4 * (-((q[1] - 0.8) / 0.05).powi(2)).exp()).collect();
    mesh.point_data.insert("p".into(), DataArray::new(1, p));
    let file = dir.path().join("up.vtu");
    write(&mesh, &file);
    let f = file.to_str().unwrap();
    let out = |name: &str| dir.path().join(name).to_str().unwrap().to_string();
    let size = |fields: &[&str], o: &str, n: &str| {
        let mut args = vec!["size", f];
        for x in fields {
            args.extend_from_slice(&["--field", x]);
        }
        args.extend_from_slice(&["--complexity", n, "-o", o, "--json"]);
        let json = ok(&smartmesh(&args, None));
        serde_json::from_str::<serde_json::Value>(&json).unwrap()
    };
    let (both, repeated) = (out("both.vtu"), out("repeated.vtu"));
    let summary = size(&["u,p"], &both, "3000");
    assert_eq!(summary["solution"]["fields"], serde_json::json!(["u", "p"]), "{summary}");
    assert_eq!(summary["solution"]["field"], "u,p");
    let expected = summary["solution"]["expected_vertices"].as_f64().unwrap();
    assert!((expected / 3000.0 - 1.0).abs() < 0.01, "{expected}");
    size(&["u", "p"], &repeated, "3000");
    assert_eq!(std::fs::read(&both).unwrap(), std::fs::read(&repeated).unwrap());

    // The count by an independent midpoint integral of the written field.
    let read = |path: &str| -> Vec<SizeTensor> {
        let m = read_path(Path::new(path), None).unwrap();
        let a = &m.point_data["metric"];
        (0..m.points.len())
            .map(|v| {
                let c = &a.values[9 * v..9 * v + 9];
                SizeTensor::try_from_metric(&smartmesh::Sym2::new(c[0], c[1], c[4])).unwrap()
            })
            .collect()
    };
    let graph = MeshGraph::from_topology(&Topology::from_mesh(&mesh), &mesh).unwrap();
    let p1 = P1Mesh::new(graph.points(), graph.cells()).unwrap();
    let t = read(&both);
    let independent = midpoint_vertices(&mesh, &t);
    assert!((independent / 3000.0 - 1.0).abs() < 0.1, "{independent}");
    assert!((vertices_of(&p1, &t) / 3000.0 - 1.0).abs() < 0.01);

    // Each field alone at the same count: the result is their intersection scaled by one
    // factor s < 1 (the share each keeps), so in every direction no larger than the
    // smaller of the two scaled, and as large somewhere. s from each vertex's areas; the
    // bounds clamp a few vertices, which then differ.
    let (u_alone, p_alone) = (out("u.vtu"), out("p.vtu"));
    size(&["u"], &u_alone, "3000");
    size(&["p"], &p_alone, "3000");
    let (tu, tp) = (read(&u_alone), read(&p_alone));
    let inter: Vec<SizeTensor> = tu.iter().zip(&tp).map(|(a, b)| a.intersection(b)).collect();
    let s_at = |v: usize| (inter[v].h1() * inter[v].h2()) / (t[v].h1() * t[v].h2());
    let mut all: Vec<f64> = (0..t.len()).map(s_at).collect();
    all.sort_by(f64::total_cmp);
    let s = all[all.len() / 2];
    assert!(s < 1.0 && s > 0.2, "{s}");
    let mut proportional = 0;
    for v in (0..t.len()).filter(|&v| (s_at(v) / s - 1.0).abs() < 1e-6) {
        proportional += 1;
        let mut touches = false;
        for k in 0..180 {
            let a = k as f64 * std::f64::consts::PI / 180.0;
            let d = [a.cos(), a.sin()];
            let smaller = tu[v].size_along(d).min(tp[v].size_along(d)) / s.sqrt();
            let h = t[v].size_along(d);
            assert!(h <= smaller * (1.0 + 1e-6), "vertex {v}, angle {a}: {h} > {smaller}");
            touches |= h > 0.99 * smaller;
        }
        assert!(touches, "vertex {v}: smaller than the intersection in every direction");
    }
    assert!(proportional * 10 >= 9 * t.len(), "{proportional} of {}", t.len());
    // Each field drives the sizes somewhere: on the layer of p far from the front of u,
    // much finer than u alone asks.
    let v = (0..t.len())
        .find(|&v| (mesh.points[v][1] - 0.8).abs() < 0.02 && mesh.points[v][0] < 0.7)
        .expect("a vertex on the layer of p, far from the front of u");
    assert!(t[v].h_min() < 0.5 * tu[v].h_min(), "{:?} vs u alone {:?}", t[v], tu[v]);

    // Refusals, exit 2.
    let e =
        bad(&smartmesh(&["size", f, "--field", "u,w,p", "--complexity", "100", "-o", &both], None));
    assert!(e.contains("up.vtu: no point data `w` (its point arrays: p, u)"), "{e}");
    let e = bad(&smartmesh(
        &["size", f, "--field", "u", "--field", "u", "--complexity", "100", "-o", &both],
        None,
    ));
    assert!(e.contains("--field: `u` is named twice"), "{e}");
    let e =
        bad(&smartmesh(&["size", f, "--field", "u,,p", "--complexity", "100", "-o", &both], None));
    assert!(e.contains("--field: an empty name in `u,,p`"), "{e}");
}

/// ∫ √det M of the Log-Euclidean interpolation of the vertex metrics by a midpoint rule
/// on the 36 sub-triangles of each triangle: the twin of the exact integral.
fn midpoint_vertices(mesh: &TaggedMesh, tensors: &[SizeTensor]) -> f64 {
    use smartmesh::metric::{log_euclidean, log_spd};
    let logs: Vec<smartmesh::Sym2> = tensors.iter().map(|t| log_spd(&t.to_metric())).collect();
    let mut c = 0.0;
    for (kind, cell, _, _) in mesh.cells() {
        if kind != smartmesh::formats::CellKind::Triangle {
            continue;
        }
        let [a, b, q] = [cell[0], cell[1], cell[2]].map(|v| mesh.points[v as usize]);
        let area = 0.5 * ((b[0] - a[0]) * (q[1] - a[1]) - (b[1] - a[1]) * (q[0] - a[0])).abs();
        let l = [cell[0], cell[1], cell[2]].map(|v| &logs[v as usize]);
        let k = 6;
        let (mut sum, mut count) = (0.0, 0);
        for i in 0..k {
            for j in 0..k - i {
                for (di, dj) in [(1.0 / 3.0, 1.0 / 3.0), (2.0 / 3.0, 2.0 / 3.0)] {
                    if di > 0.5 && i + j + 1 >= k {
                        continue;
                    }
                    let (x, y) = ((i as f64 + di) / k as f64, (j as f64 + dj) / k as f64);
                    sum += log_euclidean(&[1.0 - x - y, x, y], &l).det().sqrt();
                    count += 1;
                }
            }
        }
        c += area * sum / count as f64;
    }
    2.0 * c / 3f64.sqrt()
}

use smartmesh_test_support::formats as common;

/// A solver for the loop: u = tanh(30 (x − 0.5 − 0.15 sin 2πy)) on the mesh it is given,
/// or, from iteration `AT` on (the K of `mesh-K.vtu`), the failure `MODE` asks for; mode
/// "two" writes a second field v = 50 tanh(25 (y − 0.3)) beside u.
const SOLVER: &str = r#"
import re, sys, meshio, numpy as np
mode, at, mesh_path, out = sys.argv[1], int(sys.argv[2]), sys.argv[3], sys.argv[4]
k = int(re.search(r"mesh-(\d+)\.", mesh_path).group(1))
m = meshio.read(mesh_path)
x, y = m.points[:, 0], m.points[:, 1]
u = np.tanh(30 * (x - 0.5 - 0.15 * np.sin(2 * np.pi * y)))
if k >= at:
    if mode == "fail":
        print("solver: the linear system did not converge", file=sys.stderr)
        sys.exit(3)
    if mode == "missing":
        sys.exit(0)
    if mode == "count":
        meshio.write(out, meshio.Mesh(m.points[:-1], [], point_data={"u": u[:-1]}))
        sys.exit(0)
data = {"u": u}
if mode == "two":
    data["v"] = 50 * np.tanh(25 * (y - 0.3))
meshio.write(out, meshio.Mesh(m.points, m.cells, point_data=data))
"#;

/// `adapt --solver` on the unit square from a coarse mesh, with a failure from
/// iteration `at` on (`mode` "ok" never fails), with `extra` arguments.
fn adapt_with(dir: &Path, py: &str, mode: &str, at: usize, extra: &[&str]) -> std::process::Output {
    let script = dir.join("solver.py");
    std::fs::write(&script, SOLVER).unwrap();
    let poly = dir.join("square.poly");
    std::fs::write(
        &poly,
        "4 2 0 1\n1 0 0 1\n2 1 0 1\n3 1 1 1\n4 0 1 1\n4 1\n1 1 2 1\n2 2 3 2\n3 3 4 3\n4 4 1 4\n0\n",
    )
    .unwrap();
    let start = dir.join("start.vtu");
    ok(&smartmesh(
        &["mesh", poly.to_str().unwrap(), "--size", "0.1", "-o", start.to_str().unwrap()],
        None,
    ));
    let command = format!("{py} {} {mode} {at} {{mesh}} {{solution}}", script.display());
    let out = dir.join("adapted.vtu");
    let mut args = vec![
        "adapt",
        start.to_str().unwrap(),
        "--solver",
        &command,
        "--complexity-start",
        "150",
        "--complexity-growth",
        "2",
        "--complexity",
        "600",
        "--max-iterations",
        "7",
        "-o",
        out.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    smartmesh(&args, None)
}

fn history(dir: &Path) -> serde_json::Value {
    let text = std::fs::read_to_string(dir.join("adapted.history.json")).unwrap();
    serde_json::from_str(&text).unwrap()
}

#[test]
fn the_solver_loop_converges_and_records_the_solver() {
    let Some(py) = common::python_with(&["meshio", "numpy"]) else { return };
    let dir = tempfile::tempdir().unwrap();
    ok(&adapt_with(dir.path(), &py, "ok", usize::MAX, &[]));
    let h = history(dir.path());
    assert_eq!(h["converged"], true, "{h}");
    let its = h["iterations"].as_array().unwrap();
    let asked: Vec<f64> =
        its.iter().map(|r| r["solver"]["complexity_asked"].as_f64().unwrap()).collect();
    assert_eq!(&asked[..4], [150.0, 300.0, 600.0, 600.0]);
    // No recipe: the whole field is the solution's, normalised to the schedule's count
    // corrected by the previous remeshing's ratio of vertices made to asked.
    let normalised = h["budget"]["normalised_to"].as_array().unwrap();
    assert_eq!(normalised.len(), its.len(), "{h}");
    for (r, t) in its.iter().zip(normalised) {
        let s = &r["solver"];
        assert!(s["seconds"].as_f64().unwrap() > 0.0 && s["field"] == "u", "{r}");
        let (t, o) = (t.as_f64().unwrap(), s["complexity_obtained"].as_f64().unwrap());
        assert!((o / t - 1.0).abs() < 0.01, "{r} {t}");
    }
    // The meshes follow the schedule, and the last ones conform to their field.
    let last = its.last().unwrap();
    let v = last["vertices"].as_f64().unwrap();
    assert!((400.0..800.0).contains(&v), "{last}");
    assert!(last["conforming_share"].as_f64().unwrap() > 0.8, "{last}");
    // The best mesh carries the solution and its field; the solver's files stay.
    let mesh = read_path(&dir.path().join("adapted.vtu"), None).unwrap();
    assert!(mesh.point_data.contains_key("u") && mesh.point_data.contains_key("metric"));
    assert!(dir.path().join("adapted.solver/solution-0.vtu").is_file());
}

/// `adapt --solver --field u,v`: both fields of the solver's output are attached,
/// normalised together to the schedule's count and recorded in the history; a field the
/// solver did not write is named with the fields it did.
#[test]
fn the_solver_loop_intersects_several_fields_and_records_them() {
    let Some(py) = common::python_with(&["meshio", "numpy"]) else { return };
    let dir = tempfile::tempdir().unwrap();
    ok(&adapt_with(dir.path(), &py, "two", usize::MAX, &["--field", "u,v"]));
    let h = history(dir.path());
    let normalised = h["budget"]["normalised_to"].as_array().unwrap();
    for (r, t) in h["iterations"].as_array().unwrap().iter().zip(normalised) {
        let s = &r["solver"];
        assert_eq!(s["field"], "u,v", "{r}");
        assert_eq!(s["fields"], serde_json::json!(["u", "v"]), "{r}");
        let (t, o) = (t.as_f64().unwrap(), s["complexity_obtained"].as_f64().unwrap());
        assert!((o / t - 1.0).abs() < 0.01, "{r} {t}");
    }
    let mesh = read_path(&dir.path().join("adapted.vtu"), None).unwrap();
    assert!(mesh.point_data.contains_key("u") && mesh.point_data.contains_key("v"));

    let dir = tempfile::tempdir().unwrap();
    let out = adapt_with(dir.path(), &py, "two", usize::MAX, &["--field", "u,w"]);
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    // At the starting mesh: nothing adapted yet, the input is at fault (exit 2).
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("solution-0.vtu: no point data `w` (its point arrays: u, v)"),
        "{stderr}"
    );
}

#[test]
fn a_failing_solver_or_a_bad_solution_stops_the_loop_and_keeps_the_best_mesh() {
    let Some(py) = common::python_with(&["meshio", "numpy"]) else { return };
    for (mode, says) in [
        ("fail", vec!["exit status 3", "the linear system did not converge"]),
        ("missing", vec!["exited with 0 but wrote no", "solution-2.vtu"]),
        ("count", vec!["solution-2.vtu", "values of `u` for the"]),
    ] {
        let dir = tempfile::tempdir().unwrap();
        let out = adapt_with(dir.path(), &py, mode, 2, &[]);
        let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
        assert_eq!(out.status.code(), Some(1), "{mode}: {stderr}");
        assert!(stderr.contains("iteration 2 failed while solving"), "{mode}: {stderr}");
        for s in says {
            assert!(stderr.contains(s), "{mode}: `{s}` not in {stderr}");
        }
        assert!(stderr.contains("holds the best mesh, iteration 1"), "{mode}: {stderr}");
        let h = history(dir.path());
        assert_eq!(h["iterations"].as_array().unwrap().len(), 2, "{mode}: {h}");
        let best = read_path(&dir.path().join("adapted.vtu"), None).unwrap();
        assert_eq!(best.points.len() as u64, h["iterations"][1]["vertices"].as_u64().unwrap());
    }
}

/// examples/solution-poisson, light: a scikit-fem solver in the loop finds the circular
/// layer the recipe does not know (the edges across it are much shorter than elsewhere).
#[test]
fn the_poisson_example_finds_the_layer_the_recipe_does_not_know() {
    let Some(py) = common::python_with(&["skfem", "meshio"]) else { return };
    let dir = tempfile::tempdir().unwrap();
    let example = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/solution-poisson");
    let start = dir.path().join("start.vtu");
    let out = dir.path().join("adapted.vtu");
    let (s, o) = (start.to_str().unwrap(), out.to_str().unwrap());
    ok(&smartmesh(
        &["mesh", example.join("geometry.poly").to_str().unwrap(), "--size", "0.1", "-o", s],
        None,
    ));
    let solver = format!("{py} {} {{mesh}} {{solution}}", example.join("solve.py").display());
    let recipe = example.join("recipe.toml");
    ok(&smartmesh(
        &[
            "adapt",
            s,
            "-r",
            recipe.to_str().unwrap(),
            "--solver",
            &solver,
            "--field",
            "u",
            "--complexity-start",
            "400",
            "--complexity-growth",
            "2",
            "--complexity",
            "1600",
            "--max-iterations",
            "5",
            "-o",
            o,
        ],
        None,
    ));
    let mesh = read_path(&out, None).unwrap();
    let (mut near, mut far) = ((0.0, 0), (0.0, 0));
    for (kind, nodes, _, _) in mesh.cells() {
        if kind != smartmesh::formats::CellKind::Triangle {
            continue;
        }
        let p: Vec<[f64; 3]> = nodes.iter().map(|&v| mesh.points[v as usize]).collect();
        let c = [(p[0][0] + p[1][0] + p[2][0]) / 3.0, (p[0][1] + p[1][1] + p[2][1]) / 3.0];
        let r = (c[0] + 0.05).hypot(c[1] + 0.05);
        let shortest = (0..3)
            .map(|k| (p[k][0] - p[(k + 1) % 3][0]).hypot(p[k][1] - p[(k + 1) % 3][1]))
            .fold(f64::INFINITY, f64::min);
        let bin = if (r - 0.7).abs() < 0.02 {
            &mut near
        } else if (r - 0.7).abs() > 0.2 {
            &mut far
        } else {
            continue;
        };
        bin.0 += shortest;
        bin.1 += 1;
    }
    let (near, far) = (near.0 / near.1 as f64, far.0 / far.1 as f64);
    assert!(near < 0.25 * far, "shortest edges: {near} across the layer, {far} away from it");
}

/// `--error` from a bare `.poly` met its first solution on the graph's 4 vertices, where
/// no quadratic fits: the graph is now meshed to --complexity-start or 1000 vertices
/// first, as --complexity does with its schedule's first count.
#[test]
fn an_error_goal_from_a_bare_graph_meshes_it_to_a_start_count_first() {
    let Some(py) = common::python_with(&["skfem", "meshio"]) else { return };
    let dir = tempfile::tempdir().unwrap();
    let example = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/solution-poisson");
    let out = dir.path().join("adapted.vtu");
    let solver = format!("{py} {} {{mesh}} {{solution}}", example.join("solve.py").display());
    let recipe = example.join("recipe.toml");
    ok(&smartmesh(
        &[
            "adapt",
            example.join("geometry.poly").to_str().unwrap(),
            "-r",
            recipe.to_str().unwrap(),
            "--solver",
            &solver,
            "--field",
            "u",
            "--error",
            "0.01",
            "--max-iterations",
            "1",
            "-o",
            out.to_str().unwrap(),
        ],
        None,
    ));
    let h = history(dir.path());
    let first = h["iterations"][0]["vertices"].as_u64().unwrap();
    assert!((500..2000).contains(&first), "{first} vertices at iteration 0");
}

/// Gmsh's meshes of the public fixtures (an airfoil in a circular far field; a
/// square with a hole): both recovery methods give a quadratic's Hessian at every vertex,
/// interior and boundary, to 1e-9 of it.
#[test]
fn both_recoveries_are_exact_on_a_quadratic_on_gmsh_meshes() {
    smartmesh_test_support::require_public_fixtures!();
    for name in ["gmsh/naca0012.v41_ascii.msh", "gmsh/square_hole.v41_ascii.msh"] {
        let mesh = read_path(&smartmesh_test_support::formats::public_fixture(name), None).unwrap();
        let points: Vec<[f64; 2]> = mesh.points.iter().map(|p| [p[0], p[1]]).collect();
        let triangles: Vec<[u32; 3]> = mesh
            .cells()
            .filter(|c| c.0 == CellKind::Triangle)
            .map(|(_, n, _, _)| [n[0], n[1], n[2]])
            .collect();
        // Centred on the mesh, so that the values' round-off stays small.
        let n = points.len() as f64;
        let c = [0, 1].map(|k| points.iter().map(|p| p[k]).sum::<f64>() / n);
        let (a, b, d) = (3.0, -4.0, 1.4);
        let u = |p: [f64; 2]| {
            let (x, y) = (p[0] - c[0], p[1] - c[1]);
            1.0 + 2.0 * x - y + 0.5 * (a * x * x + 2.0 * b * x * y + d * y * y)
        };
        let values: Vec<f64> = points.iter().map(|&p| u(p)).collect();
        let p1 = P1Mesh::from_triangles(&points, &triangles).unwrap();
        let norm = (a * a + 2.0 * b * b + d * d).sqrt();
        for method in Method::ALL {
            let h = recover(&p1, &values, method).unwrap().hessian;
            let (mut worst, mut used) = (0.0f64, 0);
            for v in (0..points.len()).filter(|&v| p1.is_used(v)) {
                let e = ((h[v].a - a).powi(2) + 2.0 * (h[v].b - b).powi(2) + (h[v].c - d).powi(2))
                    .sqrt()
                    / norm;
                worst = worst.max(e);
                used += 1;
            }
            eprintln!(
                "{name}, {}: {used} vertices, worst relative Hessian error {worst:.1e}",
                method.name()
            );
            assert!(used > 100 && worst < 1e-9, "{name}, {method:?}: {worst}");
        }
    }
}
