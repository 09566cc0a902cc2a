//! CGNS (`.cgns`) reached by extension from the commands: `convert` both ways, `info`,
//! `adapt -o`, with what CGNS cannot hold in `dropped`; the file `adapt` writes passes
//! the CGNS library's `cgnscheck` where it is on PATH. A build without the `cgns`
//! feature refuses `.cgns` with exit 2, naming the feature and libhdf5 (and the rest
//! skips, saying so; `.ci/run` runs this file again with `--features cgns`).

#[path = "support/cli.rs"]
#[allow(dead_code)]
mod support;

use std::path::Path;

#[cfg(feature = "cgns")]
use support::ok;
use support::{bad, bundled, run};

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

#[cfg(not(feature = "cgns"))]
#[test]
fn without_the_feature_cgns_is_refused_with_exit_2_naming_the_feature() {
    let d = tempfile::tempdir().unwrap();
    let out = d.path().join("cyl.cgns");
    let err = bad(&run(&["convert", &bundled("cylinder.msh"), s(&out)]));
    assert!(err.contains("`cgns` feature") && err.contains("libhdf5"), "{err}");
    assert!(!out.exists());
    std::fs::write(&out, b"\x89HDF\r\n\x1a\nnot much more").unwrap();
    let err = bad(&run(&["info", s(&out)]));
    assert!(err.contains("`cgns` feature"), "{err}");
    smartmesh_test_support::skip::skip("the CGNS commands need `--features cgns` (and libhdf5)");
}

#[cfg(feature = "cgns")]
fn repo(path: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(path).display().to_string()
}

#[cfg(feature = "cgns")]
#[test]
fn convert_and_info_reach_cgns_by_extension_with_names_and_dropped() {
    let d = tempfile::tempdir().unwrap();
    let cgns = d.path().join("cyl.cgns");
    let o = ok(&run(&["convert", &bundled("cylinder.msh"), s(&cgns), "--json"]));
    let j: serde_json::Value = serde_json::from_str(&o).unwrap();
    assert!(j["dropped"].is_array(), "{o}");
    let info = ok(&run(&["info", s(&cgns)]));
    assert!(info.contains("1148") && info.contains("Cylinder"), "{info}");
    // And back to Gmsh, the same counts and names.
    let back = d.path().join("back.msh");
    ok(&run(&["convert", s(&cgns), s(&back)]));
    let a = smartmesh::formats::read_path(Path::new(&bundled("cylinder.msh")), None).unwrap();
    let b = smartmesh::formats::read_path(&back, None).unwrap();
    assert_eq!(a.points.len(), b.points.len());
    assert_eq!(a.num_cells(), b.num_cells());
    for (k, name) in &a.tag_names {
        if a.cells().any(|c| (c.0.dim(), c.2) == *k) {
            assert_eq!(b.tag_names.get(k), Some(name), "{k:?}");
        }
    }
    // A file that is no CGNS: exit 2 naming it.
    let junk = d.path().join("junk.cgns");
    std::fs::write(&junk, b"junk").unwrap();
    let err = bad(&run(&["info", s(&junk)]));
    assert!(err.contains("junk.cgns") && err.contains("HDF5"), "{err}");
}

#[cfg(feature = "cgns")]
#[test]
fn adapt_writes_its_best_mesh_as_cgns_that_cgnscheck_accepts() {
    let d = tempfile::tempdir().unwrap();
    let out = d.path().join("a.cgns");
    ok(&run(&[
        "adapt",
        &bundled("cylinder.msh"),
        "--recipe",
        &repo("fixtures/cylinder.toml"),
        "--max-iterations",
        "2",
        "-o",
        s(&out),
    ]));
    let mesh = smartmesh::formats::read_path(&out, None).unwrap();
    assert!(mesh.num_cells_of(smartmesh::formats::CellKind::Triangle) > 100);
    assert!(mesh.tag_names.values().any(|n| n == "Cylinder"), "{:?}", mesh.tag_names);
    assert!(d.path().join("a.history.json").is_file());
    ok(&run(&["info", s(&out)]));
    let Some(check) = support::program("cgnscheck") else { return };
    let o = std::process::Command::new(check).arg(&out).output().unwrap();
    let text =
        String::from_utf8_lossy(&o.stdout).into_owned() + &String::from_utf8_lossy(&o.stderr);
    assert!(
        o.status.success() && !text.contains("ERROR") && text.contains("checking complete"),
        "{text}"
    );
}

#[cfg(feature = "cgns")]
#[test]
fn size_writes_the_metric_as_a_flow_solution_that_reads_back() {
    let d = tempfile::tempdir().unwrap();
    let cgns = d.path().join("field.cgns");
    let vtu = d.path().join("field.vtu");
    let (mesh, recipe) = (bundled("cylinder.msh"), bundled("cylinder.toml"));
    ok(&run(&["size", &mesh, "--recipe", &recipe, "-o", s(&cgns)]));
    ok(&run(&["size", &mesh, "--recipe", &recipe, "-o", s(&vtu)]));
    let a = smartmesh::formats::read_path(&cgns, None).unwrap();
    let b = smartmesh::formats::read_path(&vtu, None).unwrap();
    let (ma, mb) = (&a.point_data["metric"], &b.point_data["metric"]);
    assert_eq!(a.points.len(), b.points.len());
    assert_eq!(ma.components, mb.components);
    for (x, y) in ma.values.iter().zip(&mb.values) {
        assert!((x - y).abs() <= 1e-12 * y.abs().max(1.0), "{x} != {y}");
    }
}
