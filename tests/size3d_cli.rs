//! `smartmesh size` on meshes in space: the public box-cylinder (tetrahedra, named
//! surfaces and volume) sized by recipes whose steps work in space, the field written in
//! every metric format and read back apart from the library (the `.sol` by `mmg3d_O3`
//! through `remesh`, the `.vtu` by our reader and its sizes checked here), and the
//! refusal of what is not sized in space.
//!
//! Needs the public fixtures (skipped with a message without them, mandatory under CI),
//! and `mmg3d_O3` for the remeshing (skipped without it).

use smartmesh::formats::{read_path, CellKind};
use smartmesh_test_support::formats::public_fixture;
use smartmesh_test_support::require_public_fixtures;
use smartmesh_test_support::space::{
    box_cyl, cylinder_wall_recipe, edge_lengths, edges, median, metric_length, size_then_mmg3d,
};

#[path = "support/cli.rs"]
mod support;
use support::{program, run, streams, BIN};

/// UNIFORM on the cylinder surface and on the fluid volume, h_max 0.15.
const UNIFORM: &str = r#"
[global]
h_max = 0.15

[regions]
cyl = ["Cylinder"]
fluid = ["Fluid"]

[[algorithms]]
type = "uniform"
regions = ["cyl"]
size = 0.05

[[algorithms]]
type = "uniform"
regions = ["fluid"]
size = 0.12
"#;

/// The sizes h1 ≥ h2 ≥ h3 at each vertex of a `.vtu` the command wrote.
fn vtu_sizes(path: &std::path::Path) -> Vec<[f64; 3]> {
    let m = read_path(path, None).unwrap();
    let h = |k: &str| m.point_data[k].values.clone();
    let (h1, h2, h3) = (h("h1"), h("h2"), h("h3"));
    (0..m.points.len()).map(|i| [h1[i], h2[i], h3[i]]).collect()
}

/// UNIFORM in space: the cylinder's 67 vertices get 0.05, every other vertex 0.12 (the
/// volume's size, below h_max); every format is written, the `.sol` with `Dimension 3`
/// and one tensor of type 3 per vertex; the JSON summary counts the vertices reached.
#[test]
fn size_writes_a_uniform_field_on_a_tetrahedral_mesh_in_every_format() {
    require_public_fixtures!();
    let dir = tempfile::tempdir().unwrap();
    let recipe = dir.path().join("u.toml");
    std::fs::write(&recipe, UNIFORM).unwrap();
    let mesh = read_path(std::path::Path::new(&box_cyl()), None).unwrap();
    for ext in ["sol", "solb", "msh", "pos", "vtu", "vtk", "mesh"] {
        let out = dir.path().join(format!("f.{ext}"));
        let o = run(&[
            "size",
            &box_cyl(),
            "--recipe",
            recipe.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--json",
        ]);
        assert_eq!(o.status.code(), Some(0), "{ext}: {}", streams(&o));
        assert!(out.exists(), "{ext}");
        let j: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        assert_eq!(j["vertices"], 634);
        assert_eq!(j["vertices_reached"], 634);
        assert_eq!(j["smallest_size"], 0.05);
        assert_eq!(j["largest_size"], 0.12);
    }
    let sol = std::fs::read_to_string(dir.path().join("f.sol")).unwrap();
    let words: Vec<&str> = sol.split_whitespace().collect();
    assert!(words.windows(2).any(|w| w == ["Dimension", "3"]), "{sol:.200}");
    let at = words.iter().position(|w| *w == "SolAtVertices").unwrap();
    assert_eq!(words[at + 1..at + 4], ["634", "1", "3"]);
    let sizes = vtu_sizes(&dir.path().join("f.vtu"));
    let on_cylinder = |p: [f64; 3]| ((p[0] - 0.6).hypot(p[1] - 0.5) - 0.2).abs() < 1e-9;
    let mut cyl = 0;
    for (p, h) in mesh.points.iter().zip(&sizes) {
        let want = if on_cylinder(*p) { 0.05 } else { 0.12 };
        cyl += usize::from(on_cylinder(*p));
        assert!(h.iter().all(|x| (x - want).abs() < 1e-12), "{p:?}: {h:?}");
    }
    assert_eq!(cyl, 67);
}

/// mmg3d_O3 adapts box_cyl to the `.sol` that `size` wrote (through `remesh`): finer
/// than the start, every tetrahedron positive.
#[test]
fn mmg3d_takes_the_sol_size_writes() {
    require_public_fixtures!();
    if program("mmg3d_O3").is_none() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let recipe = dir.path().join("u.toml");
    std::fs::write(&recipe, UNIFORM).unwrap();
    let mesh = size_then_mmg3d(BIN, dir.path(), &recipe, "f.sol");
    assert!(mesh.num_cells_of(CellKind::Tetra) > 2187, "{}", mesh.num_cells_of(CellKind::Tetra));
}

/// The wall layer's metric at `p`, written here from the exact cylinder (axis along z
/// through (0.6, 0.5), radius 0.2): radial size perp(d), the others par(d).
fn wall_metric(p: [f64; 3]) -> [[f64; 3]; 3] {
    let (dx, dy) = (p[0] - 0.6, p[1] - 0.5);
    let r = dx.hypot(dy);
    let d = (r - 0.2).max(0.0);
    let lin = |a: f64, b: f64| if d >= 0.3 { b } else { a + (b - a) * d / 0.3 };
    let (hn, ht) = (lin(0.02, 0.15), lin(0.06, 0.15));
    let n = [dx / r, dy / r, 0.0];
    let mut m = [[0.0; 3]; 3];
    for (i, row) in m.iter_mut().enumerate() {
        for (j, v) in row.iter_mut().enumerate() {
            let nn = n[i] * n[j];
            *v = nn / (hn * hn) + (f64::from(u8::from(i == j)) - nn) / (ht * ht);
        }
    }
    m
}

/// DISTANCE_TO_BORDER on the cylinder of box_cyl: the `.vtu` sizes are the wall layer's
/// (checked here against the exact cylinder, to the faceting of its 118 triangles);
/// `mmg3d_O3` adapts box_cyl to
/// the `.sol` (through `remesh`) and the median metric length of the result's edges,
/// measured here in the metric of the exact cylinder, is in [0.7, 1.3].
#[test]
fn a_wall_layer_on_the_cylinder_is_sized_and_mmg3d_follows_it() {
    require_public_fixtures!();
    let dir = tempfile::tempdir().unwrap();
    let recipe = dir.path().join("w.toml");
    std::fs::write(&recipe, cylinder_wall_recipe("")).unwrap();
    let vtu = dir.path().join("w.vtu");
    let o = run(&[
        "size",
        &box_cyl(),
        "--recipe",
        recipe.to_str().unwrap(),
        "-o",
        vtu.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", streams(&o));
    let mesh = read_path(std::path::Path::new(&box_cyl()), None).unwrap();
    let field = read_path(&vtu, None).unwrap();
    let axis1 = &field.point_data["axis1"];
    for (v, p) in mesh.points.iter().enumerate() {
        let h3 = field.point_data["h3"].values[v];
        let h1 = field.point_data["h1"].values[v];
        let d = ((p[0] - 0.6).hypot(p[1] - 0.5) - 0.2).max(0.0);
        // The facets lie inside the cylinder, their corners on it 8 to a turn or fewer:
        // the distance to them exceeds the exact one by at most 0.2 (1 − cos(π/6)) < 0.03
        // (a triangle spans at most 60° of the turn).
        let lin = |a: f64, b: f64, d: f64| if d >= 0.3 { b } else { a + (b - a) * d / 0.3 };
        let within = |h: f64, a: f64, b: f64| {
            lin(a, b, d) * (1.0 - 1e-9) <= h && h <= lin(a, b, d + 0.03) * (1.0 + 1e-9)
        };
        assert!(within(h3, 0.02, 0.15), "{p:?}: h3 {h3}");
        assert!(within(h1, 0.06, 0.15), "{p:?}: h1 {h1}");
        // The largest size lies in the tangent plane: no radial part where anisotropic.
        if h1 > 1.5 * h3 {
            let a = axis1.item(v);
            let radial = (a[0] * (p[0] - 0.6) + a[1] * (p[1] - 0.5)).abs() / (h1 * (d + 0.2));
            assert!(radial < 0.2, "{p:?}: axis1 {a:?}");
        }
    }
    if program("mmg3d_O3").is_none() {
        return;
    }
    let adapted = size_then_mmg3d(BIN, dir.path(), &recipe, "w.sol");
    let tetra_edges = edges(&adapted, CellKind::Tetra);
    let l = edge_lengths(&adapted, &tetra_edges, |a, b| metric_length(a, b, wall_metric));
    let median = median(&l);
    eprintln!(
        "box_cyl wall layer: {} tets after mmg3d, median metric length {median:.3}",
        adapted.num_cells_of(CellKind::Tetra)
    );
    assert!((0.7..=1.3).contains(&median), "median metric length {median}");
}

/// A recipe whose second step does not size in space (DISTANCE_TO_IMAGINARY_POLYLINE
/// with a polyline of two coordinates: there is no implied z): `recipe check` says so
/// per step, and `size` refuses the mesh naming the step and why (exit 2), writing
/// nothing.
const NOT_IN_SPACE: &str = r#"
[regions]
cyl = ["Cylinder"]

[polylines]
Wake = [[0.8, 0.5], [2.0, 0.5]]

[functions.D]
kind = "distance"
size_at_source = 0.02
size_at_max_distance = 0.15
max_distance = 0.3
exponent = 1.0

[functions.P]
kind = "projection"
size_at_max_distance = 0.15
max_distance = 0.3
exponent = 1.0

[[algorithms]]
type = "uniform"
regions = ["cyl"]
size = 0.05

[[algorithms]]
type = "distance_to_imaginary_polyline"
perpendicular = "D"
polyline_distance = "D"
projection = "P"
polyline = "Wake"
"#;

#[test]
fn a_step_not_sized_in_space_is_said_and_refused() {
    require_public_fixtures!();
    let dir = tempfile::tempdir().unwrap();
    let recipe = dir.path().join("n.toml");
    std::fs::write(&recipe, NOT_IN_SPACE).unwrap();
    let r = recipe.to_str().unwrap();
    let o = run(&["recipe", "check", "--json", r, &box_cyl()]);
    assert_eq!(o.status.code(), Some(0), "{}", streams(&o));
    let j: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(j["algorithms"][0]["in_space"], true);
    assert_eq!(j["algorithms"][1]["in_space"], false);
    let said = j["sizing"].as_str().unwrap();
    assert!(
        said.contains("steps 1 (UNIFORM)")
            && said.contains("steps 2 (DISTANCE_TO_IMAGINARY_POLYLINE)"),
        "{said}"
    );
    let out = dir.path().join("n.sol");
    let o = run(&["size", &box_cyl(), "--recipe", r, "-o", out.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2), "{}", streams(&o));
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(
        e.contains("step 1")
            && e.contains("DISTANCE_TO_IMAGINARY_POLYLINE")
            && e.contains("the polyline's points have 2 coordinates, but the mesh is in space"),
        "{e}"
    );
    assert!(!out.exists());
}

/// DISTANCE_TO_POINT on a region naming a surface: its sources are vertices (points, or a
/// curve's vertices), so in space a surface is refused by `recipe check` and `size` alike,
/// at the recipe's line, rather than accepted by the check and refused by `size`; a curve
/// is sized (its vertices as points).
#[test]
fn distance_to_point_on_a_surface_is_refused_at_its_line_in_space() {
    require_public_fixtures!();
    let dir = tempfile::tempdir().unwrap();
    let recipe = |entity: &str| {
        format!(
            "[global]\nh_max = 0.5\n\n[regions]\nR = [\"{entity}\"]\n\n[functions.D]\nkind = \"distance\"\nsize_at_source = 0.05\nsize_at_max_distance = 0.5\nmax_distance = 0.5\nexponent = 1.0\n\n[[algorithms]]\ntype = \"distance_to_point\"\nfunction = \"D\"\nregions = [\"R\"]\n"
        )
    };
    let path = dir.path().join("p.toml");
    let out = dir.path().join("p.sol");
    std::fs::write(&path, recipe("Cylinder")).unwrap();
    let r = path.to_str().unwrap();
    for args in [
        vec!["recipe", "check", r, &box_cyl()],
        vec!["size", &box_cyl(), "--recipe", r, "-o", out.to_str().unwrap()],
    ] {
        let o = run(&args);
        assert_eq!(o.status.code(), Some(2), "{}", streams(&o));
        let e = String::from_utf8_lossy(&o.stderr);
        assert!(
            e.contains("p.toml:17") && e.contains("DISTANCE_TO_POINT takes points or curves"),
            "{e}"
        );
    }
    assert!(!out.exists());
    std::fs::write(&path, recipe("CylinderEdges")).unwrap();
    let o = run(&["recipe", "check", "--json", r, &box_cyl()]);
    assert_eq!(o.status.code(), Some(0), "{}", streams(&o));
    let j: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(j["regions"][0]["dimension"], 1, "{j}");
    let o = run(&["size", &box_cyl(), "--recipe", r, "-o", out.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(0), "{}", streams(&o));
}

/// `recipe check` takes a surface mesh in space (MMG's box-cylinder surface, triangles off
/// one plane) as `size` does: regions resolved on its 3D topology (tag 4, the cylinder, a
/// surface), every step said sized in space, exit 0; `size` then sizes it. A
/// SOLUTION_HESSIAN step, which needs volume cells, is said not sized there.
#[test]
fn recipe_check_takes_a_surface_mesh_in_space_as_size_does() {
    require_public_fixtures!();
    let surface = public_fixture("3d/box_cyl_surf_input.mesh").display().to_string();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("s.toml");
    std::fs::write(
        &path,
        "[global]\nh_max = 0.5\n\n[regions]\nCyl = [4]\n\n[polylines]\nV = [[0.1, 0.5, 0.5], [1.9, 0.5, 0.5]]\n\n[functions.D]\nkind = \"distance\"\nsize_at_source = 0.05\nsize_at_max_distance = 0.5\nmax_distance = 0.5\nexponent = 1.0\n\n[functions.P]\nkind = \"projection\"\nsize_at_max_distance = 0.5\nmax_distance = 0.2\nexponent = 1.0\n\n[[algorithms]]\ntype = \"distance_to_border\"\nperpendicular = \"D\"\nparallel = \"D\"\nregions = [\"Cyl\"]\n\n[[algorithms]]\ntype = \"distance_to_imaginary_polyline\"\nperpendicular = \"D\"\npolyline_distance = \"D\"\nprojection = \"P\"\npolyline = \"V\"\n",
    )
    .unwrap();
    let r = path.to_str().unwrap();
    let o = run(&["recipe", "check", "--json", r, &surface]);
    assert_eq!(o.status.code(), Some(0), "{}", streams(&o));
    let j: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(j["regions"][0]["dimension"], 2, "{j}");
    assert_eq!(j["regions"][0]["vertices"], 67, "{j}");
    assert_eq!(j["algorithms"][0]["faces"], 1, "{j}");
    assert_eq!(j["algorithms"][1]["in_space"], true, "{j}");
    assert_eq!(j["sizing"], "every step is sized in space");
    let out = dir.path().join("s.sol");
    let o = run(&["size", &surface, "--recipe", r, "-o", out.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(0), "{}", streams(&o));
    // SOLUTION_HESSIAN needs volume cells: not sized on a surface alone, and said so.
    let hessian = dir.path().join("h.toml");
    std::fs::write(
        &hessian,
        "[[algorithms]]\ntype = \"solution_hessian\"\nfield = \"u\"\ncomplexity = 1000\n",
    )
    .unwrap();
    let o = run(&["recipe", "check", "--json", hessian.to_str().unwrap(), &surface]);
    assert_eq!(o.status.code(), Some(0), "{}", streams(&o));
    let j: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(j["algorithms"][0]["in_space"], false, "{j}");
    assert!(j["sizing"].as_str().unwrap().contains("1 (SOLUTION_HESSIAN)"), "{j}");
}
