//! What `info`, `recipe check` and `remesh --json` say about tags, curves, histograms
//! and numbers (issue 17, item 11): the tag `info` lists is the one a recipe names, a
//! `.poly` is meshed before a recipe is checked on it, JSON histograms come with their
//! bins, and no number is printed with more digits than it has.

#[path = "support/cli.rs"]
mod cli;

use std::path::Path;

use cli::{bundled, ok, smartmesh};
use smartmesh::formats::{read_path, write_path, DataArray, WriteOptions};

fn p(path: &Path) -> &str {
    path.to_str().unwrap()
}

/// The unit square, its sides tagged 1 (three) and 2 (one), no region.
const SQUARE: &str =
    "4 2 0 1\n1 0 0 1\n2 1 0 1\n3 1 1 1\n4 0 1 1\n4 1\n1 1 2 1\n2 2 3 2\n3 3 4 1\n4 4 1 1\n0\n";

fn uniform_recipe(dir: &Path, face: i64) -> std::path::PathBuf {
    let r = dir.join(format!("face{face}.toml"));
    std::fs::write(
        &r,
        format!("[regions]\nAll = [{face}]\n[[algorithms]]\ntype = \"uniform\"\nsize = 0.1\nregions = [\"All\"]\n"),
    )
    .unwrap();
    r
}

#[test]
fn the_face_tag_info_lists_is_the_one_a_recipe_names() {
    let dir = tempfile::tempdir().unwrap();
    let poly = dir.path().join("sq.poly");
    std::fs::write(&poly, SQUARE).unwrap();
    let msh = dir.path().join("sq.msh");
    ok(&smartmesh(&["mesh", p(&poly), "-o", p(&msh)], None));
    let info: serde_json::Value =
        serde_json::from_str(&ok(&smartmesh(&["info", "--json", p(&msh)], None))).unwrap();
    let faces: Vec<&serde_json::Value> =
        info["tags"].as_array().unwrap().iter().filter(|t| t["dim"] == 2).collect();
    assert_eq!(faces.len(), 1, "{info}");
    let listed = faces[0]["tag"].as_i64().unwrap();
    assert_eq!(faces[0]["elementary"], true, "the mesher gives no physical tag: {info}");
    assert_eq!(info["topology"]["faces"][0]["tag"].as_i64().unwrap(), listed, "{info}");
    let recipe = uniform_recipe(dir.path(), listed);
    ok(&smartmesh(&["recipe", "check", p(&recipe), p(&msh)], None));
    let text = ok(&smartmesh(&["info", p(&msh)], None));
    assert!(text.contains("elementary tag"), "{text}");
}

#[test]
fn recipe_check_meshes_a_poly_first_as_adapt_does() {
    let dir = tempfile::tempdir().unwrap();
    let poly = dir.path().join("sq.poly");
    // The same square with a region of attribute 7: face 7 exists only once meshed.
    std::fs::write(&poly, SQUARE.replace("\n0\n", "\n0\n1\n1 0.5 0.5 7 -1\n")).unwrap();
    let recipe = uniform_recipe(dir.path(), 7);
    let out = ok(&smartmesh(&["recipe", "check", p(&recipe), p(&poly)], None));
    assert!(out.contains("valid") && out.contains("1 face"), "{out}");
}

#[test]
fn the_segments_of_a_poly_are_not_called_interior() {
    let dir = tempfile::tempdir().unwrap();
    let poly = dir.path().join("sq.poly");
    std::fs::write(&poly, SQUARE).unwrap();
    let text = ok(&smartmesh(&["info", p(&poly)], None));
    assert!(!text.contains("interior") && text.contains("no faces yet"), "{text}");
    let json: serde_json::Value =
        serde_json::from_str(&ok(&smartmesh(&["info", "--json", p(&poly)], None))).unwrap();
    assert!(json["topology"]["curves"]
        .as_array()
        .unwrap()
        .iter()
        .all(|c| c["on_boundary"].is_null()));
}

#[test]
fn json_histograms_come_with_their_bins_and_remesh_pairs_have_names() {
    let dir = tempfile::tempdir().unwrap();
    let field = dir.path().join("f.vtu");
    let cyl = bundled("cylinder.msh");
    ok(&smartmesh(&["size", &cyl, "-r", &bundled("cylinder.toml"), "-o", p(&field)], None));
    let info: serde_json::Value =
        serde_json::from_str(&ok(&smartmesh(&["info", "--json", p(&field)], None))).unwrap();
    let bins = &info["histogram_bins"];
    let n = |v: &serde_json::Value| v.as_array().unwrap().len();
    assert_eq!(n(&bins["quality"]), n(&info["quality"]["histogram"]) + 1, "{bins}");
    let c = &info["metric"]["conformity"];
    assert_eq!(n(&bins["metric_edge_length"]), n(&c["edge_length_histogram"]) + 1, "{bins}");
    assert_eq!(n(&bins["quality"]), n(&c["quality_histogram"]) + 1);
    assert_eq!(bins["metric_edge_length"][1].as_f64(), Some(0.1));
    let measure: serde_json::Value =
        serde_json::from_str(&ok(&smartmesh(&["remesh", p(&field), "--measure", "--json"], None)))
            .unwrap();
    assert_eq!(measure["histogram_bins"], *bins);
    let out = dir.path().join("r.msh");
    let stats: serde_json::Value = serde_json::from_str(&ok(&smartmesh(
        &["remesh", &cyl, "--metric", p(&field), "-o", p(&out), "--json"],
        None,
    )))
    .unwrap();
    assert_eq!(stats["input"]["vertices"].as_u64().unwrap(), 1148, "{stats}");
    assert!(stats["output"]["triangles"].as_u64().unwrap() > 0, "{stats}");
}

#[test]
fn a_huge_metric_prints_short_numbers() {
    let dir = tempfile::tempdir().unwrap();
    let mut mesh = read_path(Path::new(&bundled("cylinder.msh")), None).unwrap();
    // Sizes of 1e-29: metric lengths near 1e27.
    let m = 1e58;
    let values: Vec<f64> =
        (0..mesh.points.len()).flat_map(|_| [m, 0.0, 0.0, 0.0, m, 0.0, 0.0, 0.0, m]).collect();
    mesh.point_data.insert("metric".into(), DataArray::new(9, values));
    let file = dir.path().join("huge.vtu");
    write_path(&file, &mesh, None, &WriteOptions::default()).unwrap();
    let text = ok(&smartmesh(&["info", p(&file)], None));
    assert!(text.contains("  metric "), "the metric is measured: {text}");
    let measure = ok(&smartmesh(&["remesh", p(&file), "--measure"], None));
    for out in [&text, &measure] {
        let longest = out.split(|c: char| !c.is_ascii_digit()).map(str::len).max().unwrap_or(0);
        assert!(longest <= 12, "a number of {longest} digits:\n{out}");
    }
}

/// An equilateral triangle and, apart, a wall quad ten times longer than high, in legacy
/// VTK: one triangle, one quad, one layer of one quad.
const ONE_TRIANGLE_ONE_QUAD: &str = "# vtk DataFile Version 4.2\none of each\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 7 double\n0 0 0\n1 0 0\n0.5 0.8660254037844386 0\n2 0 0\n12 0 0\n12 1 0\n2 1 0\nCELLS 2 9\n3 0 1 2\n4 3 4 5 6\nCELL_TYPES 2\n5\n9\n";

/// `info` says "1 triangle", "1 quad" (not "1 triangles", "1 quads"), and "2 triangles"
/// when there are two.
#[test]
fn info_counts_one_cell_in_the_singular() {
    let dir = tempfile::tempdir().unwrap();
    let f = dir.path().join("m.vtk");
    std::fs::write(&f, ONE_TRIANGLE_ONE_QUAD).unwrap();
    let text = ok(&smartmesh(&["info", p(&f)], None));
    assert!(text.contains("  quality     1 triangle: min 1.0000"), "{text}");
    assert!(text.contains("layers      1 from the walls (1 quad; height"), "{text}");
    assert!(text.contains("    layer 1    1 quad, height 1 [1, 1]"), "{text}");
    assert!(!text.contains("1 triangles") && !text.contains("1 quads"), "{text}");

    let two = ONE_TRIANGLE_ONE_QUAD
        .replace("POINTS 7", "POINTS 8")
        .replace("2 1 0\nCELLS 2 9\n", "2 1 0\n0.5 -0.8660254037844386 0\nCELLS 3 13\n")
        .replace("4 3 4 5 6\n", "4 3 4 5 6\n3 0 7 1\n")
        .replace("CELL_TYPES 2\n5\n9\n", "CELL_TYPES 3\n5\n9\n5\n");
    std::fs::write(&f, two).unwrap();
    let text = ok(&smartmesh(&["info", p(&f)], None));
    assert!(text.contains("  quality     2 triangles: min 1.0000"), "{text}");
}
