//! `adapt --complexity N` on a recipe alone: the final mesh has N vertices within 5 %,
//! whatever the recipe's own complexity (fewer and more than it: its sizes, HMIN and HMAX
//! included, scale with the budget), and the history says the budget and what each
//! field was normalised to. A budget below the vertices a `.poly` keeps is said before the loop. The heavy check,
//! on every example and benchmark problem, is `benches/budget.py`.

#[path = "support/cli.rs"]
#[allow(dead_code)]
mod support;
use support::fixture;

fn final_vertices(n: f64) -> (f64, serde_json::Value) {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out.msh");
    let o = support::command(&[
        "adapt",
        fixture("cylinder.msh").to_str().unwrap(),
        "--recipe",
        fixture("cylinder.toml").to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--complexity",
        &n.to_string(),
        "--max-iterations",
        "8",
    ])
    .output()
    .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let h: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.path().join("out.history.json")).unwrap())
            .unwrap();
    let best = h["best_iteration"].as_u64().unwrap() as usize;
    (h["iterations"][best]["vertices"].as_f64().unwrap(), h)
}

#[test]
fn the_final_mesh_has_the_vertices_asked_within_five_percent() {
    for n in [600.0, 2500.0] {
        let (v, h) = final_vertices(n);
        assert!((v / n - 1.0).abs() <= 0.05, "asked {n}, got {v}: {h}");
        assert_eq!(h["budget"]["vertices"].as_f64(), Some(n));
        assert!(h["budget"]["from"].as_str().unwrap().contains("--complexity"));
        let normalised = h["budget"]["normalised_to"].as_array().unwrap();
        assert_eq!(normalised.len(), h["iterations"].as_array().unwrap().len());
    }
}

/// `adapt` on the u-duct's `.poly` (487 vertices on its segments) with a budget; the
/// stderr and the best mesh's vertex count.
fn u_duct(n: usize, extra: &[&str]) -> (String, f64) {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out.vtu");
    let example = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/u-duct");
    let n = n.to_string();
    let mut args: Vec<String> = vec![
        "adapt".into(),
        example.join("geometry.poly").to_str().unwrap().into(),
        "--recipe".into(),
        example.join("recipe.cfg").to_str().unwrap().into(),
        "-o".into(),
        out.to_str().unwrap().into(),
        "--complexity".into(),
        n,
    ];
    args.extend(extra.iter().map(|s| s.to_string()));
    let refs: Vec<&str> = args.iter().map(String::as_str).collect();
    let o = support::command(&refs).output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let h: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.path().join("out.history.json")).unwrap())
            .unwrap();
    let best = h["best_iteration"].as_u64().unwrap() as usize;
    let v = h["iterations"][best]["vertices"].as_f64().unwrap();
    (String::from_utf8_lossy(&o.stderr).into_owned(), v)
}

#[test]
fn a_budget_below_the_kept_geometry_is_said_before_the_loop_and_coarsening_meets_it() {
    // 300 vertices asked, 487 kept: said before any iteration, with the floor and the way out.
    let (stderr, _) = u_duct(300, &["--max-iterations", "0"]);
    assert!(
        stderr.contains("budget of 300 vertices cannot hold")
            && stderr.contains("a floor of 487")
            && stderr.contains("--coarsen-geometry"),
        "{stderr}"
    );
    // With the geometry's vertices free to go, no warning and the budget holds.
    let (stderr, v) = u_duct(300, &["--coarsen-geometry"]);
    assert!(!stderr.contains("cannot hold"), "{stderr}");
    assert!((v / 300.0 - 1.0).abs() <= 0.05, "got {v}: {stderr}");
    // A budget above the floor is not warned about.
    let (stderr, _) = u_duct(1300, &["--max-iterations", "0"]);
    assert!(!stderr.contains("cannot hold"), "{stderr}");
}
