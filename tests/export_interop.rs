//! The metric exports read by the tools they are written for: VTK's Python reader finds
//! our tensor arrays with our values; Gmsh meshes a square with our `.pos` and `.msh` as
//! background mesh (`gmsh -bgm`, BAMG) and the result is fine and stretched where the field says so;
//! `mmg2d_O3` adapts our mesh to our `.sol` with the same outcome. Each test skips when
//! its Python modules are missing, unless `SMARTMESH_REQUIRE_INTEROP=1` (CI).
#![allow(clippy::print_stdout, clippy::print_stderr)] // What a test measured or skipped is printed for the log.

use smartmesh_test_support::formats as common;

use std::path::Path;
use std::process::Command;

use common::{python_with, run_python};

#[path = "support/cli.rs"]
#[allow(dead_code)]
mod support;
use smartmesh::formats::{read_path, CellKind, TaggedMesh, WriteOptions};
use smartmesh::SizeTensor;
use smartmesh::{MetricField, MetricTarget};
use smartmesh_test_support::grid::unit_square;

/// The test field: in the band `0.4 < y < 0.6`, edges of 0.1 along x and 0.01 across
/// (a wake); elsewhere isotropic 0.1.
fn wake_field(mesh: &TaggedMesh) -> Vec<SizeTensor> {
    mesh.points
        .iter()
        .map(|p| {
            if (p[1] - 0.5).abs() < 0.1 {
                SizeTensor::new([1.0, 0.0], 0.1, 0.01)
            } else {
                SizeTensor::isotropic(0.1)
            }
        })
        .collect()
}

fn export(mesh: &TaggedMesh, path: &Path) {
    let target = MetricTarget::from_path(path).unwrap();
    MetricField::from_sizes(&wake_field(mesh), "the wake")
        .write(path, mesh, target, &WriteOptions::default())
        .unwrap_or_else(|e| panic!("{e}"));
}

/// Triangle count, then mean |dx| and mean |dy| of the edges of triangles whose centroid
/// is in the band `|y - 0.5| < 0.08`, then the triangle count outside `|y - 0.5| < 0.15`.
fn band_statistics(mesh: &TaggedMesh) -> (usize, f64, f64, usize) {
    let (mut inside, mut dx, mut dy, mut outside) = (0usize, 0.0, 0.0, 0usize);
    for (kind, nodes, _, _) in mesh.cells() {
        if kind != CellKind::Triangle {
            continue;
        }
        let p: Vec<[f64; 3]> = nodes.iter().map(|&v| mesh.points[v as usize]).collect();
        let cy = (p[0][1] + p[1][1] + p[2][1]) / 3.0;
        if (cy - 0.5).abs() < 0.08 {
            inside += 1;
            for k in 0..3 {
                dx += (p[k][0] - p[(k + 1) % 3][0]).abs();
                dy += (p[k][1] - p[(k + 1) % 3][1]).abs();
            }
        } else if (cy - 0.5).abs() > 0.15 {
            outside += 1;
        }
    }
    (inside, dx / (3 * inside.max(1)) as f64, dy / (3 * inside.max(1)) as f64, outside)
}

/// The wake band (area 0.16) must hold many more triangles than the same area outside
/// (0.7 of the square holds `outside`), stretched along x.
fn assert_wake_refined(what: &str, mesh: &TaggedMesh) {
    let (inside, dx, dy, outside) = band_statistics(mesh);
    let density_in = inside as f64 / 0.16;
    let density_out = outside as f64 / 0.7;
    eprintln!("{what}: {inside} triangles in the band, {outside} outside; mean |dx| {dx:.4}, |dy| {dy:.4}");
    // The field asks for 10x more triangles per area in the band (0.1 x 0.01 against
    // 0.1 x 0.1); demand at least 4x, and edges at least 3x longer along x than across.
    assert!(
        density_in > 4.0 * density_out,
        "{what}: band density {density_in:.0} vs {density_out:.0} outside"
    );
    assert!(dx > 3.0 * dy, "{what}: band edges not stretched along x (|dx| {dx}, |dy| {dy})");
}

#[test]
fn vtk_reads_our_tensor_arrays() {
    let Some(py) = python_with(&["vtk"]) else { return };
    let mesh = unit_square(8);
    let dir = tempfile::tempdir().unwrap();
    let field = wake_field(&mesh);
    let arrays = MetricField::from_sizes(&field, "the wake").arrays();
    for name in ["m.vtu", "m.vtk"] {
        let path = dir.path().join(name);
        export(&mesh, &path);
        let script = r#"
import sys, vtk
path = sys.argv[1]
r = vtk.vtkXMLUnstructuredGridReader() if path.endswith('.vtu') else vtk.vtkUnstructuredGridReader()
r.SetFileName(path)
if not path.endswith('.vtu'):
    r.ReadAllScalarsOn(); r.ReadAllVectorsOn(); r.ReadAllTensorsOn(); r.ReadAllFieldsOn()
r.Update()
pd = r.GetOutput().GetPointData()
for k in range(pd.GetNumberOfArrays()):
    a = pd.GetArray(k)
    vals = [a.GetComponent(40, c) for c in range(a.GetNumberOfComponents())]
    print(a.GetName(), a.GetNumberOfComponents(), a.GetNumberOfTuples(), ' '.join(repr(v) for v in vals))
"#;
        let out = run_python(&py, script, &[path.to_str().unwrap()]);
        let mut seen = 0;
        for line in out.lines() {
            let mut w = line.split_whitespace();
            let name = w.next().unwrap();
            let comps: usize = w.next().unwrap().parse().unwrap();
            let tuples: usize = w.next().unwrap().parse().unwrap();
            let vals: Vec<f64> = w.map(|v| v.parse().unwrap()).collect();
            let Some(ours) = arrays.get(name) else { continue };
            seen += 1;
            assert_eq!((comps, tuples), (ours.components, mesh.points.len()), "{name} in {path:?}");
            let expect = &ours.values[40 * comps..41 * comps];
            for (a, b) in vals.iter().zip(expect) {
                assert!(
                    (a - b).abs() <= 1e-12 * b.abs().max(1.0),
                    "{name} in {path:?}: VTK reads {vals:?}, we wrote {expect:?}"
                );
            }
        }
        assert_eq!(seen, arrays.len(), "{path:?}: VTK found {out}");
    }
}

/// Meshes the unit square with the `gmsh` command, BAMG and `-bgm bgm`, as a user
/// would; returns the mesh Gmsh wrote.
fn gmsh_with_background(bgm: &Path, out: &Path) -> TaggedMesh {
    let geo = out.with_extension("geo");
    std::fs::write(
        &geo,
        "Point(1) = {0, 0, 0}; Point(2) = {1, 0, 0}; Point(3) = {1, 1, 0}; Point(4) = {0, 1, 0};\n\
         Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};\n\
         Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};\n",
    )
    .unwrap();
    let o = Command::new("gmsh")
        .arg(&geo)
        .args([
            "-2",
            "-v",
            "2",
            "-setnumber",
            "Mesh.Algorithm",
            "7",
            "-setnumber",
            "Mesh.MeshSizeExtendFromBoundary",
            "0",
        ])
        .args(["-setnumber", "Mesh.MeshSizeFromPoints", "0", "-bgm"])
        .arg(bgm)
        .arg("-o")
        .arg(out)
        .output()
        .expect("run gmsh");
    assert!(
        o.status.success(),
        "gmsh: {}\n{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
    read_path(out, None).unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn gmsh_meshes_with_our_pos_and_msh_as_background() {
    // PyPI `gmsh` puts the `gmsh` command on PATH.
    if python_with(&["gmsh"]).is_none() || support::program("gmsh").is_none() {
        return;
    }
    let mesh = unit_square(20);
    let dir = tempfile::tempdir().unwrap();
    for name in ["field.pos", "field.msh"] {
        let bgm = dir.path().join(name);
        export(&mesh, &bgm);
        let result = gmsh_with_background(&bgm, &dir.path().join(format!("out-{name}.msh")));
        assert_wake_refined(&format!("gmsh -bgm {name}"), &result);
    }
}

#[test]
fn mmg2d_adapts_our_mesh_to_our_sol() {
    let Some(py) = python_with(&["mmgpy"]) else { return };
    let exe = common::mmg2d(&py);
    let mesh = unit_square(20);
    let dir = tempfile::tempdir().unwrap();
    // Once as a mesh with its .sol beside it, once as a .sol alone next to a plain mesh.
    let with_sol = dir.path().join("a.mesh");
    export(&mesh, &with_sol);
    let plain = dir.path().join("b.mesh");
    smartmesh::formats::write_path(&plain, &mesh, None, &WriteOptions::default()).unwrap();
    let alone = dir.path().join("b-metric.sol");
    export(&mesh, &alone);
    for (input, sol) in [(&with_sol, dir.path().join("a.sol")), (&plain, alone.clone())] {
        let out = input.with_extension("o.mesh");
        let o = Command::new(&exe)
            .arg("-in")
            .arg(input)
            .arg("-sol")
            .arg(&sol)
            .arg("-out")
            .arg(&out)
            .args(["-v", "1"])
            .output()
            .expect("run mmg2d_O3");
        assert!(
            o.status.success(),
            "mmg2d_O3: {}\n{}",
            String::from_utf8_lossy(&o.stdout),
            String::from_utf8_lossy(&o.stderr)
        );
        let result = read_path(&out, None).unwrap_or_else(|e| panic!("{e}"));
        assert_wake_refined(&format!("mmg2d_O3 on {}", sol.display()), &result);
        // MMG keeps the references: the four sides are still there.
        for tag in 11..=14 {
            assert!(result.cells().any(|c| c.0 == CellKind::Line && c.2 == tag), "side {tag} lost");
        }
    }
}

#[test]
fn wrong_vertex_count_and_unknown_target_are_errors() {
    let mesh = unit_square(2);
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("x.sol");
    let e = MetricField::from_sizes(&[SizeTensor::isotropic(1.0)], "one tensor")
        .write(&path, &mesh, MetricTarget::Sol { binary: false }, &WriteOptions::default())
        .unwrap_err();
    assert!(e.to_string().contains("1 size tensors for 9 mesh vertices"), "{e}");
    assert!(!path.exists());
    assert_eq!(MetricTarget::from_path(Path::new("x.obj")), None);
    assert_eq!(
        MetricTarget::from_path(Path::new("x.SOLB")),
        Some(MetricTarget::Sol { binary: true })
    );
}
