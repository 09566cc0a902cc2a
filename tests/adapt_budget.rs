//! `adapt --complexity N` on a recipe alone: the final mesh has N vertices within 5 %,
//! whatever the recipe's own complexity (fewer and more than it), with the recipe's
//! bounds acting, and the history says the budget and what each field was normalised to.
//! The heavy check, on every example and benchmark problem, is `benches/budget.py`.

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
