//! The CGNS tests that need the `cgns` feature (see `cgns.rs`).

use std::collections::BTreeMap;
use std::path::Path;
use std::process::Command;

use proptest::prelude::*;
use smartmesh_formats::arbitrary::{arb_tagged_mesh, MeshFeatures};
use smartmesh_formats::{
    read_bytes, read_bytes_reported, write_bytes, CellKind, DataArray, Format, ReadContext,
    TaggedMesh, WriteOptions,
};
use smartmesh_test_support::cli::program;
use smartmesh_test_support::formats as common;

fn write(mesh: &TaggedMesh) -> smartmesh_formats::Written {
    write_bytes(Format::Cgns, mesh, &WriteOptions::default()).unwrap_or_else(|e| panic!("{e}"))
}

fn read(bytes: &[u8]) -> smartmesh_formats::Result<TaggedMesh> {
    read_bytes(Format::Cgns, bytes, &ReadContext::alone("cgns"))
}

/// Every cell as (kind, nodes, physical tag), sorted: the mesh up to cell order (the
/// writer groups cells by dimension, tag and kind).
fn cells(mesh: &TaggedMesh) -> Vec<(CellKind, Vec<u32>, i32)> {
    let mut v: Vec<_> = mesh.cells().map(|(k, n, p, _)| (k, n.to_vec(), p)).collect();
    v.sort();
    v
}

/// The names of the tags that cells use, by (dimension, tag).
fn used_names(mesh: &TaggedMesh) -> BTreeMap<(u8, i32), String> {
    let mut out = BTreeMap::new();
    for (k, _, p, _) in mesh.cells() {
        if let Some(n) = mesh.tag_name(k.dim(), p) {
            out.insert((k.dim(), p), n.to_string());
        }
    }
    out
}

fn assert_same_mesh(a: &TaggedMesh, b: &TaggedMesh) {
    assert_eq!(a.points.len(), b.points.len());
    for (p, q) in a.points.iter().zip(&b.points) {
        assert_eq!(p.map(f64::to_bits), q.map(f64::to_bits));
    }
    assert_eq!(cells(a), cells(b));
    assert_eq!(used_names(a), used_names(b));
}

#[test]
fn public_3d_meshes_round_trip_with_their_names() {
    smartmesh_test_support::require_public_fixtures!();
    for name in ["box_cyl", "hex_prism_pyr"] {
        let mesh = common::read_file(&format!("3d/{name}.v41_ascii.msh"));
        let written = write(&mesh);
        let back = read(&written.main).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_same_mesh(&mesh, &back);
        assert_eq!(back.coordinate_dim, 3);
        // The writer is deterministic: the same mesh gives the same file, read or not.
        assert_eq!(write(&back).main.len(), written.main.len(), "{name}");
    }
}

/// A 2D mesh with a scalar, a vector and the metric (a full 3x3 tensor and a packed
/// symmetric 2D one) as point fields; tags named and unnamed.
fn square_with_fields() -> TaggedMesh {
    let mut mesh = smartmesh_test_support::grid::unit_square(3);
    let n = mesh.points.len();
    let f = |k: usize| (0..n * k).map(|i| i as f64 * 0.25 - 1.0).collect::<Vec<_>>();
    mesh.point_data.insert("p".into(), DataArray::new(1, f(1)));
    mesh.point_data.insert("Velocity".into(), DataArray::new(3, f(3)));
    mesh.point_data.insert("metric".into(), DataArray::new(9, f(9)));
    mesh.point_data.insert("m2".into(), DataArray::symmetric2(f(3)));
    mesh
}

/// Names CGNS cannot hold as they are (too long, a `/`, a name the layout uses) are
/// made CGNS names, unique, and said so; the mesh is written and reads back.
#[test]
fn awkward_tag_names_are_made_cgns_names() {
    let mut mesh = smartmesh_test_support::grid::unit_square(2);
    mesh.tag_names.insert((2, 1), "Zone1".into());
    mesh.tag_names.insert((1, 11), "a/b".into());
    mesh.tag_names.insert((1, 12), "x".repeat(40) + "a");
    mesh.tag_names.insert((1, 13), "x".repeat(40) + "b");
    mesh.tag_names.insert((1, 14), "GridCoordinates".into());
    let written = write(&mesh);
    assert!(
        written.report.dropped.iter().any(|d| d.contains("CGNS names")),
        "{:?}",
        written.report
    );
    let back = read(&written.main).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(cells(&back), cells(&mesh));
    let names: std::collections::BTreeSet<String> = used_names(&back).into_values().collect();
    assert_eq!(names.len(), 5, "{names:?}");
}

#[test]
fn point_fields_and_2d_meshes_round_trip() {
    let mesh = square_with_fields();
    let written = write(&mesh);
    let back = read(&written.main).unwrap_or_else(|e| panic!("{e}"));
    assert_same_mesh(&mesh, &back);
    assert_eq!(back.coordinate_dim, 2);
    assert_eq!(back.point_data, mesh.point_data);
    assert!(written.report.dropped.is_empty(), "{:?}", written.report.dropped);
}

const FEATURES: MeshFeatures = MeshFeatures {
    quads: true,
    lines: true,
    vertices: true,
    geometrical: false,
    names: true,
    point_scalar: true,
    point_tensor: true,
    negative_tags: false,
};

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    #[test]
    fn prop_round_trip_keeps_points_cells_tags_names_and_fields(mesh in arb_tagged_mesh(FEATURES)) {
        let written = write(&mesh);
        let back = read(&written.main).unwrap_or_else(|e| panic!("{e}"));
        prop_assert_eq!(back.points.len(), mesh.points.len());
        // Vertex cells of several tags on one point read back under one (reported).
        // So do tags that share a name (one family; reported).
        let merged = |d: &String| d.contains("vertex cells of several tags") || d.contains("share the name");
        if !written.report.dropped.iter().any(merged) {
            prop_assert_eq!(cells(&back), cells(&mesh));
        } else {
            prop_assert_eq!(back.num_cells(), mesh.num_cells());
        }
        let shared = written.report.dropped.iter().any(merged);
        if !shared && !written.report.dropped.iter().any(|d| d.contains("CGNS names")) {
            prop_assert_eq!(used_names(&back), used_names(&mesh));
        }
        prop_assert_eq!(&back.point_data, &mesh.point_data);
    }
}

// ---------------------------------------------------------------------------------
// Malformed files

#[test]
fn bytes_that_are_no_hdf5_file_are_refused_at_byte_0() {
    let e = read(b"CGNS? no").unwrap_err();
    assert!(e.to_string().contains("byte 0") && e.to_string().contains("HDF5"), "{e}");
    assert!(e.is_input_error());
    let e = read(b"@(#)ADF Database Version A02011>").unwrap_err();
    assert!(e.to_string().contains("cgnsconvert"), "{e}");
}

#[test]
fn truncated_and_corrupted_files_are_refused_without_panic() {
    let bytes = write(&square_with_fields()).main;
    for cut in [8, 100, bytes.len() / 3, bytes.len() / 2, bytes.len() - 1] {
        assert!(read(&bytes[..cut]).is_err(), "cut at {cut}");
    }
}

/// A Python with h5py, or `None` after saying the test skips.
fn h5py() -> Option<String> {
    common::python_with(&["h5py", "numpy"])
}

/// Edits a CGNS file with h5py: `ops` is Python code with `f` the open file.
fn edit(py: &str, path: &Path, ops: &str) {
    let script = format!(
        "import h5py, numpy as np, sys\nf = h5py.File(sys.argv[1], 'r+')\n{ops}\nf.close()\n"
    );
    common::run_python(py, &script, &[path.to_str().unwrap()]);
}

/// Sets a node's data, keeping its attributes.
const SET: &str = "def set(path, values, dtype='i4'):\n    g = f[path]\n    del g[' data']\n    g.create_dataset(' data', data=np.array(values, dtype=dtype))\n";

#[test]
fn malformed_nodes_are_refused_naming_their_hdf5_path() {
    let Some(py) = h5py() else { return };
    let dir = tempfile::tempdir().unwrap();
    let bytes = write(&smartmesh_test_support::grid::unit_square(2)).main;
    let cases = [
        (
            "set('/Base/Zone1/GridElements/ElementConnectivity', [1, 2, 999] * 8)",
            "/Base/Zone1/GridElements/ElementConnectivity",
        ),
        (
            "set('/Base/Zone1/GridElements/ElementRange', [1, 10**12], 'i8')",
            "/Base/Zone1/GridElements",
        ),
        ("set('/Base/Zone1/GridElements', [99, 0])", "/Base/Zone1/GridElements"),
        ("set('/Base/Zone1/GridElements', [22, 0])", "/Base/Zone1/GridElements"),
        ("del f['/Base/Zone1/ZoneType']", "/Base/Zone1"),
        ("set('/Base/Zone1', [[10**15], [8], [0]], 'i8')", "/Base/Zone1"),
        (
            "set('/Base/Zone1/GridCoordinates/CoordinateX', [0.0, 1.0], 'f8')",
            "/Base/Zone1/GridCoordinates/CoordinateX",
        ),
        ("set('/Base', [4, 3])", "/Base"),
        ("del f['/Base/Zone1']", "/Base"),
        ("set('/Base/Zone1/ZoneBC/tag11/PointRange', [[1], [500]])", "/Base/Zone1/ZoneBC/tag11"),
    ];
    for (i, (op, path)) in cases.iter().enumerate() {
        let file = dir.path().join(format!("bad{i}.cgns"));
        std::fs::write(&file, &bytes).unwrap();
        edit(&py, &file, &format!("{SET}{op}"));
        let e = read(&std::fs::read(&file).unwrap()).expect_err(op).to_string();
        assert!(e.contains(path), "{op}: {e}");
    }
}

/// A MIXED section (the tetrahedra of box_cyl's section rewritten with a type code
/// before each element) and a second zone (a copy of the first) read back.
#[test]
fn mixed_sections_and_several_zones_are_read() {
    smartmesh_test_support::require_public_fixtures!();
    let Some(py) = h5py() else { return };
    let mesh = common::read_file("3d/hex_prism_pyr.v41_ascii.msh");
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("mixed.cgns");
    std::fs::write(&file, write(&mesh).main).unwrap();
    // Every section of volume cells becomes one MIXED section of the same elements.
    let ops = "\
sizes = {10: 4, 12: 5, 14: 6, 17: 8}
z = f['/Base/Zone1']
for name in list(z.keys()):
    if name.startswith(' '):
        continue
    g = z[name]
    if g.attrs['label'].tobytes().rstrip(b'\\0') != b'Elements_t':
        continue
    t = int(g[' data'][0])
    if t not in sizes:
        continue
    c = np.array(g['ElementConnectivity'][' data']).reshape(-1, sizes[t])
    mixed = np.hstack([np.full((len(c), 1), t), c]).ravel()
    set('/Base/Zone1/' + name, [20, 0])
    set('/Base/Zone1/' + name + '/ElementConnectivity', mixed)
f.copy(f['/Base/Zone1'], '/Base/Zone2')
";
    edit(&py, &file, &format!("{SET}{ops}"));
    let (back, report) = read_bytes_reported(
        Format::Cgns,
        &std::fs::read(&file).unwrap(),
        &ReadContext::alone("cgns"),
    )
    .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(back.points.len(), 2 * mesh.points.len());
    for kind in CellKind::ALL {
        assert_eq!(back.num_cells_of(kind), 2 * mesh.num_cells_of(kind), "{kind:?}");
    }
    assert!(report.notes.iter().any(|n| n.contains("2 zones")), "{:?}", report.notes);
    // The first zone is the mesh itself.
    let mut first = back.clone();
    let n = mesh.points.len() as u32;
    first.points.truncate(mesh.points.len());
    for b in &mut first.blocks {
        let keep: Vec<usize> = (0..b.len()).filter(|&i| b.cell(i).iter().all(|&v| v < n)).collect();
        let k = b.kind.nodes_per_cell();
        b.nodes = keep.iter().flat_map(|&i| b.nodes[i * k..(i + 1) * k].to_vec()).collect();
        b.physical = keep.iter().map(|&i| b.physical[i]).collect();
        b.geometrical = keep.iter().map(|&i| b.geometrical[i]).collect();
    }
    assert_eq!(cells(&first), cells(&mesh));
}

// ---------------------------------------------------------------------------------
// The CGNS library's own tools

/// `cgnscheck` on a file: no error (warnings allowed), and its text.
fn cgnscheck(exe: &Path, file: &Path) -> String {
    let out = Command::new(exe).arg(file).output().expect("run cgnscheck");
    let text =
        format!("{}{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
    assert!(
        out.status.success() && !text.contains("ERROR"),
        "cgnscheck {}:\n{text}",
        file.display()
    );
    assert!(text.contains("checking complete"), "{text}");
    text
}

#[test]
fn cgnscheck_finds_no_error_in_what_we_write() {
    smartmesh_test_support::require_public_fixtures!();
    let Some(exe) = program("cgnscheck") else { return };
    let dir = tempfile::tempdir().unwrap();
    let meshes = [
        ("box_cyl", common::read_file("3d/box_cyl.v41_ascii.msh")),
        ("hex_prism_pyr", common::read_file("3d/hex_prism_pyr.v41_ascii.msh")),
        ("square", square_with_fields()),
    ];
    for (name, mesh) in meshes {
        let file = dir.path().join(format!("{name}.cgns"));
        std::fs::write(&file, write(&mesh).main).unwrap();
        let text = cgnscheck(&exe, &file);
        assert!(text.contains("checking zone \"Zone1\""), "{text}");
        for (_, tag_name) in used_names(&mesh) {
            if mesh.cells().any(|(k, _, _, _)| k.dim() == 3) {
                assert!(
                    text.contains(&tag_name) || !text.contains("checking BC"),
                    "{tag_name}: {text}"
                );
            }
        }
    }
}

/// box_cyl through TetGen files into the CGNS library's `tetgen_to_cgns`: its file reads
/// back with box_cyl's points and cells, the boundary triangles tagged per section.
#[test]
fn files_the_cgns_library_writes_are_read() {
    smartmesh_test_support::require_public_fixtures!();
    let Some(exe) = program("tetgen_to_cgns") else { return };
    let mesh = common::read_file("3d/box_cyl.v41_ascii.msh");
    let dir = tempfile::tempdir().unwrap();
    let base = dir.path().join("box");
    let opts = WriteOptions { main_name: Some("box.node".into()), ..Default::default() };
    let tet = write_bytes(Format::TetGen, &mesh, &opts).unwrap_or_else(|e| panic!("{e}"));
    std::fs::write(base.with_extension("node"), &tet.main).unwrap();
    for (ext, bytes) in &tet.siblings {
        std::fs::write(base.with_extension(ext), bytes).unwrap();
    }
    let file = dir.path().join("box.cgns");
    let out = Command::new(exe).arg(&base).arg(&file).output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let back = read(&std::fs::read(&file).unwrap()).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(back.points.len(), mesh.points.len());
    assert_eq!(back.num_cells_of(CellKind::Tetra), mesh.num_cells_of(CellKind::Tetra));
    assert_eq!(back.num_cells_of(CellKind::Triangle), mesh.num_cells_of(CellKind::Triangle));
    // Its points are single precision: within 1e-6 relative of ours.
    for (p, q) in mesh.points.iter().zip(&back.points) {
        for c in 0..3 {
            assert!((p[c] - q[c]).abs() <= 1e-6 * p[c].abs().max(1.0), "{p:?} {q:?}");
        }
    }
    // A section per boundary marker, each a named surface tag.
    let surface_tags: std::collections::BTreeSet<i32> =
        back.cells().filter(|c| c.0 == CellKind::Triangle).map(|c| c.2).collect();
    let markers: std::collections::BTreeSet<i32> =
        mesh.cells().filter(|c| c.0 == CellKind::Triangle).map(|c| c.2).collect();
    assert_eq!(surface_tags.len(), markers.len());
    for t in surface_tags {
        assert!(back.tag_name(2, t).is_some_and(|n| n.starts_with("Tri Group")), "{t}");
    }
    // And `cgnsconvert` to ADF gives a file we refuse saying how to convert it back.
    if let Some(conv) = program("cgnsconvert") {
        let adf = dir.path().join("box.adf.cgns");
        let out = Command::new(conv).arg("-a").arg(&file).arg(&adf).output().unwrap();
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        let e = read(&std::fs::read(&adf).unwrap()).unwrap_err().to_string();
        assert!(e.contains("ADF") && e.contains("cgnsconvert"), "{e}");
    }
}

// ---------------------------------------------------------------------------------
// meshio and VTK

#[test]
fn meshio_reads_the_tetrahedra_we_write() {
    smartmesh_test_support::require_public_fixtures!();
    let Some(py) = common::python_with(&["meshio", "h5py"]) else { return };
    let mesh = common::read_file("3d/box_cyl.v41_ascii.msh");
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("box.cgns");
    std::fs::write(&file, write(&mesh).main).unwrap();
    let out = common::run_python(
        &py,
        "import meshio, sys\nm = meshio.read(sys.argv[1])\nprint(len(m.points), sum(len(c.data) for c in m.cells if c.type == 'tetra'), m.cells[0].data.max())",
        &[file.to_str().unwrap()],
    );
    let expected = format!(
        "{} {} {}",
        mesh.points.len(),
        mesh.num_cells_of(CellKind::Tetra),
        mesh.points.len() - 1
    );
    assert_eq!(out.trim(), expected);
}

/// VTK's `vtkCGNSReader` (ParaView's CGNS reader): points, cells per VTK type, the
/// connectivity of every volume cell equal to what VTK reads from our `.vtu` (so each
/// kind's node order and orientation, the 10-node tetrahedra of box_cyl_o2 included),
/// the boundary patches by name, the point fields.
const VTK_SCRIPT: &str = r#"
import sys, vtk
from vtk.util.numpy_support import vtk_to_numpy
r = vtk.vtkCGNSReader()
r.SetFileName(sys.argv[1])
r.UpdateInformation()
r.EnableAllBases()
r.EnableAllPointArrays()
r.SetLoadBndPatch(1)
r.Update()
out = r.GetOutput()
it = out.NewIterator()
it.SetVisitOnlyLeaves(False)
it.InitTraversal()
blocks = {}
while not it.IsDoneWithTraversal():
    name = it.GetCurrentMetaData().Get(vtk.vtkCompositeDataSet.NAME())
    blocks[name] = it.GetCurrentDataObject()
    it.GoToNextItem()
x = vtk.vtkXMLUnstructuredGridReader()
x.SetFileName(sys.argv[2])
x.Update()
ref = x.GetOutput()
ref_cells = sorted(tuple(ref.GetCell(i).GetPointIds().GetId(j) for j in range(ref.GetCell(i).GetNumberOfPoints())) for i in range(ref.GetNumberOfCells()) if ref.GetCell(i).GetCellDimension() == 3)
zone = blocks['Internal']
cells = sorted(tuple(zone.GetCell(i).GetPointIds().GetId(j) for j in range(zone.GetCell(i).GetNumberOfPoints())) for i in range(zone.GetNumberOfCells()) if zone.GetCell(i).GetCellDimension() == 3)
arrays = sorted(zone.GetPointData().GetArrayName(i) + ':' + str(zone.GetPointData().GetArray(i).GetNumberOfComponents()) for i in range(zone.GetPointData().GetNumberOfArrays()))
print(zone.GetNumberOfPoints(), len(cells), cells == ref_cells, ' '.join(arrays))
print(' '.join(sorted(n for n in blocks if n not in ('Base', 'Zone1', 'Internal', 'Patches'))))
"#;

#[test]
fn vtk_cgns_reader_reads_cells_in_order_patches_and_fields() {
    smartmesh_test_support::require_public_fixtures!();
    let Some(py) = common::python_with(&["vtk"]) else { return };
    let dir = tempfile::tempdir().unwrap();
    for name in ["hex_prism_pyr", "box_cyl", "box_cyl_o2"] {
        let mut mesh = common::read_file(&format!("3d/{name}.v41_ascii.msh"));
        let n = mesh.points.len();
        mesh.point_data
            .insert("metric".into(), DataArray::new(9, (0..9 * n).map(|i| i as f64).collect()));
        mesh.point_data.insert("p".into(), DataArray::new(1, (0..n).map(|i| i as f64).collect()));
        let file = dir.path().join(format!("{name}.cgns"));
        std::fs::write(&file, write(&mesh).main).unwrap();
        let vtu = dir.path().join(format!("{name}.vtu"));
        let w = write_bytes(Format::Vtu, &mesh, &WriteOptions::default()).unwrap();
        std::fs::write(&vtu, w.main).unwrap();
        let out =
            common::run_python(&py, VTK_SCRIPT, &[file.to_str().unwrap(), vtu.to_str().unwrap()]);
        let mut lines = out.lines();
        let volumes = mesh.cells().filter(|c| c.0.dim() == 3).count();
        let first = lines.next().unwrap_or("");
        assert!(first.starts_with(&format!("{n} {volumes} True ")), "{name}: {out}");
        assert!(first.contains("p:1"), "{name}: {out}");
        let patches = lines.next().unwrap_or("");
        for (&(d, _), tag_name) in &used_names(&mesh) {
            if d == 2 {
                assert!(patches.contains(tag_name.as_str()), "{name}: {tag_name}: {out}");
            }
        }
    }
}
