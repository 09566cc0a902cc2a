//! The 3D topology through the commands: `info` (text and JSON, `--ridge-angle`), `recipe
//! check` resolving surfaces and volumes on a 3D mesh and saying which steps are sized in
//! space (`size` on a 3D mesh: `tests/size3d_cli.rs`).

#[path = "support/cli.rs"]
#[allow(dead_code)]
mod cli;

use cli::{bad, ok, smartmesh};
use serde_json::Value;
use smartmesh_test_support::formats::public_fixture;

fn box_cyl() -> String {
    public_fixture("3d/box_cyl.v41_ascii.msh").display().to_string()
}

fn info_json(args: &[&str]) -> Value {
    serde_json::from_str(&ok(&smartmesh(args, None))).unwrap()
}

/// The curves' origins in `info --json`.
fn origins(j: &Value) -> Vec<String> {
    j["topology"]["curves"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c["origin"].as_str().unwrap().to_string())
        .collect()
}

/// box_cyl: every surface one patch; Walls bounded by four closed loops (the inlet and
/// outlet squares, the two circles), the cylinder by two; the Walls' box edges and 21
/// edges of the coarse cylinder (up to 47.2°) are ridges at 45°, the cylinder's no more
/// at 50°; a ridge angle outside [0, 180] is bad input.
#[test]
fn info_reports_patches_loops_and_ridges_of_box_cyl() {
    smartmesh_test_support::require_public_fixtures!();
    let f = box_cyl();
    let j = info_json(&["info", "--json", &f]);
    let t = &j["topology"];
    assert_eq!(t["ridge_angle_deg"], 45.0);
    let faces = t["faces"].as_array().unwrap();
    assert!(faces.iter().all(|f| f["patches"] == 1), "{t}");
    let loops = |tag: i64| -> Vec<(u64, bool)> {
        let f = faces.iter().find(|f| f["tag"] == tag).unwrap();
        f["boundary_loops"]
            .as_array()
            .unwrap()
            .iter()
            .map(|l| (l["edges"].as_u64().unwrap(), l["closed"].as_bool().unwrap()))
            .collect()
    };
    let mut walls = loops(3);
    walls.sort_unstable();
    assert_eq!(walls, [(8, true), (8, true), (24, true), (24, true)]);
    assert_eq!(loops(1), [(24, true)]);
    assert_eq!(origins(&j), ["tagged", "derived", "derived", "ridge", "ridge"]);
    let ridge_edges: Vec<u64> = t["curves"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|c| c["origin"] == "ridge")
        .map(|c| c["edges"].as_u64().unwrap())
        .collect();
    assert_eq!(ridge_edges, [48, 21]);
    let j50 = info_json(&["info", "--json", "--ridge-angle", "50", &f]);
    assert_eq!(origins(&j50), ["tagged", "derived", "derived", "ridge"]);
    let text = ok(&smartmesh(&["info", &f], None));
    assert!(
        text.contains("surface 3 \"Walls\"                714 cells, area 7.77373, 1 patch, 4 boundary loops on curves c1, c2, c3"),
        "{text}"
    );
    assert!(text.contains("ridge (normals turn by more than 45°)"), "{text}");
    for a in ["200", "-1", "nan"] {
        let e = bad(&smartmesh(&["info", &format!("--ridge-angle={a}"), &f], None));
        assert!(e.contains("expected an angle in degrees in [0, 180]"), "{e}");
    }
}

/// A 2D mesh's JSON has none of the 3D keys: it is what it was.
#[test]
fn a_2d_mesh_has_no_3d_topology_keys() {
    let f = cli::fixture("cylinder.msh");
    let j = info_json(&["info", "--json", f.to_str().unwrap()]);
    let t = &j["topology"];
    assert!(t.get("ridge_angle_deg").is_none() && t.get("file_ridge_edges").is_none(), "{t}");
    assert!(t["faces"][0].get("patches").is_none(), "{t}");
    assert!(t["curves"][0].get("origin").is_none(), "{t}");
}

const RECIPE: &str = r#"
[regions]
cyl = ["Cylinder"]
fluid = ["Fluid"]
walls = [3]
edges = ["CylinderEdges"]

[functions.lin]
kind = "distance"
size_at_source = 0.01
size_at_max_distance = 0.1
max_distance = 0.3
exponent = 1.0

[[algorithms]]
type = "uniform"
regions = ["fluid"]
size = 0.1

[[algorithms]]
type = "distance_to_border"
regions = ["cyl", "edges"]
perpendicular = "lin"
parallel = "lin"
"#;

/// `recipe check` on box_cyl: the regions resolve to a volume, surfaces and a curve with
/// their counts (the cylinder's 118 triangles and 67 vertices, the fluid's 2187 tetrahedra
/// on 634 vertices), exit 0, and it says which steps are sized in space.
#[test]
fn recipe_check_resolves_surfaces_and_volumes_and_says_what_is_sized() {
    smartmesh_test_support::require_public_fixtures!();
    let dir = tempfile::tempdir().unwrap();
    let recipe = dir.path().join("r.toml");
    std::fs::write(&recipe, RECIPE).unwrap();
    let (r, f) = (recipe.to_str().unwrap(), box_cyl());
    let j = info_json(&["recipe", "check", "--json", r, &f]);
    let region = |name: &str| {
        j["regions"].as_array().unwrap().iter().find(|x| x["name"] == name).unwrap().clone()
    };
    let (cyl, fluid, walls, edges) =
        (region("cyl"), region("fluid"), region("walls"), region("edges"));
    assert_eq!((cyl["dimension"].as_u64(), cyl["cells"].as_u64()), (Some(2), Some(118)));
    assert_eq!(cyl["vertices"], 67);
    assert_eq!((fluid["dimension"].as_u64(), fluid["tags"][0].as_i64()), (Some(3), Some(10)));
    assert_eq!((fluid["cells"].as_u64(), fluid["vertices"].as_u64()), (Some(2187), Some(634)));
    assert_eq!(
        (walls["dimension"].as_u64(), walls["used_by"].as_array().unwrap().len()),
        (Some(2), 0)
    );
    assert_eq!((edges["dimension"].as_u64(), edges["edges"].as_u64()), (Some(1), Some(16)));
    assert!(j["sizing"].as_str().unwrap().contains("sized in space"), "{j}");
    assert_eq!(j["algorithms"][0]["in_space"], true);
    assert_eq!(j["algorithms"][0]["volumes"], 1);
    let text = ok(&smartmesh(&["recipe", "check", r, &f], None));
    assert!(
        text.contains("fluid            1 volume: tags 10 (\"Fluid\"); 634 vertices, 2187 cells"),
        "{text}"
    );
    assert!(text.contains("cyl              1 surface: tags 4 (\"Cylinder\")"), "{text}");
}
