//! 3D metric fields: written to every target and read back, read from the forms other
//! tools write (ParaView's 6 components, a Gmsh data-only `.msh`, a `.pos` tensor view on
//! tetrahedra), refused with the vertex or line, and measured by `info --metric` as the
//! UGAWG does, against a twin written from the definitions in this file; the UGAWG
//! measures of a 2D mesh with `--measures ugawg`.

#[path = "support/cli.rs"]
#[allow(dead_code)]
mod cli;

use std::path::Path;

use cli::{bad, ok, smartmesh};
use serde_json::Value;
use smartmesh::formats::{write_path, DataArray, TaggedMesh, WriteOptions};
use smartmesh::metric::Sym3;
use smartmesh::{MetricField, MetricTarget};
use smartmesh_test_support::grid::kuhn_box;

#[path = "support/metric3d.rs"]
#[allow(dead_code)]
mod metric3d;
use metric3d::analytic;

fn field(mesh: &TaggedMesh) -> MetricField<Sym3> {
    MetricField::new(mesh.points.iter().map(|&p| analytic(p)).collect(), "the analytic field")
}

fn close(a: &Sym3, b: &Sym3, what: &str) {
    let scale = b.to_medit().iter().fold(0.0f64, |s, x| s.max(x.abs()));
    for (x, y) in a.to_medit().iter().zip(b.to_medit()) {
        assert!((x - y).abs() <= 1e-12 * scale, "{what}: {a:?} read, {b:?} written");
    }
}

#[test]
fn a_3d_field_goes_to_every_target_and_back() {
    let mesh = kuhn_box(3, [1.0, 1.0, 1.0]);
    let dir = tempfile::tempdir().unwrap();
    let mesh_path = dir.path().join("cube.mesh");
    write_path(&mesh_path, &mesh, None, &WriteOptions::default()).unwrap();
    let f = field(&mesh);
    for name in ["m.sol", "m.solb", "m.msh", "m.vtu", "m.vtk", "m.pos", "m.mesh", "m.meshb"] {
        let path = dir.path().join(name);
        let target = MetricTarget::from_path(&path).unwrap();
        f.write(&path, &mesh, target, &WriteOptions::default()).unwrap_or_else(|e| panic!("{e}"));
        let back = MetricField::<Sym3>::read_field(&path, None, &mesh, &mesh_path)
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        for (a, b) in back.tensors().iter().zip(f.tensors()) {
            close(a, b, name);
        }
    }
    // MMG's order in the .sol: m11 m12 m22 m13 m23 m33 of vertex 0, as written.
    let text = std::fs::read_to_string(dir.path().join("m.sol")).unwrap();
    assert!(text.contains("Dimension 3"), "{text}");
    let m = analytic(mesh.points[0]);
    let row: Vec<f64> = text
        .lines()
        .skip_while(|l| !l.trim().starts_with("1 3"))
        .nth(1)
        .unwrap()
        .split_whitespace()
        .map(|v| v.parse().unwrap())
        .collect();
    for (x, y) in row.iter().zip(m.to_medit()) {
        assert!((x - y).abs() <= 1e-12 * y.abs().max(1.0), "{row:?} vs {:?}", m.to_medit());
    }
}

fn info_json(args: &[&str]) -> Value {
    let mut all = vec!["info", "--json"];
    all.extend_from_slice(args);
    serde_json::from_str(&ok(&smartmesh(&all, None))).unwrap()
}

#[test]
fn info_measures_tetrahedra_as_the_ugawg_does() {
    let mesh = kuhn_box(4, [1.0, 1.0, 1.0]);
    let dir = tempfile::tempdir().unwrap();
    let mesh_path = dir.path().join("cube.mesh");
    write_path(&mesh_path, &mesh, None, &WriteOptions::default()).unwrap();
    let sol = dir.path().join("metric.sol");
    field(&mesh)
        .write(&sol, &mesh, MetricTarget::Sol { binary: false }, &WriteOptions::default())
        .unwrap();
    let (m, s) = (mesh_path.to_str().unwrap(), sol.to_str().unwrap());
    let j = info_json(&[m, "--metric", s]);
    let u = &j["metric"]["ugawg"];
    let lengths = metric3d::edge_lengths(&mesh, smartmesh::formats::CellKind::Tetra);
    assert_eq!(u["dimension"], 3);
    assert_eq!(u["cell"], "tetrahedron");
    assert_eq!(u["cells"], 6 * 64);
    assert_eq!(u["edges"].as_u64().unwrap() as usize, lengths.len());
    let lo = lengths.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = lengths.iter().copied().fold(0.0, f64::max);
    let mean = lengths.iter().sum::<f64>() / lengths.len() as f64;
    let share = lengths.iter().filter(|&&l| (0.5f64.sqrt()..=2f64.sqrt()).contains(&l)).count()
        as f64
        / lengths.len() as f64;
    let got = |k: &str, i: usize| u[k][i].as_f64().unwrap();
    assert!((got("edge_length_range", 0) - lo).abs() < 1e-9 * lo, "{u} {lo}");
    assert!((got("edge_length_range", 1) - hi).abs() < 1e-9 * hi, "{u} {hi}");
    assert!((u["mean_edge_length"].as_f64().unwrap() - mean).abs() < 1e-9 * mean, "{u} {mean}");
    assert!((u["conforming_share"].as_f64().unwrap() - share).abs() < 1e-12, "{u} {share}");
    assert_eq!(u["non_positive"], 0, "{u}");
    // The text says the same.
    let text = ok(&smartmesh(&["info", m, "--metric", s], None));
    assert!(
        text.contains("ugawg       3D metric") && text.contains("mean ratio over 384 tetrahedra"),
        "{text}"
    );
}

/// `mesh` as a .vtu with the point array `metric` of `components` per vertex.
fn vtu_with(
    dir: &Path,
    name: &str,
    mesh: &TaggedMesh,
    values: Vec<f64>,
    components: usize,
) -> String {
    let mut m = mesh.clone();
    m.point_data.insert("metric".into(), DataArray::new(components, values));
    let p = dir.join(name);
    write_path(&p, &m, None, &WriteOptions::default()).unwrap();
    p.to_str().unwrap().to_string()
}

#[test]
fn paraview_s_six_components_and_bad_tensors() {
    let mesh = kuhn_box(2, [1.0, 1.0, 1.0]);
    let dir = tempfile::tempdir().unwrap();
    let nine: Vec<f64> = mesh.points.iter().flat_map(|&p| analytic(p).to_row_major()).collect();
    // XX YY ZZ XY YZ XZ.
    let six: Vec<f64> = mesh
        .points
        .iter()
        .flat_map(|&p| {
            let m = analytic(p);
            [m.xx, m.yy, m.zz, m.xy, m.yz, m.xz]
        })
        .collect();
    let a = info_json(&[&vtu_with(dir.path(), "nine.vtu", &mesh, nine.clone(), 9)]);
    let b = info_json(&[&vtu_with(dir.path(), "six.vtu", &mesh, six, 6)]);
    assert_eq!(a["metric"]["ugawg"], b["metric"]["ugawg"]);
    assert!(a["metric"]["ugawg"]["edges"].as_u64().unwrap() > 0);
    // Vertex 5 not positive definite, given as --metric: exit 2, the vertex named.
    let mut broken = nine.clone();
    broken[9 * 5..9 * 5 + 9].copy_from_slice(&[1.0, 0.0, 0.9, 0.0, 1.0, 0.9, 0.9, 0.9, 1.0]);
    let plain = dir.path().join("plain.vtu");
    write_path(&plain, &mesh, None, &WriteOptions::default()).unwrap();
    let bad_file = vtu_with(dir.path(), "bad.vtu", &mesh, broken, 9);
    let e = bad(&smartmesh(&["info", plain.to_str().unwrap(), "--metric", &bad_file], None));
    assert!(
        e.contains("bad.vtu")
            && e.contains("vertex 5")
            && e.contains("not a 3D metric")
            && e.contains("positive definite"),
        "{e}"
    );
    // Four components are no metric.
    let four = vtu_with(dir.path(), "four.vtu", &mesh, vec![1.0; 4 * mesh.points.len()], 4);
    let e = bad(&smartmesh(&["info", plain.to_str().unwrap(), "--metric", &four], None));
    assert!(e.contains("4 components") && e.contains("a 3D metric has 9"), "{e}");
}

#[test]
fn a_gmsh_data_only_file_and_a_tetrahedron_view_are_read_in_3d() {
    let mesh = kuhn_box(2, [1.0, 1.0, 1.0]);
    let dir = tempfile::tempdir().unwrap();
    let mesh_path = dir.path().join("cube.msh");
    write_path(&mesh_path, &mesh, None, &WriteOptions::default()).unwrap();
    // As gmsh.view.write writes a view alone: node tag t at vertex t - 1.
    let mut text = format!(
        "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$NodeData\n1\n\"metric\"\n1\n0\n3\n0\n9\n{}\n",
        mesh.points.len()
    );
    for (i, &p) in mesh.points.iter().enumerate() {
        let v: Vec<String> = analytic(p).to_row_major().iter().map(|x| x.to_string()).collect();
        text.push_str(&format!("{} {}\n", i + 1, v.join(" ")));
    }
    text.push_str("$EndNodeData\n");
    let data = dir.path().join("data.msh");
    std::fs::write(&data, text).unwrap();
    let f = MetricField::<Sym3>::read_field(&data, None, &mesh, &mesh_path).unwrap();
    for (a, &p) in f.tensors().iter().zip(&mesh.points) {
        close(a, &analytic(p), "data-only .msh");
    }
    // A TS view whose node is not a vertex: refused, the vertex named.
    let pos = dir.path().join("moved.pos");
    let id = "1,0,0,0,1,0,0,0,1";
    std::fs::write(
        &pos,
        format!("View \"m\" {{\nTS(0,0,0,9,0,0,0,9,0,0,0,9){{{id},{id},{id},{id}}};\n}};\n"),
    )
    .unwrap();
    let e = MetricField::<Sym3>::read_field(&pos, None, &mesh, &mesh_path).unwrap_err().to_string();
    assert!(
        e.contains("moved.pos") && e.contains("vertex 1 (0-based)") && e.contains("no node"),
        "{e}"
    );
}

#[test]
fn a_2d_mesh_gets_the_ugawg_measures_when_asked() {
    let mesh = smartmesh_test_support::grid::unit_square(4);
    let dir = tempfile::tempdir().unwrap();
    let mut m = mesh.clone();
    let values: Vec<f64> = mesh
        .points
        .iter()
        .flat_map(|p| {
            let h = 0.1 + 0.2 * p[0];
            [1.0 / (h * h), 0.0, 0.0, 0.0, 1.0 / (0.25 * 0.25), 0.0, 0.0, 0.0, 1.0]
        })
        .collect();
    m.point_data.insert("metric".into(), DataArray::new(9, values));
    let p = dir.path().join("sq.vtu");
    write_path(&p, &m, None, &WriteOptions::default()).unwrap();
    let p = p.to_str().unwrap();
    let plain = info_json(&[p]);
    assert!(plain["metric"].get("ugawg").is_none(), "{}", plain["metric"]);
    let j = info_json(&[p, "--measures", "ugawg"]);
    let u = &j["metric"]["ugawg"];
    assert_eq!((u["dimension"].as_u64(), u["cell"].as_str()), (Some(2), Some("triangle")));
    // The same edges as the default conformity, measured alike.
    let c = &j["metric"]["conformity"];
    assert_eq!(u["edges"], c["edges"]);
    assert_eq!(u["edge_length_range"], c["edge_length_range"]);
    // The longest edge: the diagonal of the first column of cells, from (0, y) to
    // (0.25, y + 0.25); lengths at its ends with hx = 0.1 and 0.15, hy = 0.25, log-mean.
    let (la, lb) = ((2.5f64 * 2.5 + 1.0).sqrt(), ((0.25f64 / 0.15).powi(2) + 1.0).sqrt());
    let longest = (la - lb) / (la / lb).ln();
    let got = u["edge_length_range"][1].as_f64().unwrap();
    assert!((got - longest).abs() < 1e-12, "{got} {longest}");
    let text = ok(&smartmesh(&["info", p, "--measures", "ugawg"], None));
    assert!(text.contains("ugawg       2D metric") && text.contains("geometric mean"), "{text}");
}
