//! `smartmesh size` with CURVATURE_OF_BORDER on a mesh in space: the public box-cylinder's
//! cylinder (radius 0.2, eight vertices round) as the border. Its vertices get the normal
//! size `perpendicular(0)` exactly, a size along the circle from the curvature 1/0.2
//! through the curvature-to-size function (within the error of a fit on eight vertices
//! round), and a larger one along the axis; vertices out of reach keep the default.
//!
//! Needs the public fixtures (skipped with a message without them, mandatory under CI).

use smartmesh::formats::read_path;
use smartmesh_test_support::formats::public_fixture;
use smartmesh_test_support::require_public_fixtures;

#[path = "support/cli.rs"]
mod support;
use support::{run, streams};

const RECIPE: &str = r#"
[global]
h_max = 0.5

[regions]
cyl = ["Cylinder"]

[functions.D]
kind = "distance"
size_at_source = 0.005
size_at_max_distance = 0.2
max_distance = 0.2
exponent = 1.0

[functions.P]
kind = "projection"
size_at_max_distance = 0.2
max_distance = 0.2
exponent = 1.0

[functions.C]
kind = "curvature_to_size"
min_size = 0.001
max_size = 0.4
size_of_error = 0.002

[[algorithms]]
type = "curvature_of_border"
perpendicular = "D"
curvature_to_size = "C"
projection = "P"
regions = ["cyl"]
"#;

#[test]
fn size_takes_a_cylinders_curvature_in_space() {
    require_public_fixtures!();
    let dir = tempfile::tempdir().unwrap();
    let recipe = dir.path().join("c.toml");
    std::fs::write(&recipe, RECIPE).unwrap();
    let input = public_fixture("3d/box_cyl.v41_ascii.msh");
    let out = dir.path().join("f.vtu");
    let o = run(&[
        "size",
        input.to_str().unwrap(),
        "--recipe",
        recipe.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--json",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", streams(&o));
    let j: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(j["steps"][0]["algorithm"], "CURVATURE_OF_BORDER");
    let mesh = read_path(&input, None).unwrap();
    let sized = read_path(&out, None).unwrap();
    let h = |k: &str| sized.point_data[k].values.clone();
    let (h1, h2, h3) = (h("h1"), h("h2"), h("h3"));
    // h(1/R) = 2 √(δ (2R − δ)) with δ = 0.002, R = 0.2.
    let h_circle = 2.0 * (0.002f64 * (0.4 - 0.002)).sqrt();
    let mut on = 0;
    for (i, p) in mesh.points.iter().enumerate() {
        let r = (p[0] - 0.6).hypot(p[1] - 0.5);
        if (r - 0.2).abs() < 1e-9 {
            on += 1;
            // The file rounds the points to about 1e-8 off the facets: d ~ 1e-8.
            assert!((h3[i] - 0.005).abs() < 1e-6, "{p:?}: {}", h3[i]);
            // Eight vertices round: the fit reads up to 1.8 times the curvature.
            assert!(h2[i] > 0.7 * h_circle && h2[i] < 1.05 * h_circle, "{p:?}: {}", h2[i]);
            assert!(h1[i] > h2[i] * 1.1, "{p:?}: {} {}", h1[i], h2[i]);
        } else if r > 0.45 {
            // Out of reach (0.2 from the cylinder, the box's side 0.25 away at most).
            assert_eq!([h1[i], h2[i], h3[i]], [0.5; 3], "{p:?}");
        }
    }
    assert_eq!(on, 67);
}
