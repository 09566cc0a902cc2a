//! `smartmesh size` on the public box-cylinder (tetrahedra) with a recipe of a vortex
//! line (DISTANCE_TO_IMAGINARY_POLYLINE with (x, y, z) points) and a wake sheet
//! (DISTANCE_TO_IMAGINARY_SURFACE, an STL file beside the recipe): `recipe check` says
//! both steps are sized in space, the field's sizes near the sheet are those of the
//! recipe's functions, `mmg3d_O3` adapts the mesh to the written `.sol` (finer at the
//! sheet), and a missing or malformed sheet is refused with its path (exit 2).
//!
//! REGIONS on both steps in space: on a box of two volumes meshed by Gmsh, only the
//! vertices of the named volume (or surface) are sized, as without REGIONS, and `recipe
//! check` reports what the region resolved to.
//!
//! Needs the public fixtures (skipped with a message without them, mandatory under CI),
//! `mmg3d_O3` for the remeshing (skipped without it), and Gmsh's Python API for the
//! two-volume box (skipped without it, mandatory under CI).

use std::path::Path;

use smartmesh::formats::{read_path, CellKind, TaggedMesh};
use smartmesh_test_support::formats::{python_with, run_python};
use smartmesh_test_support::require_public_fixtures;
use smartmesh_test_support::space::{box_cyl, size_then_mmg3d};

#[path = "support/cli.rs"]
mod support;
use support::{program, run, streams, BIN};

/// The wake sheet behind the cylinder, tilted: y = 0.5 + 0.05 (x − 0.85), x in
/// [0.85, 1.95], z in [0.05, 0.95], as two triangles.
const SHEET: [[f64; 3]; 4] =
    [[0.85, 0.5, 0.05], [1.95, 0.555, 0.05], [1.95, 0.555, 0.95], [0.85, 0.5, 0.95]];

fn write_sheet_stl(path: &Path) {
    let v = |p: [f64; 3]| format!("   vertex {} {} {}\n", p[0], p[1], p[2]);
    let mut s = String::from("solid wake\n");
    for t in [[0, 1, 2], [0, 2, 3]] {
        s += " facet normal 0 0 0\n  outer loop\n";
        for k in t {
            s += &v(SHEET[k]);
        }
        s += "  endloop\n endfacet\n";
    }
    s += "endsolid wake\n";
    std::fs::write(path, s).unwrap();
}

/// Distance from `p` to the sheet's plane, and whether its foot lies on the sheet.
fn to_sheet(p: [f64; 3]) -> (f64, bool) {
    let n: [f64; 3] = [-0.05, 1.0, 0.0];
    let l = (n[0] * n[0] + n[1] * n[1]).sqrt();
    let d = ((p[0] - 0.85) * n[0] + (p[1] - 0.5) * n[1]) / l;
    let inside = (0.9..=1.9).contains(&p[0]) && (0.1..=0.9).contains(&p[2]);
    (d.abs(), inside)
}

const RECIPE: &str = r#"
[global]
h_max = 0.15

[polylines]
Vortex = [[0.3, 0.25, 0.7], [1.0, 0.22, 0.72], [1.9, 0.2, 0.75]]

[functions.core]
kind = "distance"
size_at_source = 0.03
size_at_max_distance = 0.15
max_distance = 0.2
exponent = 1.0

[functions.along]
kind = "distance"
size_at_source = 0.1
size_at_max_distance = 0.15
max_distance = 1.0
exponent = 1.0

[functions.away]
kind = "projection"
size_at_max_distance = 0.15
max_distance = 0.2
exponent = 1.0

[functions.perp]
kind = "distance"
size_at_source = 0.02
size_at_max_distance = 0.15
max_distance = 0.2
exponent = 1.0

[functions.par]
kind = "distance"
size_at_source = 0.08
size_at_max_distance = 0.15
max_distance = 0.2
exponent = 1.0

[[algorithms]]
type = "distance_to_imaginary_polyline"
perpendicular = "core"
polyline_distance = "along"
projection = "away"
polyline = "Vortex"

[[algorithms]]
type = "distance_to_imaginary_surface"
perpendicular = "perp"
parallel = "par"
file = "wake.stl"
"#;

/// Vertices within 0.05 of the sheet, over it.
fn near_sheet(mesh: &TaggedMesh) -> usize {
    mesh.points
        .iter()
        .filter(|p| {
            let (d, inside) = to_sheet(**p);
            inside && d < 0.05
        })
        .count()
}

#[test]
fn a_vortex_line_and_a_wake_sheet_size_box_cyl_and_mmg3d_follows() {
    require_public_fixtures!();
    let dir = tempfile::tempdir().unwrap();
    write_sheet_stl(&dir.path().join("wake.stl"));
    let recipe = dir.path().join("wake.toml");
    std::fs::write(&recipe, RECIPE).unwrap();
    let r = recipe.to_str().unwrap();
    let o = run(&["recipe", "check", "--json", r, &box_cyl()]);
    assert_eq!(o.status.code(), Some(0), "{}", streams(&o));
    let j: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(j["algorithms"][0]["in_space"], true);
    assert_eq!(j["algorithms"][1]["in_space"], true);
    assert_eq!(j["sizing"], "every step is sized in space");

    let vtu = dir.path().join("f.vtu");
    let o = run(&["size", &box_cyl(), "--recipe", r, "-o", vtu.to_str().unwrap(), "--json"]);
    assert_eq!(o.status.code(), Some(0), "{}", streams(&o));
    let m = read_path(&vtu, None).unwrap();
    let h3 = &m.point_data["h3"].values;
    let mut near = 0;
    for (p, &h) in m.points.iter().zip(h3) {
        let (d, inside) = to_sheet(*p);
        if inside && d < 0.2 {
            // The sheet's perpendicular size at d; the vortex step can only shrink it.
            let perp = 0.02 + (0.15 - 0.02) * d / 0.2;
            assert!(h <= perp * (1.0 + 1e-9), "{p:?}: h3 {h} above {perp}");
            near += 1;
        }
    }
    assert!(near > 30, "{near}");

    if program("mmg3d_O3").is_none() {
        return;
    }
    let adapted = size_then_mmg3d(BIN, dir.path(), &recipe, "f.sol");
    let start = read_path(Path::new(&box_cyl()), None).unwrap();
    assert!(adapted.num_cells_of(CellKind::Tetra) > 2 * start.num_cells_of(CellKind::Tetra));
    let (before, after) = (near_sheet(&start), near_sheet(&adapted));
    assert!(after > 4 * before, "vertices near the sheet: {before} then {after}");
}

#[test]
fn a_missing_or_malformed_sheet_is_refused_with_its_path() {
    require_public_fixtures!();
    let dir = tempfile::tempdir().unwrap();
    let recipe = dir.path().join("wake.toml");
    std::fs::write(&recipe, RECIPE).unwrap();
    let r = recipe.to_str().unwrap();
    let sol = dir.path().join("f.sol");
    for (body, why) in [
        (None, "No such file"),
        (Some("solid w\n facet normal 0 0 1\n  outer loop\n   vertex 1 2\n"), "wake.stl:5"),
    ] {
        if let Some(b) = body {
            std::fs::write(dir.path().join("wake.stl"), b).unwrap();
        }
        for args in [
            vec!["size", &box_cyl(), "--recipe", r, "-o", sol.to_str().unwrap()],
            vec!["recipe", "check", r, &box_cyl()],
        ] {
            let o = run(&args);
            assert_eq!(o.status.code(), Some(2), "{}", streams(&o));
            let e = String::from_utf8_lossy(&o.stderr);
            assert!(e.contains("wake.stl") && e.contains(why) && e.contains("wake.toml:"), "{e}");
        }
        assert!(!sol.exists());
    }
}

/// Gmsh: the boxes [0, 1] × [0, 1]² ("Upstream", volume tag 1) and [1, 2] × [0, 1]²
/// ("Downstream", 2) sharing the face x = 1 ("Interface"), tetrahedra of size 0.25.
const TWO_VOLUMES: &str = r#"
import gmsh, sys
gmsh.initialize()
gmsh.option.setNumber("General.Terminal", 0)
gmsh.model.occ.addBox(0, 0, 0, 1, 1, 1)
gmsh.model.occ.addBox(1, 0, 0, 1, 1, 1)
gmsh.model.occ.fragment([(3, 1)], [(3, 2)])
gmsh.model.occ.synchronize()
for tag, name in [(1, "Upstream"), (2, "Downstream")]:
    gmsh.model.setPhysicalName(3, gmsh.model.addPhysicalGroup(3, [tag]), name)
faces = gmsh.model.getEntitiesInBoundingBox(0.9, -0.1, -0.1, 1.1, 1.1, 1.1, 2)
p = gmsh.model.addPhysicalGroup(2, [t for _, t in faces])
gmsh.model.setPhysicalName(2, p, "Interface")
gmsh.option.setNumber("Mesh.MeshSizeMax", 0.25)
gmsh.model.mesh.generate(3)
gmsh.write(sys.argv[1])
gmsh.finalize()
"#;

/// A vortex along x through both volumes and a sheet at z = 0.3 across both, each
/// step with `REGIONS = ["zone"]` (`zone` names `ENTITY`) unless `regions` is false.
fn two_volume_recipe(entity: &str, regions: bool) -> String {
    let within = if regions { "regions = [\"zone\"]" } else { "" };
    let zone = if regions { format!("[regions]\nzone = [\"{entity}\"]\n") } else { String::new() };
    format!(
        r#"
[global]
h_max = 0.5

{zone}
[polylines]
Vortex = [[0.2, 0.5, 0.6], [1.8, 0.5, 0.62]]

[functions.core]
kind = "distance"
size_at_source = 0.02
size_at_max_distance = 0.2
max_distance = 0.3
exponent = 1.0

[functions.along]
kind = "distance"
size_at_source = 0.1
size_at_max_distance = 0.2
max_distance = 0.3
exponent = 1.0

[functions.away]
kind = "projection"
size_at_max_distance = 0.2
max_distance = 0.3
exponent = 1.0

[[algorithms]]
type = "distance_to_imaginary_polyline"
perpendicular = "core"
polyline_distance = "along"
projection = "away"
polyline = "Vortex"
{within}

[[algorithms]]
type = "distance_to_imaginary_surface"
perpendicular = "core"
parallel = "along"
file = "wake.stl"
{within}
"#
    )
}

/// The wake of the two-volume box: z = 0.3 over x in [0.1, 1.9], y in [0.05, 0.95].
fn write_flat_wake(path: &Path) {
    let c = [[0.1, 0.05], [1.9, 0.05], [1.9, 0.95], [0.1, 0.95]];
    let mut s = String::from("solid wake\n");
    for t in [[0, 1, 2], [0, 2, 3]] {
        s += " facet normal 0 0 1\n  outer loop\n";
        for k in t {
            s += &format!("   vertex {} {} 0.3\n", c[k][0], c[k][1]);
        }
        s += "  endloop\n endfacet\n";
    }
    std::fs::write(path, s + "endsolid wake\n").unwrap();
}

/// The `.vtu` field of `recipe` on `mesh`: each vertex's point and sizes h1, h2, h3.
fn sized(dir: &Path, mesh: &str, recipe: &str, name: &str) -> Vec<([f64; 3], [f64; 3])> {
    let path = dir.join(format!("{name}.toml"));
    std::fs::write(&path, recipe).unwrap();
    let vtu = dir.join(format!("{name}.vtu"));
    let o = run(&["size", mesh, "--recipe", path.to_str().unwrap(), "-o", vtu.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(0), "{}", streams(&o));
    let m = read_path(&vtu, None).unwrap();
    let h = |k: &str| m.point_data[k].values.clone();
    let (h1, h2, h3) = (h("h1"), h("h2"), h("h3"));
    (0..m.points.len()).map(|i| (m.points[i], [h1[i], h2[i], h3[i]])).collect()
}

#[test]
fn regions_keep_a_vortex_and_a_wake_to_the_named_volume_or_surface() {
    let Some(py) = python_with(&["gmsh"]) else { return };
    let dir = tempfile::tempdir().unwrap();
    let mesh = dir.path().join("two.msh");
    let mesh = mesh.to_str().unwrap();
    run_python(&py, TWO_VOLUMES, &[mesh]);
    write_flat_wake(&dir.path().join("wake.stl"));
    let everywhere = sized(dir.path(), mesh, &two_volume_recipe("", false), "all");
    for (entity, dimension, inside) in [
        ("Downstream", 3, (|x: f64| x >= 1.0 - 1e-9) as fn(f64) -> bool),
        ("Interface", 2, |x: f64| (x - 1.0).abs() < 1e-9),
    ] {
        let recipe = two_volume_recipe(entity, true);
        let path = dir.path().join(format!("{entity}.toml"));
        std::fs::write(&path, &recipe).unwrap();
        let o = run(&["recipe", "check", "--json", path.to_str().unwrap(), mesh]);
        assert_eq!(o.status.code(), Some(0), "{}", streams(&o));
        let j: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        assert_eq!(j["regions"][0]["dimension"], dimension, "{j}");
        assert_eq!(j["regions"][0]["entity_names"][0], entity, "{j}");
        assert_eq!(j["sizing"], "every step is sized in space");
        let kind = if dimension == 3 { "volumes" } else { "faces" };
        for k in 0..2 {
            assert_eq!(j["algorithms"][k][kind], 1, "{j}");
        }
        let within = sized(dir.path(), mesh, &recipe, entity);
        let (mut kept, mut cut) = (0, 0);
        for ((p, h), (q, g)) in within.iter().zip(&everywhere) {
            assert_eq!(p, q);
            if inside(p[0]) {
                // Sized as without REGIONS.
                assert!(h.iter().zip(g).all(|(a, b)| (a - b).abs() <= 1e-12 * b), "{p:?}");
                kept += usize::from(g[2] < 0.5);
            } else {
                assert_eq!(*h, [0.5; 3], "{p:?}: sized outside {entity}");
                cut += usize::from(g[2] < 0.5);
            }
        }
        assert!(kept > 5 && cut > 20, "{entity}: {kept} sized inside, {cut} left out");
    }
}
