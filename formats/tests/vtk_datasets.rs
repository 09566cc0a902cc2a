//! What ParaView users hand over besides unstructured grids: legacy POLYDATA,
//! STRUCTURED_GRID, RECTILINEAR_GRID and STRUCTURED_POINTS, XML PolyData (`.vtp`),
//! multi-piece and parallel files, read as meshes with their data; polygons and strips
//! split with a note. VTK writes the samples and measures them (`vtkCellSizeFilter`):
//! the same counts, lengths, areas and volumes come back. Skips when Python lacks
//! `vtk`, unless `SMARTMESH_REQUIRE_INTEROP=1`.

use smartmesh_test_support::formats as common;

use smartmesh_formats::{read_path_reported, CellKind, TaggedMesh};

fn legacy(text: &str) -> Result<TaggedMesh, smartmesh_formats::Error> {
    smartmesh_formats::read_bytes(
        smartmesh_formats::Format::VtkLegacy,
        text.as_bytes(),
        &smartmesh_formats::ReadContext::alone("vtk"),
    )
}

#[test]
fn polydata_cells_come_in_vtk_s_order_with_their_data() {
    let text = "# vtk DataFile Version 4.2\nt\nASCII\nDATASET POLYDATA\nPOINTS 8 float\n\
        0 0 0 1 0 0 2 0 0 0 1 0 1 1 0 2 1 0 0.5 2 0 1.5 2.5 0\n\
        TRIANGLE_STRIPS 1 5\n4 3 0 4 1\nPOLYGONS 2 10\n5 0 1 4 6 3\n3 1 2 5\n\
        VERTICES 2 5\n2 6 7\n1 0\nLINES 1 4\n3 0 1 2\n\
        CELL_DATA 6\nSCALARS id int\nLOOKUP_TABLE default\n10 11 12 13 14 15\n";
    let m = legacy(text).unwrap();
    assert_eq!(m.num_cells_of(CellKind::Vertex), 3);
    assert_eq!(m.num_cells_of(CellKind::Line), 2);
    assert_eq!(m.num_cells_of(CellKind::Triangle), 6);
    // Vertices first, then lines, polygons, strips, each piece with its parent's value.
    assert_eq!(
        m.cell_data["id"].values,
        vec![10.0, 10.0, 11.0, 12.0, 12.0, 13.0, 13.0, 13.0, 14.0, 15.0, 15.0]
    );
    // The strip's triangles keep its orientation: (3 0 4), then (4 0 1) turned.
    let tris = m.blocks.iter().find(|b| b.kind == CellKind::Triangle).unwrap();
    assert_eq!(&tris.nodes[12..], &[3, 0, 4, 4, 0, 1]);
    let areas: Vec<f64> = tris
        .cells()
        .map(|c| {
            let [a, b, c] = [c[0], c[1], c[2]].map(|v| m.points[v as usize]);
            0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]))
        })
        .collect();
    // Pentagon 1.5, triangle 0.5, strip 1: every triangle counter-clockwise.
    assert!(areas.iter().all(|&a| a > 0.0), "{areas:?}");
    assert_eq!(areas.iter().sum::<f64>(), 3.0);
}

#[test]
fn structured_datasets_become_quads_and_hexahedra() {
    let head = "# vtk DataFile Version 4.2\nt\nASCII\n";
    let m = legacy(&format!(
        "{head}DATASET STRUCTURED_POINTS\nDIMENSIONS 3 2 1\nORIGIN 1 2 0\nSPACING 0.5 2 1\nPOINT_DATA 6\nSCALARS f double\nLOOKUP_TABLE default\n0 1 2 3 4 5\n"
    ))
    .unwrap();
    assert_eq!(m.points[5], [2.0, 4.0, 0.0]);
    assert_eq!(m.blocks[0].kind, CellKind::Quad);
    assert_eq!(m.blocks[0].nodes, vec![0, 1, 4, 3, 1, 2, 5, 4]);
    assert_eq!(m.point_data["f"].values.len(), 6);
    let m = legacy(&format!(
        "{head}DATASET RECTILINEAR_GRID\nDIMENSIONS 2 2 2\nX_COORDINATES 2 float\n0 3\nY_COORDINATES 2 float\n0 2\nZ_COORDINATES 2 float\n-1 0\nCELL_DATA 1\nSCALARS c int\nLOOKUP_TABLE default\n7\n"
    ))
    .unwrap();
    assert_eq!(m.blocks[0].kind, CellKind::Hexa);
    assert_eq!(m.blocks[0].nodes, vec![0, 1, 3, 2, 4, 5, 7, 6]);
    assert_eq!(m.points[7], [3.0, 2.0, 0.0]);
    assert_eq!(m.cell_data["c"].values, vec![7.0]);
    let m = legacy(&format!(
        "{head}DATASET STRUCTURED_GRID\nDIMENSIONS 1 3 1\nPOINTS 3 float\n0 0 0 0 1 0 1 2 0\n"
    ))
    .unwrap();
    assert_eq!(m.blocks[0].kind, CellKind::Line);
    assert_eq!(m.blocks[0].nodes, vec![0, 1, 1, 2]);
}

#[test]
fn structured_datasets_refuse_what_does_not_fit() {
    let head = "# vtk DataFile Version 4.2\nt\nASCII\n";
    // 10^15 points announced by 30 bytes: refused before anything is allocated.
    let e = legacy(&format!("{head}DATASET STRUCTURED_POINTS\nDIMENSIONS 100000 100000 100000\n"))
        .unwrap_err();
    assert!(e.to_string().contains("points of DIMENSIONS"), "{e}");
    assert_eq!(e.at, Some(smartmesh_formats::Position::Line(5)));
    let e = legacy(&format!(
        "{head}DATASET STRUCTURED_GRID\nDIMENSIONS 2 2 1\nPOINTS 3 float\n0 0 0 1 0 0 0 1 0\n"
    ))
    .unwrap_err();
    assert!(e.to_string().contains("make 4 points, POINTS gives 3"), "{e}");
    let e = legacy(&format!(
        "{head}DATASET RECTILINEAR_GRID\nDIMENSIONS 2 2 1\nX_COORDINATES 3 float\n0 1 2\n"
    ))
    .unwrap_err();
    assert!(e.to_string().contains("DIMENSIONS gives 2"), "{e}");
    let e = legacy(&format!(
        "{head}DATASET POLYDATA\nPOLYGONS 1 4\n3 0 1 2\nPOINTS 2 float\n0 0 0 1 1 1\n"
    ))
    .unwrap_err();
    assert!(e.to_string().contains("POLYDATA cell"), "{e}");
    let e = legacy(&format!("{head}DATASET FIELD\n")).unwrap_err();
    assert!(e.to_string().contains("POLYDATA, STRUCTURED_GRID"), "{e}");
}

/// VTK writes each sample (legacy ASCII and binary, 4.2 and 5.1, XML) and measures it;
/// prints `{file: [points, cells, vertices, length, area, volume]}`.
const VTK_SAMPLES: &str = r#"
import sys, os, json
import vtk
d = sys.argv[1]
out = {}
def measure(name, reader):
    reader.SetFileName(os.path.join(d, name))
    reader.Update()
    g = reader.GetOutput()
    f = vtk.vtkCellSizeFilter()
    f.SetInputData(g)
    f.Update()
    o = f.GetOutput()
    sums = []
    for a in ("VertexCount", "Length", "Area", "Volume"):
        arr = o.GetCellData().GetArray(a)
        sums.append(sum(arr.GetValue(i) for i in range(o.GetNumberOfCells())))
    out[name] = [g.GetNumberOfPoints(), g.GetNumberOfCells()] + sums
def legacy(obj, stem):
    for ver in (42, 51):
        for binary in (False, True):
            name = f"{stem}_{ver}_{'bin' if binary else 'ascii'}.vtk"
            w = vtk.vtkDataSetWriter()
            w.SetInputData(obj)
            w.SetFileName(os.path.join(d, name))
            w.SetFileVersion(ver)
            w.SetFileTypeToBinary() if binary else w.SetFileTypeToASCII()
            assert w.Write() == 1
            measure(name, vtk.vtkDataSetReader())
pts = vtk.vtkPoints()
for p in [(0,0,0),(1,0,0),(2,0,0),(0,1,0),(1,1,0),(2,1,0),(0.5,2,0),(1.5,2.5,0),(3,0,0),(3,2,0)]:
    pts.InsertNextPoint(p)
m = vtk.vtkPolyData()
m.SetPoints(pts)
verts = vtk.vtkCellArray(); verts.InsertNextCell(2, [6, 7]); verts.InsertNextCell(1, [0]); m.SetVerts(verts)
lines = vtk.vtkCellArray(); lines.InsertNextCell(3, [0, 1, 2]); lines.InsertNextCell(2, [2, 8]); m.SetLines(lines)
polys = vtk.vtkCellArray()
polys.InsertNextCell(5, [0, 1, 4, 6, 3]); polys.InsertNextCell(3, [1, 2, 5]); polys.InsertNextCell(4, [2, 8, 9, 5])
polys.InsertNextCell(6, [0, 8, 9, 7, 6, 3])
m.SetPolys(polys)
strips = vtk.vtkCellArray(); strips.InsertNextCell(5, [3, 0, 4, 1, 5]); m.SetStrips(strips)
legacy(m, "poly")
w = vtk.vtkXMLPolyDataWriter(); w.SetInputData(m); w.SetFileName(os.path.join(d, "poly.vtp")); w.Write()
measure("poly.vtp", vtk.vtkXMLPolyDataReader())
img = vtk.vtkImageData(); img.SetDimensions(3, 4, 2); img.SetOrigin(1, 2, 3); img.SetSpacing(0.5, 0.25, 2)
legacy(img, "image")
img2 = vtk.vtkImageData(); img2.SetDimensions(4, 1, 3); img2.SetSpacing(1, 1, 0.5)
legacy(img2, "image_xz")
rg = vtk.vtkRectilinearGrid(); rg.SetDimensions(3, 2, 2)
for f, vals in ((rg.SetXCoordinates, [0, 1, 3]), (rg.SetYCoordinates, [0, 2]), (rg.SetZCoordinates, [0, 0.5])):
    c = vtk.vtkDoubleArray(); [c.InsertNextValue(v) for v in vals]; f(c)
legacy(rg, "rect")
sg = vtk.vtkStructuredGrid(); sg.SetDimensions(3, 3, 2); sp = vtk.vtkPoints()
for k in range(2):
    for j in range(3):
        for i in range(3):
            sp.InsertNextPoint(i + 0.3 * j, j + 0.2 * k, k + 0.1 * i)
sg.SetPoints(sp)
legacy(sg, "sgrid")
print(json.dumps(out))
"#;

/// `[points, cells, vertices, length, area, volume]` of a mesh, as `vtkCellSizeFilter`
/// sums them (a quad's area by two triangles: the samples' quads are planar; a
/// hexahedron's volume by six tetrahedra: the samples' are affine images of cubes). The
/// samples' polygons are convex: VTK's filter sums the absolute areas of a fan, which
/// overcounts a non-convex polygon (an L's notch), where ear clipping is exact
/// (`vtk::cells` unit test).
fn measures(m: &TaggedMesh) -> [f64; 6] {
    let p = |v: u32| m.points[v as usize];
    let sub = |a: [f64; 3], b: [f64; 3]| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    let cross = |a: [f64; 3], b: [f64; 3]| {
        [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
    };
    let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let norm = |a: [f64; 3]| dot(a, a).sqrt();
    let tri = |a: u32, b: u32, c: u32| 0.5 * norm(cross(sub(p(b), p(a)), sub(p(c), p(a))));
    let tet = |a: u32, b: u32, c: u32, d: u32| {
        dot(sub(p(b), p(a)), cross(sub(p(c), p(a)), sub(p(d), p(a)))) / 6.0
    };
    let mut s = [m.points.len() as f64, m.num_cells() as f64, 0.0, 0.0, 0.0, 0.0];
    for (kind, c, _, _) in m.cells() {
        match kind {
            CellKind::Vertex => s[2] += 1.0,
            CellKind::Line => s[3] += norm(sub(p(c[1]), p(c[0]))),
            CellKind::Triangle => s[4] += tri(c[0], c[1], c[2]),
            CellKind::Quad => s[4] += tri(c[0], c[1], c[2]) + tri(c[0], c[2], c[3]),
            CellKind::Tetra => s[5] += tet(c[0], c[1], c[2], c[3]),
            CellKind::Hexa => {
                s[5] += [
                    [0, 1, 2, 6],
                    [0, 2, 3, 6],
                    [0, 3, 7, 6],
                    [0, 7, 4, 6],
                    [0, 4, 5, 6],
                    [0, 5, 1, 6],
                ]
                .iter()
                .map(|t| tet(c[t[0]], c[t[1]], c[t[2]], c[t[3]]))
                .sum::<f64>()
            }
            k => panic!("{k:?} in a sample"),
        }
    }
    s
}

#[test]
fn vtk_samples_of_every_dataset_read_with_vtk_s_measures() {
    let Some(py) = common::python_with(&["vtk"]) else { return };
    let dir = tempfile::tempdir().unwrap();
    let out: serde_json::Value = serde_json::from_str(&common::run_python(
        &py,
        VTK_SAMPLES,
        &[dir.path().to_str().unwrap()],
    ))
    .unwrap();
    let files = out.as_object().unwrap();
    assert_eq!(files.len(), 21);
    for (name, vtk) in files {
        let (m, report) = read_path_reported(&dir.path().join(name), None)
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        let ours = measures(&m);
        let vtk: Vec<f64> = vtk.as_array().unwrap().iter().map(|v| v.as_f64().unwrap()).collect();
        assert_eq!(ours[0], vtk[0], "{name}: points");
        // Counts of VTK's cells: ours has more where polygons and strips were split.
        if !name.starts_with("poly") {
            assert_eq!(ours[1], vtk[1], "{name}: cells");
        } else {
            assert!(report.notes.iter().any(|n| n.contains("triangle strips split")), "{name}");
            assert!(report.notes.iter().any(|n| n.contains("polygons of more than 4")), "{name}");
        }
        for (i, what) in [(2, "vertices"), (3, "length"), (4, "area"), (5, "volume")] {
            assert!(
                (ours[i] - vtk[i]).abs() <= 1e-6 * vtk[i].abs().max(1.0),
                "{name}: {what} {} against VTK's {}",
                ours[i],
                vtk[i]
            );
        }
    }
}

/// VTK cuts box_cyl into 3 pieces (`vtkExtractUnstructuredGridPiece`) and writes them
/// as a parallel `.pvtu` with its piece files, and as one `.vtu` of 3 pieces; then
/// reads both back and measures them. Prints `{file: [points, cells, ..measures]}`.
const VTK_PIECES: &str = r#"
import sys, os, json
import vtk
src, d = sys.argv[1], sys.argv[2]
r = vtk.vtkXMLUnstructuredGridReader()
r.SetFileName(src)
e = vtk.vtkExtractUnstructuredGridPiece()
e.SetInputConnection(r.GetOutputPort())
w = vtk.vtkXMLPUnstructuredGridWriter()
w.SetInputConnection(e.GetOutputPort())
w.SetFileName(os.path.join(d, "box.pvtu"))
w.SetNumberOfPieces(3)
w.SetStartPiece(0)
w.SetEndPiece(2)
assert w.Write() == 1
w = vtk.vtkXMLUnstructuredGridWriter()
w.SetInputConnection(e.GetOutputPort())
w.SetFileName(os.path.join(d, "multi.vtu"))
w.SetNumberOfPieces(3)
assert w.Write() == 1
out = {}
for name, reader in (("box.pvtu", vtk.vtkXMLPUnstructuredGridReader()), ("multi.vtu", vtk.vtkXMLUnstructuredGridReader())):
    reader.SetFileName(os.path.join(d, name))
    reader.Update()
    g = reader.GetOutput()
    f = vtk.vtkCellSizeFilter()
    f.SetInputData(g)
    f.Update()
    o = f.GetOutput()
    sums = []
    for a in ("VertexCount", "Length", "Area", "Volume"):
        arr = o.GetCellData().GetArray(a)
        sums.append(sum(arr.GetValue(i) for i in range(o.GetNumberOfCells())))
    out[name] = [g.GetNumberOfPoints(), g.GetNumberOfCells()] + sums
print(json.dumps(out))
"#;

#[test]
fn pieces_of_vtk_s_parallel_and_multi_piece_files_are_appended() {
    smartmesh_test_support::require_public_fixtures!();
    let Some(py) = common::python_with(&["vtk"]) else { return };
    let dir = tempfile::tempdir().unwrap();
    let src = common::public_fixture("3d/box_cyl_binary_zlib.vtu");
    let out: serde_json::Value = serde_json::from_str(&common::run_python(
        &py,
        VTK_PIECES,
        &[src.to_str().unwrap(), dir.path().to_str().unwrap()],
    ))
    .unwrap();
    let whole = common::read_file("3d/box_cyl_binary_zlib.vtu");
    for name in ["box.pvtu", "multi.vtu"] {
        let m = smartmesh_formats::read_path(&dir.path().join(name), None)
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        let vtk: Vec<f64> =
            out[name].as_array().unwrap().iter().map(|v| v.as_f64().unwrap()).collect();
        let ours = measures(&m);
        // Points shared by two pieces are in both: more than the whole mesh's 634.
        assert_eq!(ours[0], vtk[0], "{name}: points");
        assert!(ours[0] > 634.0, "{name}");
        assert_eq!(ours[1], vtk[1], "{name}: cells");
        assert!((ours[4] - vtk[4]).abs() < 1e-9 * vtk[4], "{name}: area");
        assert!((ours[5] - vtk[5]).abs() < 1e-9 * vtk[5], "{name}: volume");
        assert_eq!(
            common::counts_per_tag(&m),
            common::counts_per_tag(&whole),
            "{name}: cells per tag"
        );
        assert_eq!(m.point_data["metric"].len(), m.points.len(), "{name}");
    }
    // A piece file that is not there is named.
    std::fs::remove_file(dir.path().join("box/box_1.vtu"))
        .or_else(|_| std::fs::remove_file(dir.path().join("box_1.vtu")))
        .unwrap();
    let e = smartmesh_formats::read_path(&dir.path().join("box.pvtu"), None).unwrap_err();
    assert!(e.to_string().contains("box_1.vtu"), "{e}");
}

#[test]
fn vtk_reads_the_vtp_we_write() {
    let Some(py) = common::python_with(&["vtk"]) else { return };
    let dir = tempfile::tempdir().unwrap();
    // Lines after triangles in the mesh: PolyData wants them first, data following.
    let text = "# vtk DataFile Version 4.2\nt\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 5 double\n\
        0 0 0 1 0 0 1 1 0 0 1 0 0.5 0.5 1\nCELLS 5 18\n3 0 1 4\n3 1 2 4\n4 0 1 2 3\n2 0 1\n1 4\n\
        CELL_TYPES 5\n5\n5\n9\n3\n1\nCELL_DATA 5\nSCALARS q double\nLOOKUP_TABLE default\n1 2 3 4 5\n";
    let m = legacy(text).unwrap();
    let path = dir.path().join("out.vtp");
    smartmesh_formats::write_path(&path, &m, None, &smartmesh_formats::WriteOptions::default())
        .unwrap();
    let script = r#"
import sys, json
import vtk
from vtk.util.numpy_support import vtk_to_numpy as v2n
r = vtk.vtkXMLPolyDataReader()
r.SetFileName(sys.argv[1])
r.Update()
g = r.GetOutput()
print(json.dumps(dict(verts=g.GetNumberOfVerts(), lines=g.GetNumberOfLines(), polys=g.GetNumberOfPolys(),
    q=v2n(g.GetCellData().GetArray("q")).tolist(),
    phys=v2n(g.GetCellData().GetArray("gmsh:physical")).tolist())))
"#;
    let out: serde_json::Value =
        serde_json::from_str(&common::run_python(&py, script, &[path.to_str().unwrap()])).unwrap();
    assert_eq!(out["verts"], 1);
    assert_eq!(out["lines"], 1);
    assert_eq!(out["polys"], 3);
    // VTK's cell order: the vertex, the line, then the polygons.
    assert_eq!(out["q"], serde_json::json!([5.0, 4.0, 1.0, 2.0, 3.0]));
    let back = smartmesh_formats::read_path(&path, None).unwrap();
    assert_eq!(measures(&back), measures(&m));
    assert_eq!(back.cell_data["q"].values, vec![5.0, 4.0, 1.0, 2.0, 3.0]);
    // Cells PolyData has no place for are refused, naming a .vtu.
    let mut tet = m.clone();
    let mut b = smartmesh_formats::CellBlock::new(CellKind::Tetra);
    b.push(&[0, 1, 2, 4], 0, 0);
    tet.blocks.push(b);
    tet.cell_data.clear();
    let e = smartmesh_formats::write_path(&path, &tet, None, &Default::default()).unwrap_err();
    assert!(e.to_string().contains("write a .vtu"), "{e}");
}

// ---------------------------------------------------------------------------------
// Malformed and extreme input: refused with a position, nothing allocated for what a
// header announces, no panic.

fn vtu(text: &str, ext: &str) -> Result<TaggedMesh, smartmesh_formats::Error> {
    smartmesh_formats::read_bytes(
        smartmesh_formats::Format::Vtu,
        text.as_bytes(),
        &smartmesh_formats::ReadContext::alone(ext),
    )
}

#[test]
fn headers_announcing_10_to_the_15_cells_allocate_nothing() {
    use smartmesh_formats::{ErrorKind, Position};
    let head = "# vtk DataFile Version 4.2\nt\nASCII\n";
    let tet = "POINTS 4 double\n0 0 0 1 0 0 0 1 0 0 0 1\n";
    for (text, line) in [
        (format!("{head}DATASET UNSTRUCTURED_GRID\n{tet}CELLS 1000000000000000 5000000000000000\n5 0 1 2 3\n"), 7),
        (format!("{head}DATASET UNSTRUCTURED_GRID\n{tet}CELLS 1 5\n4 0 1 2 3\nCELL_TYPES 1000000000000000\n10\n"), 9),
        (format!("{head}DATASET POLYDATA\n{tet}POLYGONS 1000000000000000 4000000000000000\n3 0 1 2\n"), 7),
        (format!("{head}DATASET UNSTRUCTURED_GRID\n{tet}CELLS 1000000000000001 5\nOFFSETS vtktypeint64\n0 4\n"), 7),
    ] {
        let e = legacy(&text).unwrap_err();
        assert!(
            matches!(e.kind, ErrorKind::ImplausibleCount { .. } | ErrorKind::Inconsistent(_)),
            "{e}"
        );
        assert_eq!(e.at, Some(Position::Line(line)), "{e}");
    }
    let piece = |attrs: &str, kind: &str| {
        format!(
            "<VTKFile type=\"{kind}\" version=\"1.0\"><{kind}><Piece NumberOfPoints=\"0\" {attrs}></Piece></{kind}></VTKFile>"
        )
    };
    for (text, ext) in [
        (piece("NumberOfCells=\"1000000000000000\"", "UnstructuredGrid"), "vtu"),
        (piece("NumberOfPolys=\"1000000000000000\"", "PolyData"), "vtp"),
        (
            piece(
                "NumberOfVerts=\"9223372036854775807\" NumberOfLines=\"9223372036854775807\"",
                "PolyData",
            ),
            "vtp",
        ),
    ] {
        let e = vtu(&text, ext).unwrap_err();
        assert!(matches!(e.kind, ErrorKind::ImplausibleCount { .. }), "{e}");
        assert!(matches!(e.at, Some(Position::Byte(_))), "{e}");
    }
}

#[test]
fn parallel_files_name_only_files_beside_them() {
    let dir = tempfile::tempdir().unwrap();
    let sub = dir.path().join("sub");
    std::fs::create_dir(&sub).unwrap();
    let pvtu = |source: &str| {
        format!(
            "<VTKFile type=\"PUnstructuredGrid\" version=\"1.0\"><PUnstructuredGrid><Piece Source=\"{source}\"/></PUnstructuredGrid></VTKFile>"
        )
    };
    // Outside the folder, absolute, or a parallel file naming itself: refused.
    std::fs::write(dir.path().join("secret.vtu"), "").unwrap();
    for (source, what) in [
        ("../secret.vtu", "no such file"),
        ("/etc/hostname", "no such file"),
        ("self.pvtu", "its pieces must be serial files"),
    ] {
        let p = sub.join("self.pvtu");
        std::fs::write(&p, pvtu(source)).unwrap();
        let e = smartmesh_formats::read_path(&p, None).unwrap_err();
        assert!(e.to_string().contains(what), "{source}: {e}");
    }
    // A piece that is not a mesh: the error names the piece's file.
    std::fs::write(
        sub.join("bad.vtu"),
        "<VTKFile type=\"UnstructuredGrid\"><Piece NumberOfPoints=\"x\">",
    )
    .unwrap();
    std::fs::write(sub.join("p.pvtu"), pvtu("bad.vtu")).unwrap();
    let e = smartmesh_formats::read_path(&sub.join("p.pvtu"), None).unwrap_err();
    assert!(e.to_string().contains("bad.vtu"), "{e}");
}

#[test]
fn a_large_non_convex_polygon_is_cut_quickly() {
    // A comb of 20 000 points: ear clipping would take n^3 steps.
    let n = 10_000;
    let mut pts = String::new();
    for i in 0..n {
        pts.push_str(&format!("{i} 0 0\n"));
    }
    for i in (0..n).rev() {
        pts.push_str(&format!("{i} {} 0\n", if i % 2 == 0 { 1.0 } else { 2.0 }));
    }
    let ids: Vec<String> = (0..2 * n).map(|i| i.to_string()).collect();
    let text = format!(
        "# vtk DataFile Version 4.2\nt\nASCII\nDATASET POLYDATA\nPOINTS {} double\n{pts}POLYGONS 1 {}\n{} {}\n",
        2 * n,
        2 * n + 1,
        2 * n,
        ids.join(" ")
    );
    let t = std::time::Instant::now();
    let m = legacy(&text).unwrap();
    assert_eq!(m.num_cells_of(CellKind::Triangle), 2 * n - 2);
    assert!(t.elapsed().as_secs() < 10, "{:?}", t.elapsed());
}
