//! The vertex count `info --metric` predicts for a 3D metric (its complexity over the
//! mesh, [`smartmesh::metric::complexity3`]) against the count `mmg3d_O3` makes for it, on
//! the public box-cylinder (a 2×1×1 box less a cylinder): a constant metric and an
//! anisotropic one graded along x in an oblique frame. mmg3d runs without gradation
//! (`-hgrad -1`) and without refining the boundary to the geometry (`-hausd 1`), so that
//! it meshes the metric alone. Its tetrahedra are not regular, so it makes more vertices
//! than a unit mesh of regular ones: 1.3 times the prediction for the constant metric,
//! 1.7 for the anisotropic one (measured; the bounds below allow ±15%).
//!
//! Needs `mmg3d_O3` on PATH and the public fixtures (skipped with a message without
//! them, mandatory under CI).

use std::path::Path;
use std::process::Command;

use smartmesh::formats::{read_path, TaggedMesh};
use smartmesh::metric::Sym3;
use smartmesh_test_support::formats::public_fixture;
use smartmesh_test_support::require_public_fixtures;

#[path = "support/cli.rs"]
mod support;
use support::{program, run, streams};

/// A rotation whose axes are none of the coordinate axes: about (1, 2, 3)/√14 by 0.7.
fn rotation() -> [[f64; 3]; 3] {
    let n = 14f64.sqrt();
    let (x, y, z) = (1.0 / n, 2.0 / n, 3.0 / n);
    let (s, c) = 0.7f64.sin_cos();
    let t = 1.0 - c;
    [
        [t * x * x + c, t * x * y + s * z, t * x * z - s * y],
        [t * x * y - s * z, t * y * y + c, t * y * z + s * x],
        [t * x * z + s * y, t * y * z - s * x, t * z * z + c],
    ]
}

/// A Medit `.sol` of the metric with sizes `sizes(p)` along the rows of [`rotation`].
fn write_sol(path: &Path, mesh: &TaggedMesh, sizes: impl Fn([f64; 3]) -> [f64; 3]) {
    let mut text =
        format!("MeshVersionFormatted 2\nDimension 3\nSolAtVertices\n{}\n1 3\n", mesh.points.len());
    for p in &mesh.points {
        let values = sizes(*p).map(|h| 1.0 / (h * h));
        let m = Sym3::from_eigen(values, rotation());
        let row: Vec<String> = m.to_medit().iter().map(|x| format!("{x:e}")).collect();
        text.push_str(&row.join(" "));
        text.push('\n');
    }
    text.push_str("End\n");
    std::fs::write(path, text).unwrap();
}

/// Sizes along the rows of [`rotation`] at a point.
type Sizes = fn([f64; 3]) -> [f64; 3];

/// The vertex count `info --metric --json` predicts, and the count mmg3d makes.
fn predicted_and_made(input: &Path, sol: &Path, dir: &Path) -> (f64, usize) {
    let o = run(&["info", input.to_str().unwrap(), "--metric", sol.to_str().unwrap(), "--json"]);
    assert_eq!(o.status.code(), Some(0), "{}", streams(&o));
    let json: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let predicted = json["metric"]["expected_vertices"].as_f64().expect("expected_vertices");
    let text = run(&["info", input.to_str().unwrap(), "--metric", sol.to_str().unwrap()]);
    let shown = String::from_utf8_lossy(&text.stdout);
    let line = format!("has about {} vertices", predicted.round());
    assert!(shown.contains(&line), "{shown}");
    let out = dir.join("adapted.mesh");
    let status = Command::new("mmg3d_O3")
        .args(["-in", input.to_str().unwrap(), "-sol", sol.to_str().unwrap()])
        .args(["-out", out.to_str().unwrap(), "-hgrad", "-1", "-hausd", "1", "-v", "-1"])
        .output()
        .unwrap();
    assert!(status.status.success(), "{}", String::from_utf8_lossy(&status.stderr));
    let made = read_path(&out, None).unwrap().points.len();
    (predicted, made)
}

#[test]
fn the_predicted_count_is_what_mmg3d_makes_within_its_irregularity() {
    require_public_fixtures!();
    if program("mmg3d_O3").is_none() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let input = public_fixture("3d/box_cyl_input.mesh");
    let mesh = read_path(&input, None).unwrap();
    let sol = dir.path().join("metric.sol");
    let cases: [(&str, Sizes, [f64; 2]); 2] = [
        ("constant", |_| [0.06; 3], [1.1, 1.5]),
        ("anisotropic", |p| [0.025 + 0.03 * p[0], 0.08, 0.12], [1.45, 1.95]),
    ];
    for (name, sizes, [lo, hi]) in cases {
        write_sol(&sol, &mesh, sizes);
        let (predicted, made) = predicted_and_made(&input, &sol, dir.path());
        let ratio = made as f64 / predicted;
        eprintln!("{name}: predicted {predicted:.0}, mmg3d made {made}, ratio {ratio:.3}");
        assert!((lo..=hi).contains(&ratio), "{name}: {made} / {predicted} = {ratio}");
    }
}
