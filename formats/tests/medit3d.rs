//! Medit in 3D: volume elements of every kind smartmesh and libMeshb share, surfaces in
//! space, `Corners`/`RequiredVertices`/`Ridges`, 3D solutions, read from the public
//! fixtures MMG and Gmsh wrote, written and read back, and adapted by MMG's own
//! `mmg3d_O3` and `mmgs_O3` (PyPI `mmgpy`). Interop tests skip when their Python modules
//! are missing, unless interop is required (CI), where they fail.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;
use std::process::Command;

use smartmesh_formats::{
    read_bytes, read_path, write_bytes, write_path, CellBlock, CellKind, DataArray, ErrorKind,
    Format, MeditWrite, Position, ReadContext, TaggedMesh, WriteOptions,
};
use smartmesh_test_support::formats::{
    counts_per_tag, python_with, read_file, roundtrip, run_python,
};

fn tags_of(m: &TaggedMesh, kind: CellKind) -> BTreeSet<i32> {
    m.cells().filter(|c| c.0 == kind).map(|c| c.2).collect()
}

fn binary(b: bool) -> WriteOptions {
    WriteOptions { medit: MeditWrite { binary: b }, ..Default::default() }
}

/// Everything two meshes must share after a Medit round trip.
fn assert_same(a: &TaggedMesh, b: &TaggedMesh, what: &str) {
    let bits = |m: &TaggedMesh| -> Vec<u64> {
        m.points.iter().flat_map(|p| p.iter().map(|c| c.to_bits())).collect()
    };
    assert!(bits(a) == bits(b), "{what}: points differ");
    assert_eq!(a.blocks.len(), b.blocks.len(), "{what}");
    for (x, y) in a.blocks.iter().zip(&b.blocks) {
        assert_eq!(x.kind, y.kind, "{what}");
        assert!(x.nodes == y.nodes, "{what}: {} nodes differ", x.kind.name());
        assert_eq!(x.physical, y.physical, "{what}");
    }
    assert_eq!(a.point_sets, b.point_sets, "{what}");
    assert_eq!(a.cell_sets, b.cell_sets, "{what}");
    assert_eq!(a.point_data.keys().collect::<Vec<_>>(), b.point_data.keys().collect::<Vec<_>>());
    for (k, v) in &a.point_data {
        let w = &b.point_data[k];
        assert_eq!(v.components, w.components, "{what}: {k}");
        let same = v.values.iter().zip(&w.values).all(|(p, q)| p.to_bits() == q.to_bits());
        assert!(same && v.values.len() == w.values.len(), "{what}: {k} differs");
    }
}

// -----------------------------------------------------------------------------------------
// The public fixtures
// -----------------------------------------------------------------------------------------

#[test]
fn reads_gmsh_box_cyl_with_its_metric() {
    smartmesh_test_support::require_public_fixtures!();
    let m = read_file("3d/box_cyl_input.mesh");
    assert_eq!(m.coordinate_dim, 3);
    assert_eq!(m.points.len(), 634);
    let c = counts_per_tag(&m);
    assert_eq!(c[&("line".to_string(), 20)], 16);
    assert_eq!(c[&("tetra".to_string(), 10)], 2187);
    assert_eq!(m.num_cells_of(CellKind::Triangle), 1012);
    assert_eq!(tags_of(&m, CellKind::Triangle), BTreeSet::from([1, 2, 3, 4]));
    // The .sol beside it: its first row is `16 0 16.000000000000004 0 8.88e-16 16`,
    // m11 m12 m22 m13 m23 m33, so m22 (row-major index 4) is the third value and m23
    // (indices 5 and 7) the fifth.
    let metric = &m.point_data["metric"];
    assert_eq!(metric.components, 9);
    let t = metric.item(0);
    assert_eq!(t[4], 16.000000000000004);
    assert_eq!(t[5], 8.881_784_197_001_252e-16);
    assert_eq!(t[7], t[5]);
    assert_eq!((t[2], t[6]), (0.0, 0.0));
    // Every tetrahedron of Gmsh's file has a positive volume in our (Gmsh's) order.
    assert!(volumes(&m).iter().all(|&v| v > 0.0));
}

/// The signed volume of every linear tetrahedron.
fn volumes(m: &TaggedMesh) -> Vec<f64> {
    let p = |i: u32| m.points[i as usize];
    m.cells()
        .filter(|c| c.0 == CellKind::Tetra)
        .map(|(_, n, _, _)| {
            let (a, b, c, d) = (p(n[0]), p(n[1]), p(n[2]), p(n[3]));
            let u = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
            let v = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
            let w = [d[0] - a[0], d[1] - a[1], d[2] - a[2]];
            ((u[1] * v[2] - u[2] * v[1]) * w[0]
                + (u[2] * v[0] - u[0] * v[2]) * w[1]
                + (u[0] * v[1] - u[1] * v[0]) * w[2])
                / 6.0
        })
        .collect()
}

#[test]
fn reads_mmg3d_output_ascii_and_binary_alike() {
    smartmesh_test_support::require_public_fixtures!();
    let a = read_file("3d/box_cyl_mmg.mesh");
    let b = read_file("3d/box_cyl_mmg.meshb");
    assert_eq!(a.points.len(), 1263);
    assert_eq!(a.num_cells_of(CellKind::Tetra), 4831);
    assert_eq!(a.num_cells_of(CellKind::Triangle), 1656);
    assert_eq!(a.num_cells_of(CellKind::Line), 205);
    let c = counts_per_tag(&a);
    assert_eq!(c[&("triangle".to_string(), 1)] + c[&("triangle".to_string(), 2)], 54 + 60);
    assert_eq!(c[&("line".to_string(), 20)], 54);
    assert_eq!(c[&("line".to_string(), 0)], 151);
    assert_eq!(a.point_sets["Corners"].len(), 33);
    assert_eq!(a.point_sets["RequiredVertices"].len(), 22);
    assert_eq!(a.cell_sets["Ridges"].len(), 205);
    assert!(volumes(&a).iter().all(|&v| v > 0.0));
    // The ASCII file prints 15 digits: the binary one has the exact coordinates.
    assert_eq!(a.blocks.len(), b.blocks.len());
    for (x, y) in a.blocks.iter().zip(&b.blocks) {
        assert_eq!((x.kind, &x.nodes, &x.physical), (y.kind, &y.nodes, &y.physical));
    }
    assert_eq!(a.point_sets, b.point_sets);
    assert_eq!(a.cell_sets, b.cell_sets);
    let worst = a
        .points
        .iter()
        .zip(&b.points)
        .flat_map(|(p, q)| (0..3).map(move |k| (p[k] - q[k]).abs()))
        .fold(0.0, f64::max);
    assert!(worst < 1e-12, "{worst}");
}

#[test]
fn public_3d_files_round_trip_exactly() {
    smartmesh_test_support::require_public_fixtures!();
    for rel in [
        "3d/box_cyl_input.mesh",
        "3d/box_cyl_mmg.mesh",
        "3d/box_cyl_mmg.meshb",
        "3d/box_cyl_surf_input.mesh",
        "3d/box_cyl_surf_mmgs.mesh",
    ] {
        let m = read_file(rel);
        for (ext, b) in [("mesh", false), ("meshb", true)] {
            let (w, back) = roundtrip(Format::Medit, ext, &m, &binary(b));
            assert!(w.report.dropped.is_empty(), "{rel}: {:?}", w.report.dropped);
            assert_same(&m, &back, &format!("{rel} as .{ext}"));
        }
    }
}

// -----------------------------------------------------------------------------------------
// Every volume kind
// -----------------------------------------------------------------------------------------

/// One cell of `kind` on nodes 0..n (the points are not a real element: the test is
/// about numbers), tagged 7, beside a tagged triangle and edge.
fn one_of(kind: CellKind) -> TaggedMesh {
    let n = kind.nodes_per_cell();
    let mut m = TaggedMesh::new();
    m.coordinate_dim = 3;
    m.points = (0..n).map(|i| [i as f64, (i * i) as f64 * 0.5, 1.0 + i as f64 / 3.0]).collect();
    let mut tri = CellBlock::new(CellKind::Triangle);
    tri.push(&[0u32, 1, 2], 3, 3);
    let mut vol = CellBlock::new(kind);
    vol.push(&(0..n as u32).collect::<Vec<_>>(), 7, 7);
    m.blocks = vec![tri, vol];
    m
}

#[test]
fn every_volume_kind_round_trips() {
    let kinds = [
        (CellKind::Tetra, "Tetrahedra"),
        (CellKind::Wedge, "Prisms"),
        (CellKind::Hexa, "Hexahedra"),
        (CellKind::Pyramid, "Pyramids"),
        (CellKind::Tetra10, "TetrahedraP2"),
        (CellKind::Wedge18, "PrismsP2"),
        (CellKind::Hexa27, "HexahedraQ2"),
        (CellKind::Pyramid14, "PyramidsP2"),
    ];
    for (kind, keyword) in kinds {
        let m = one_of(kind);
        for (ext, b) in [("mesh", false), ("meshb", true)] {
            let (w, back) = roundtrip(Format::Medit, ext, &m, &binary(b));
            assert!(w.report.dropped.is_empty(), "{keyword}: {:?}", w.report.dropped);
            assert_same(&m, &back, &format!("{keyword} .{ext}"));
            if !b {
                let text = String::from_utf8(w.main).unwrap();
                assert!(text.contains("Dimension 3"), "{text}");
                assert!(text.contains(&format!("\n{keyword}\n1\n")), "{text}");
            }
        }
    }
}

#[test]
fn second_order_tetrahedra_are_written_in_gmsh_medit_order() {
    let m = one_of(CellKind::Tetra10);
    let w = write_bytes(Format::Medit, &m, &binary(false)).unwrap();
    let text = String::from_utf8(w.main).unwrap();
    // Our nodes 0..9 in Gmsh's order: Medit's edge nodes 1-3 and 2-3 are Gmsh's 9 and 8.
    assert!(text.contains("TetrahedraP2\n1\n1 2 3 4 5 6 7 8 10 9 7\n"), "{text}");
}

#[test]
fn serendipity_volumes_are_reported_as_dropped() {
    for kind in [CellKind::Hexa20, CellKind::Wedge15, CellKind::Pyramid13] {
        let m = one_of(kind);
        let w = write_bytes(Format::Medit, &m, &binary(false)).unwrap();
        assert!(
            w.report.dropped.iter().any(|d| d.contains(kind.name()) && d.contains("serendipity")),
            "{:?}",
            w.report.dropped
        );
    }
}

#[test]
fn a_3d_metric_is_written_in_medit_order_and_read_back() {
    let mut m = one_of(CellKind::Tetra);
    let t = [4.0, 0.5, 0.25, 0.5, 3.0, 0.125, 0.25, 0.125, 2.0];
    m.point_data.insert("metric".into(), DataArray::new(9, t.repeat(m.points.len())));
    let w = write_bytes(Format::Medit, &m, &binary(false)).unwrap();
    let sol = String::from_utf8(w.siblings[0].1.clone()).unwrap();
    // m11 m12 m22 m13 m23 m33.
    assert!(sol.contains("1 3\n4.0 0.5 3.0 0.25 0.125 2.0\n"), "{sol}");
    let (_, back) = roundtrip(Format::Medit, "meshb", &m, &binary(true));
    assert_eq!(back.point_data["metric"].values, m.point_data["metric"].values);
}

// -----------------------------------------------------------------------------------------
// Malformed and extreme input
// -----------------------------------------------------------------------------------------

const HEAD3: &str =
    "MeshVersionFormatted 2\nDimension 3\nVertices\n4\n0 0 0 0\n1 0 0 0\n0 1 0 0\n0 0 1 0\n";

fn ascii_err(body: &str) -> smartmesh_formats::Error {
    read_bytes(Format::Medit, format!("{HEAD3}{body}").as_bytes(), &ReadContext::alone("mesh"))
        .expect_err("should fail")
}

#[test]
fn malformed_volume_sections() {
    // A count of 10^15 tetrahedra in a small file: refused before any allocation, at
    // the line of the count.
    let e = ascii_err("Tetrahedra\n1000000000000000\n1 2 3 4 0\n");
    assert!(matches!(e.kind, ErrorKind::ImplausibleCount { .. }), "{e}");
    assert_eq!(e.at, Some(Position::Line(10)), "{e}");
    // A node number past the vertices, on the line of the keyword.
    let e = ascii_err("Hexahedra\n1\n1 2 3 4 1 2 3 5 0\n");
    assert!(matches!(e.kind, ErrorKind::IndexOutOfRange { .. }), "{e}");
    assert!(e.to_string().contains("hexa"), "{e}");
    // A record cut short, at the end of the file or not.
    let e = ascii_err("Prisms\n1\n1 2 3 4 1 2\n");
    assert!(matches!(e.kind, ErrorKind::ImplausibleCount { .. }), "{e}");
    let e = ascii_err("Prisms\n1\n1 2 3 4 1 2\nEnd\n");
    assert!(e.to_string().contains("expected element reference, found `End`"), "{e}");
    assert_eq!(e.at, Some(Position::Line(12)), "{e}");
    let e = ascii_err("Polyhedra\n1\n");
    assert!(e.to_string().contains("Polyhedra") || matches!(e.kind, ErrorKind::Unsupported(_)));
}

/// A binary file of version 2: the header, Dimension 3, four vertices, then `tail`.
fn binary_with(tail: &[u8]) -> Vec<u8> {
    let mut b = Vec::new();
    let i = |b: &mut Vec<u8>, v: i32| b.extend_from_slice(&v.to_le_bytes());
    i(&mut b, 1);
    i(&mut b, 2);
    i(&mut b, 3);
    i(&mut b, 20);
    i(&mut b, 3);
    let start = b.len();
    i(&mut b, 4);
    let next = start + 12 + 4 * (3 * 8 + 4);
    i(&mut b, next as i32);
    i(&mut b, 4);
    for k in 0..4 {
        for c in 0..3 {
            b.extend_from_slice(&(if c + 1 == k { 1.0f64 } else { 0.0 }).to_le_bytes());
        }
        i(&mut b, 0);
    }
    assert_eq!(b.len(), next);
    b.extend_from_slice(tail);
    b
}

#[test]
fn malformed_binary_volume_sections() {
    let i = |v: i32| v.to_le_bytes();
    // Tetrahedra (8) announcing 2^31 - 1 records of 20 bytes in 28 bytes.
    let mut tail = Vec::new();
    tail.extend_from_slice(&i(8));
    tail.extend_from_slice(&i(0));
    tail.extend_from_slice(&i(i32::MAX));
    tail.extend_from_slice(&[1, 0, 0, 0, 2, 0, 0, 0, 3, 0, 0, 0, 4, 0, 0, 0, 0, 0, 0, 0]);
    let bytes = binary_with(&tail);
    let e = read_bytes(Format::Medit, &bytes, &ReadContext::alone("meshb")).unwrap_err();
    assert!(matches!(e.kind, ErrorKind::ImplausibleCount { .. }), "{e}");
    // One tetrahedron naming vertex 9 of 4: the byte of its record.
    let mut tail = Vec::new();
    tail.extend_from_slice(&i(8));
    tail.extend_from_slice(&i(0));
    tail.extend_from_slice(&i(1));
    for v in [1, 2, 3, 9, 0] {
        tail.extend_from_slice(&i(v));
    }
    let bytes = binary_with(&tail);
    let e = read_bytes(Format::Medit, &bytes, &ReadContext::alone("meshb")).unwrap_err();
    assert!(matches!(e.kind, ErrorKind::IndexOutOfRange { .. }), "{e}");
    assert_eq!(e.at, Some(Position::Byte(bytes.len() as u64 - 20)), "{e}");
    // The same tetrahedron with vertex 4: read.
    let n = bytes.len();
    let mut good = bytes.clone();
    good[n - 8..n - 4].copy_from_slice(&i(4));
    let m = read_bytes(Format::Medit, &good, &ReadContext::alone("meshb")).unwrap();
    assert_eq!(m.blocks[0].nodes, vec![0, 1, 2, 3]);
}

// -----------------------------------------------------------------------------------------
// Gmsh's Medit writer: the order of second-order tetrahedra
// -----------------------------------------------------------------------------------------

/// Meshes a box at order 2 with Gmsh, writes it as `.mesh`, and prints the coordinates
/// of the ten nodes of the first two tetrahedra in Gmsh's own order, one line each.
const GMSH_TET10: &str = r#"
import sys, gmsh
gmsh.initialize(); gmsh.option.setNumber("General.Terminal", 0)
gmsh.model.occ.addBox(0, 0, 0, 1, 1, 1); gmsh.model.occ.synchronize()
gmsh.option.setNumber("Mesh.MeshSizeMax", 0.6)
gmsh.model.mesh.generate(3); gmsh.model.mesh.setOrder(2)
gmsh.write(sys.argv[1])
tags, coords, _ = gmsh.model.mesh.getNodes()
xyz = dict(zip(tags, coords.reshape(-1, 3)))
_, _, nodes = gmsh.model.mesh.getElements(3)
for e in nodes[0].reshape(-1, 10)[:2]:
    print(" ".join(repr(float(c)) for n in e for c in xyz[n]))
"#;

#[test]
fn gmsh_second_order_tetrahedra_read_in_gmsh_order() {
    let Some(py) = python_with(&["gmsh"]) else { return };
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("t10.mesh");
    let out = run_python(&py, GMSH_TET10, &[path.to_str().unwrap()]);
    let m = read_path(&path, None).unwrap_or_else(|e| panic!("{e}"));
    let block = m.blocks.iter().find(|b| b.kind == CellKind::Tetra10).expect("tetra10");
    for line in out.lines() {
        let want: Vec<f64> = line.split_whitespace().map(|t| t.parse().unwrap()).collect();
        // The cell of ours with the same corners, in order, has the same ten nodes.
        // Gmsh prints about 14 digits in a .mesh.
        let near = |p: [f64; 3], j: usize| (0..3).all(|k| (p[k] - want[3 * j + k]).abs() < 1e-9);
        let found = block.cells().find(|c| (0..4).all(|j| near(m.points[c[j] as usize], j)));
        let cell = found.expect("Gmsh's tetrahedron among ours");
        for (j, &v) in cell.iter().enumerate() {
            assert!(near(m.points[v as usize], j), "node {j}");
        }
    }
}

// -----------------------------------------------------------------------------------------
// MMG adapts what we write
// -----------------------------------------------------------------------------------------

fn mmg_exe(py: &str, name: &str) -> String {
    let script = format!(
        "import mmgpy, os; print(os.path.join(os.path.dirname(mmgpy.__file__), 'bin', '{name}'))"
    );
    let exe = run_python(py, &script, &[]).trim().to_string();
    assert!(Path::new(&exe).exists(), "{name} not found at {exe}");
    exe
}

fn run(exe: &str, args: &[&Path], extra: &[&str]) {
    let mut c = Command::new(exe);
    for (flag, p) in ["-in", "-sol", "-out"].iter().zip(args) {
        if !p.as_os_str().is_empty() {
            c.arg(flag).arg(p);
        }
    }
    let out = c.args(extra).args(["-v", "1"]).output().expect("run MMG");
    assert!(
        out.status.success(),
        "{exe} failed ({}):\n{}\n{}",
        out.status,
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
}

fn write(mesh: &TaggedMesh, path: &Path) {
    let report =
        write_path(path, mesh, None, &WriteOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    assert!(report.dropped.is_empty(), "{}: {:?}", path.display(), report.dropped);
}

#[test]
fn mmg3d_adapts_our_mesh_and_metric() {
    smartmesh_test_support::require_public_fixtures!();
    let Some(py) = python_with(&["mmgpy"]) else { return };
    let exe = mmg_exe(&py, "mmg3d_O3");
    let input = read_file("3d/box_cyl_input.mesh");
    let reference = read_file("3d/box_cyl_mmg.mesh");
    for (name, sol) in [("in.mesh", "in.sol"), ("in.meshb", "in.solb")] {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join(name);
        write(&input, &path);
        let out = dir.path().join("out.mesh");
        run(&exe, &[&path, &dir.path().join(sol), &out], &["-hgrad", "-1"]);
        let adapted = read_path(&out, None).unwrap_or_else(|e| panic!("{e}"));
        // MMG keeps our references, and from the same input and metric makes the mesh
        // it made from Gmsh's file and the fixture's .sol.
        assert_eq!(tags_of(&adapted, CellKind::Tetra), BTreeSet::from([10]), "{name}");
        assert_eq!(tags_of(&adapted, CellKind::Triangle), BTreeSet::from([1, 2, 3, 4]));
        assert!(tags_of(&adapted, CellKind::Line).contains(&20));
        assert_eq!(counts_per_tag(&adapted), counts_per_tag(&reference), "{name}");
        assert_eq!(adapted.points.len(), reference.points.len());
        assert!(volumes(&adapted).iter().all(|&v| v > 0.0));
        assert_eq!(adapted.point_data["metric"].len(), adapted.points.len());
    }
}

/// A unit cube of 6 tetrahedra per cell, `n` cells a side, tagged 1, its boundary
/// triangles tagged 2.
fn cube(n: usize) -> TaggedMesh {
    let id = |i: usize, j: usize, k: usize| ((k * (n + 1) + j) * (n + 1) + i) as u32;
    let mut m = TaggedMesh::new();
    m.coordinate_dim = 3;
    for k in 0..=n {
        for j in 0..=n {
            for i in 0..=n {
                m.points.push([i as f64 / n as f64, j as f64 / n as f64, k as f64 / n as f64]);
            }
        }
    }
    let mut tets = CellBlock::new(CellKind::Tetra);
    // The six tetrahedra around the diagonal 0-6 of a cube (corners numbered as a
    // hexahedron's), each positive.
    const SIX: [[usize; 4]; 6] =
        [[0, 1, 2, 6], [0, 2, 3, 6], [0, 3, 7, 6], [0, 7, 4, 6], [0, 4, 5, 6], [0, 5, 1, 6]];
    let mut faces: BTreeMap<[u32; 3], ([u32; 3], usize)> = BTreeMap::new();
    for k in 0..n {
        for j in 0..n {
            for i in 0..n {
                let c = [
                    id(i, j, k),
                    id(i + 1, j, k),
                    id(i + 1, j + 1, k),
                    id(i, j + 1, k),
                    id(i, j, k + 1),
                    id(i + 1, j, k + 1),
                    id(i + 1, j + 1, k + 1),
                    id(i, j + 1, k + 1),
                ];
                for t in SIX {
                    let v = t.map(|x| c[x]);
                    tets.push(&v, 1, 1);
                    // Faces seen from outside: (0,2,1), (0,1,3), (1,2,3), (0,3,2).
                    for f in [[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]] {
                        let face = f.map(|x| v[x]);
                        let mut key = face;
                        key.sort_unstable();
                        faces.entry(key).or_insert((face, 0)).1 += 1;
                    }
                }
            }
        }
    }
    let mut tris = CellBlock::new(CellKind::Triangle);
    for (face, count) in faces.values() {
        if *count == 1 {
            tris.push(face, 2, 2);
        }
    }
    m.blocks = vec![tris, tets];
    m
}

/// The metric lengths of the edges of `m`'s tetrahedra in the constant metric `t`
/// (row-major 3x3), sorted.
fn metric_lengths(m: &TaggedMesh, t: &[f64; 9]) -> Vec<f64> {
    let mut edges = BTreeSet::new();
    for (_, c, _, _) in m.cells().filter(|c| c.0 == CellKind::Tetra) {
        for a in 0..4 {
            for b in a + 1..4 {
                edges.insert((c[a].min(c[b]), c[a].max(c[b])));
            }
        }
    }
    let mut l: Vec<f64> = edges
        .iter()
        .map(|&(a, b)| {
            let (p, q) = (m.points[a as usize], m.points[b as usize]);
            let e = [q[0] - p[0], q[1] - p[1], q[2] - p[2]];
            let mut s = 0.0;
            for r in 0..3 {
                for c in 0..3 {
                    s += e[r] * t[3 * r + c] * e[c];
                }
            }
            s.sqrt()
        })
        .collect();
    l.sort_by(f64::total_cmp);
    l
}

/// M = R diag(1/h²) Rᵀ with sizes 0.06, 0.15, 0.35 along axes turned away from x, y, z.
fn oblique_metric() -> [f64; 9] {
    let h = [0.06f64, 0.15, 0.35];
    // R = Rz(35°) Rx(50°): columns are the principal axes.
    let (a, b) = (35f64.to_radians(), 50f64.to_radians());
    let rz = [[a.cos(), -a.sin(), 0.0], [a.sin(), a.cos(), 0.0], [0.0, 0.0, 1.0]];
    let rx = [[1.0, 0.0, 0.0], [0.0, b.cos(), -b.sin()], [0.0, b.sin(), b.cos()]];
    let mut r = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            r[i][j] = (0..3).map(|k| rz[i][k] * rx[k][j]).sum();
        }
    }
    let mut t = [0.0; 9];
    for i in 0..3 {
        for j in 0..3 {
            t[3 * i + j] = (0..3).map(|k| r[i][k] * r[j][k] / (h[k] * h[k])).sum();
        }
    }
    t
}

#[test]
fn mmg3d_reads_our_anisotropic_metric_in_its_order() {
    let Some(py) = python_with(&["mmgpy"]) else { return };
    let exe = mmg_exe(&py, "mmg3d_O3");
    let t = oblique_metric();
    let mut m = cube(3);
    m.point_data.insert("metric".into(), DataArray::new(9, t.repeat(m.points.len())));
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("cube.mesh");
    write(&m, &path);
    let out = dir.path().join("out.mesh");
    run(&exe, &[&path, &dir.path().join("cube.sol"), &out], &["-hgrad", "-1"]);
    let adapted = read_path(&out, None).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(tags_of(&adapted, CellKind::Tetra), BTreeSet::from([1]));
    assert_eq!(tags_of(&adapted, CellKind::Triangle), BTreeSet::from([2]));
    let ours = metric_lengths(&adapted, &t);
    let median = ours[ours.len() / 2];
    assert!((0.7..1.3).contains(&median), "median metric length {median}");
    // The other order (m11 m12 m13 m22 m23 m33 read where the file has m11 m12 m22 m13
    // m23 m33) is another tensor: in it MMG's edges are far from unit length.
    let mut swapped = t;
    swapped[2] = t[4];
    swapped[6] = t[4];
    swapped[4] = t[2];
    let other = metric_lengths(&adapted, &swapped);
    let other_median = other[other.len() / 2];
    assert!((other_median - 1.0).abs() > 2.0 * (median - 1.0).abs(), "{other_median}");
    // MMG wrote its metric back (adjusted at the boundary, so not compared).
    assert_eq!(adapted.point_data["metric"].len(), adapted.points.len());
}

#[test]
fn mmg3d_adapts_our_mesh_to_an_isotropic_size() {
    let Some(py) = python_with(&["mmgpy"]) else { return };
    let exe = mmg_exe(&py, "mmg3d_O3");
    let mut m = cube(2);
    m.point_data.insert("size".into(), DataArray::new(1, vec![0.1; m.points.len()]));
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("cube.meshb");
    write(&m, &path);
    let out = dir.path().join("out.meshb");
    run(&exe, &[&path, &dir.path().join("cube.solb"), &out], &["-hgrad", "-1"]);
    let adapted = read_path(&out, None).unwrap_or_else(|e| panic!("{e}"));
    let l = metric_lengths(&adapted, &[100.0, 0.0, 0.0, 0.0, 100.0, 0.0, 0.0, 0.0, 100.0]);
    let median = l[l.len() / 2];
    assert!((0.7..1.3).contains(&median), "median length / h {median}");
    let v: f64 = volumes(&adapted).iter().sum();
    assert!((v - 1.0).abs() < 1e-9, "volume {v}");
}

#[test]
fn mmgs_adapts_our_surface_in_space() {
    smartmesh_test_support::require_public_fixtures!();
    let Some(py) = python_with(&["mmgpy"]) else { return };
    let exe = mmg_exe(&py, "mmgs_O3");
    let input = read_file("3d/box_cyl_surf_input.mesh");
    let reference = read_file("3d/box_cyl_surf_mmgs.mesh");
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("surf.mesh");
    write(&input, &path);
    let out = dir.path().join("out.mesh");
    run(&exe, &[&path, Path::new(""), &out], &["-hmax", "0.15"]);
    let adapted = read_path(&out, None).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(tags_of(&adapted, CellKind::Triangle), BTreeSet::from([1, 2, 3, 4]));
    // The same run on Gmsh's file gave the fixture.
    assert_eq!(counts_per_tag(&adapted), counts_per_tag(&reference));
    assert_eq!(adapted.points.len(), reference.points.len());
}

// -----------------------------------------------------------------------------------------
// Damaged 3D files
// -----------------------------------------------------------------------------------------

/// Copies of `bytes` cut short and with bytes replaced, the same every run (a fixed
/// xorshift sequence): a deterministic complement to the `medit` fuzz target.
fn damaged(bytes: &[u8]) -> Vec<Vec<u8>> {
    let mut state = 0x5eed_3d3d_1234_9876u64;
    let mut below = |n: usize| {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state % n.max(1) as u64) as usize
    };
    let n = bytes.len();
    let mut v: Vec<Vec<u8>> = (0..24).map(|k| bytes[..(k * n / 24).min(n)].to_vec()).collect();
    for _ in 0..48 {
        let mut b = bytes.to_vec();
        for _ in 0..1 + below(4) {
            let i = below(n);
            b[i] = [b'9', b'-', 0xff, b'\n', b' ', 0x7f, 0][below(7)];
        }
        v.push(b);
    }
    v
}

#[test]
fn damaged_3d_files_are_refused_or_read_never_panic() {
    smartmesh_test_support::require_public_fixtures!();
    let root = smartmesh_test_support::formats::public_fixture("3d");
    for (name, ext) in [("box_cyl_mmg.meshb", "meshb"), ("box_cyl_input.mesh", "mesh")] {
        let bytes = std::fs::read(root.join(name)).unwrap();
        let mut refused = 0;
        let copies = damaged(&bytes);
        for d in &copies {
            let r =
                std::panic::catch_unwind(|| read_bytes(Format::Medit, d, &ReadContext::alone(ext)));
            match r {
                Ok(Ok(m)) => assert_eq!(m.validate(), Vec::new()),
                Ok(Err(e)) => {
                    refused += 1;
                    assert!(!e.to_string().is_empty());
                }
                Err(_) => panic!("the Medit reader panicked on a damaged {name}"),
            }
        }
        assert!(refused > copies.len() / 4, "{name}: {refused} of {} refused", copies.len());
    }
}
