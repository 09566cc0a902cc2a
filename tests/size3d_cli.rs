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

#[path = "support/cli.rs"]
mod support;
use support::{program, run, streams};

fn box_cyl() -> String {
    public_fixture("3d/box_cyl.v41_ascii.msh").display().to_string()
}

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
    let sol = dir.path().join("f.sol");
    let o = run(&[
        "size",
        &box_cyl(),
        "--recipe",
        recipe.to_str().unwrap(),
        "-o",
        sol.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", streams(&o));
    let out = dir.path().join("adapted.msh");
    let o = run(&[
        "remesh",
        &box_cyl(),
        "--metric",
        sol.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--hgrad",
        "-1",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", streams(&o));
    let mesh = read_path(&out, None).unwrap();
    assert!(mesh.num_cells_of(CellKind::Tetra) > 2187, "{}", mesh.num_cells_of(CellKind::Tetra));
}
