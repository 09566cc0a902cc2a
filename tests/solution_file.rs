//! `--solution-file` takes a Gmsh data-only `.msh` (views without a mesh, as
//! `gmsh.view.write` or a solver writes it beside the mesh), as `--metric` does: node
//! tag t at vertex t − 1 of the mesh.

#[path = "support/cli.rs"]
#[allow(dead_code)]
mod cli;

use cli::{fixture, ok, smartmesh};
use smartmesh::formats::{read_path, write_path, DataArray, WriteOptions};

/// The field u = x² + 3y² on the cylinder fixture's vertices, given as a data-only
/// `.msh` and as a `.vtu` of the mesh with `u`: `size --solution-file` writes the same
/// metric from both; a data-only file that leaves a vertex out is refused, naming it.
#[test]
fn a_gmsh_data_only_view_is_a_solution_file() {
    let dir = tempfile::tempdir().unwrap();
    let mesh_path = fixture("cylinder.msh");
    let mut mesh = read_path(&mesh_path, None).unwrap();
    let u: Vec<f64> = mesh.points.iter().map(|p| p[0] * p[0] + 3.0 * p[1] * p[1]).collect();
    let view = |skip: Option<usize>| {
        let given: Vec<(usize, f64)> =
            u.iter().copied().enumerate().filter(|(i, _)| Some(*i) != skip).collect();
        let mut s = format!(
            "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$NodeData\n1\n\"u\"\n1\n0\n3\n0\n1\n{}\n",
            given.len()
        );
        for (i, v) in given {
            s += &format!("{} {v:?}\n", i + 1);
        }
        s + "$EndNodeData\n"
    };
    let data_only = dir.path().join("u.msh");
    std::fs::write(&data_only, view(None)).unwrap();
    mesh.point_data.insert("u".into(), DataArray::new(1, u.clone()));
    let with_u = dir.path().join("u.vtu");
    write_path(&with_u, &mesh, None, &WriteOptions::default()).unwrap();

    let size = |solution: &std::path::Path, out: &str| {
        let out = dir.path().join(out);
        let o = smartmesh(
            &[
                "size",
                mesh_path.to_str().unwrap(),
                "--solution-file",
                solution.to_str().unwrap(),
                "--field",
                "u",
                "--complexity",
                "300",
                "-o",
                out.to_str().unwrap(),
            ],
            None,
        );
        (o, out)
    };
    let (o, a) = size(&data_only, "a.sol");
    ok(&o);
    let (o, b) = size(&with_u, "b.sol");
    ok(&o);
    assert_eq!(std::fs::read(&a).unwrap(), std::fs::read(&b).unwrap());

    let holed = dir.path().join("holed.msh");
    std::fs::write(&holed, view(Some(7))).unwrap();
    let (o, _) = size(&holed, "c.sol");
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("holed.msh") && err.contains("vertex 7"), "{err}");
}
