//! Reading Fluent meshes: our own writer's files read back (2D and 3D public samples:
//! the same cells by their coordinates, each with the same outward faces, i.e. the
//! same node order up to the cell's symmetries and a positive volume; the same
//! boundary cells per tag name), files meshio's `ansys` writer makes (ASCII and binary,
//! cells by nodes) read with meshio's counts, and malformed files refused with their
//! position.

use std::collections::BTreeMap;

use smartmesh_formats::{
    read_bytes, read_bytes_reported, read_path, write_bytes, CellKind, Error, Format, ReadContext,
    TaggedMesh, WriteOptions,
};
use smartmesh_test_support::formats::{public_fixture, python_with, read_file, run_python};

type Key = Vec<Vec<[u64; 3]>>;

fn bits(p: [f64; 3]) -> [u64; 3] {
    // +0.0 and -0.0 are one coordinate.
    p.map(|x| if x == 0.0 { 0 } else { x.to_bits() })
}

/// A cycle of points from its least point.
fn cycle(mut c: Vec<[u64; 3]>) -> Vec<[u64; 3]> {
    let m = (0..c.len()).min_by_key(|&i| c[i]).unwrap_or(0);
    c.rotate_left(m);
    c
}

/// A cell by its oriented faces (3D) or its counter-clockwise cycle (2D).
fn cell_key(mesh: &TaggedMesh, kind: CellKind, nodes: &[u32]) -> Key {
    let p = |v: u32| mesh.points[v as usize];
    if kind.dim() == 3 {
        let mut fs: Key = kind
            .faces()
            .iter()
            .map(|f| cycle(f.iter().map(|&k| bits(p(nodes[k]))).collect()))
            .collect();
        fs.sort();
        fs
    } else {
        let n = nodes.len();
        let area: f64 = (0..n)
            .map(|i| {
                let (a, b) = (p(nodes[i]), p(nodes[(i + 1) % n]));
                a[0] * b[1] - a[1] * b[0]
            })
            .sum();
        let mut c: Vec<[u64; 3]> = nodes.iter().map(|&v| bits(p(v))).collect();
        if area < 0.0 {
            c.reverse();
        }
        vec![cycle(c)]
    }
}

/// Every cell of dimension `dim`, by key, counted.
fn cells_of(mesh: &TaggedMesh, dim: u8) -> BTreeMap<(CellKind, Key), usize> {
    let mut out = BTreeMap::new();
    for b in mesh.blocks.iter().filter(|b| b.kind.dim() == dim) {
        for c in b.cells() {
            *out.entry((b.kind, cell_key(mesh, b.kind, c))).or_default() += 1;
        }
    }
    out
}

/// Boundary cells per tag name.
fn named_counts(mesh: &TaggedMesh, dim: u8) -> BTreeMap<String, usize> {
    let mut out = BTreeMap::new();
    for b in mesh.blocks.iter().filter(|b| b.kind.dim() == dim) {
        for &t in &b.physical {
            if let Some(n) = mesh.tag_name(dim, t) {
                *out.entry(n.to_string()).or_default() += 1;
            }
        }
    }
    out
}

fn round_trip(rel: &str, dim: u8) {
    let mesh = read_file(rel);
    let written = write_bytes(Format::Fluent, &mesh, &WriteOptions::default()).unwrap();
    let (back, report) =
        read_bytes_reported(Format::Fluent, &written.main, &ReadContext::alone("msh"))
            .unwrap_or_else(|e| panic!("{rel}: {e}"));
    assert_eq!(back.coordinate_dim, dim);
    let (a, b) = (cells_of(&mesh, dim), cells_of(&back, dim));
    assert_eq!(a.values().sum::<usize>(), b.values().sum::<usize>(), "{rel}");
    assert!(a == b, "{rel}: the cells read back differ from the cells written");
    let used: std::collections::BTreeSet<[u64; 3]> =
        a.keys().flat_map(|(_, k)| k.iter().flatten().copied()).collect();
    assert_eq!(back.points.len(), used.len(), "{rel}");
    // Boundary cells keep their tag names and counts.
    let names = named_counts(&mesh, dim - 1);
    let got = named_counts(&back, dim - 1);
    assert!(!names.is_empty(), "{rel}: a sample with named boundaries");
    for (n, c) in &names {
        assert_eq!(got.get(n), Some(c), "{rel}: boundary `{n}` ({got:?})");
    }
    assert!(report.notes.iter().any(|n| n.contains("default-interior")), "{:?}", report.notes);
}

#[test]
fn our_2d_files_read_back_with_their_cells_and_names() {
    smartmesh_test_support::require_public_fixtures!();
    round_trip("gmsh/naca0012.v41_ascii.msh", 2);
    round_trip("gmsh/square_hole.v41_ascii.msh", 2);
}

#[test]
fn our_3d_files_read_back_with_their_cells_and_names() {
    smartmesh_test_support::require_public_fixtures!();
    round_trip("3d/hex_prism_pyr.v41_ascii.msh", 3);
    round_trip("3d/box_cyl.v41_ascii.msh", 3);
}

/// meshio's ansys writer, the top-dimension cells of a sample, ASCII then binary; the
/// file read by its path (`.msh`, recognised as Fluent by its first byte) must hold
/// meshio's counts.
#[test]
fn meshio_ansys_files_read_with_their_counts() {
    smartmesh_test_support::require_public_fixtures!();
    let Some(py) = python_with(&["meshio"]) else { return };
    let script = r#"
import sys, meshio
m = meshio.read(sys.argv[1])
dim = int(sys.argv[3])
keep = {2: ["triangle", "quad"], 3: ["tetra", "hexahedron", "wedge", "pyramid"]}[dim]
cells = [c for c in m.cells if c.type in keep]
pts = m.points[:, :dim]
out = meshio.Mesh(pts, cells)
meshio.write(sys.argv[2], out, file_format="ansys", binary=sys.argv[4] == "1")
print(len(pts), " ".join(f"{c.type}:{len(c.data)}" for c in cells))
"#;
    let dir = tempfile::tempdir().unwrap();
    for (rel, dim) in [("gmsh/naca0012.v41_ascii.msh", 2), ("3d/hex_prism_pyr.v41_ascii.msh", 3)] {
        for binary in ["0", "1"] {
            let out = dir.path().join("m.msh");
            let src = public_fixture(rel);
            let printed = run_python(
                &py,
                script,
                &[src.to_str().unwrap(), out.to_str().unwrap(), &dim.to_string(), binary],
            );
            let mesh = read_path(&out, None).unwrap_or_else(|e| panic!("{rel} {binary}: {e}"));
            let mut words = printed.split_whitespace();
            let np: usize = words.next().unwrap().parse().unwrap();
            assert_eq!(mesh.points.len(), np, "{rel} binary={binary}");
            for w in words {
                let (t, n) = w.split_once(':').unwrap();
                let kind = match t {
                    "triangle" => CellKind::Triangle,
                    "quad" => CellKind::Quad,
                    "tetra" => CellKind::Tetra,
                    "hexahedron" => CellKind::Hexa,
                    "wedge" => CellKind::Wedge,
                    _ => CellKind::Pyramid,
                };
                assert_eq!(mesh.num_cells_of(kind), n.parse::<usize>().unwrap(), "{rel} {t}");
            }
        }
    }
}

fn refuse(text: &[u8]) -> Error {
    match read_bytes(Format::Fluent, text, &ReadContext::alone("msh")) {
        Ok(_) => panic!("accepted {:?}", String::from_utf8_lossy(text)),
        Err(e) => e,
    }
}

#[test]
fn malformed_files_are_refused_with_their_position() {
    let ok = b"(2 2)\n(10 (1 1 3 1 2)(\n0 0\n1 0\n0 1\n))\n(12 (2 1 1 1 1))\n\
(13 (3 1 3 3 2)(\n1 2 1 0\n2 3 1 0\n3 1 1 0\n))\n(45 (3 wall Sides)())\n";
    let m = read_bytes(Format::Fluent, ok, &ReadContext::alone("msh")).unwrap();
    assert_eq!(m.num_cells_of(CellKind::Triangle), 1);
    assert_eq!(m.num_cells_of(CellKind::Line), 3);
    assert_eq!(m.tag_name(1, 3), Some("Sides"));

    let e = refuse(b"(2 2)\n(10 (1 1 3 1 2)(\n0 0\n1 x\n0 1\n))\n");
    assert!(e.to_string().contains(":4:") && e.to_string().contains("coordinate"), "{e}");
    // A header announcing 2^40 nodes allocates nothing.
    let e = refuse(b"(2 3)\n(10 (1 1 ffffffffff 1 3)(\n0 0 0\n))");
    assert!(e.to_string().contains("announces"), "{e}");
    let e = refuse(b"(2 2)\n(13 (3 1 ffffffff 3 0)(\n");
    assert!(e.to_string().contains("announces"), "{e}");
    // A face naming a node that does not exist.
    let bad = String::from_utf8_lossy(ok).replace("3 1 1 0", "3 9 1 0");
    let e = refuse(bad.as_bytes());
    assert!(e.to_string().contains(":8:") && e.to_string().contains("refers to 9"), "{e}");
    // A section never closed, a binary section cut short.
    let e = refuse(b"(2 2)\n(0 \"comment");
    assert!(e.to_string().contains(":2:"), "{e}");
    let e = refuse(b"(2 3)\n(3010 (1 1 2 1 3)(\x00\x00\x00");
    assert!(e.to_string().contains("byte"), "{e}");
    let e = refuse(b"(2 3)\n(12 (1 1 1 1 2)(");
    assert!(e.to_string().contains("end of file") || e.to_string().contains("announces"), "{e}");
    // Cells whose faces are not a cell.
    let bad = String::from_utf8_lossy(ok).replace("3 1 1 0", "3 2 1 0");
    let e = refuse(bad.as_bytes());
    assert!(e.to_string().contains(":8:") && e.to_string().contains("cell 1"), "{e}");
}

/// A binary file of one unit tetrahedron (double-precision nodes, 32-bit faces), each
/// face's right-hand normal into its cell c0 as Fluent's convention has it.
fn binary_tetra() -> Vec<u8> {
    binary_tetra_with([[1, 2, 3], [1, 4, 2], [2, 4, 3], [1, 3, 4]])
}

fn binary_tetra_with(faces: [[i32; 3]; 4]) -> Vec<u8> {
    let mut b = b"(0 \"binary\")\n(2 3)\n(10 (0 1 4 0 3))\n(3010 (1 1 4 1 3)(".to_vec();
    for x in [0.0f64, 0., 0., 1., 0., 0., 0., 1., 0., 0., 0., 1.] {
        b.extend(x.to_le_bytes());
    }
    b.extend(b")End of Binary Section 3010)\n(12 (2 1 1 1 2))\n(2013 (3 1 4 3 3)(");
    for f in faces {
        for v in f.into_iter().chain([1, 0]) {
            b.extend(v.to_le_bytes());
        }
    }
    b.extend(b")End of Binary Section 2013)\n(45 (2 fluid Solid)())\n(45 (3 wall Skin)())\n");
    b
}

#[test]
fn a_binary_tetrahedron_reads_with_a_positive_volume() {
    let (m, report) =
        read_bytes_reported(Format::Fluent, &binary_tetra(), &ReadContext::alone("msh")).unwrap();
    assert!(report.notes.is_empty(), "{:?}", report.notes);
    check_tetra(&m);
    // Faces following the opposite rule (normals out of c0): the same tetrahedron, said.
    let other = binary_tetra_with([[1, 3, 2], [1, 2, 4], [2, 3, 4], [1, 4, 3]]);
    let (m, report) =
        read_bytes_reported(Format::Fluent, &other, &ReadContext::alone("msh")).unwrap();
    assert!(report.notes.iter().any(|n| n.contains("opposite right-hand rule")), "{report:?}");
    check_tetra(&m);
    damaged_binary_never_panics();
}

fn check_tetra(m: &TaggedMesh) {
    let tets: Vec<&[u32]> =
        m.blocks.iter().filter(|b| b.kind == CellKind::Tetra).flat_map(|b| b.cells()).collect();
    assert_eq!(tets.len(), 1);
    let p = |i: usize| m.points[tets[0][i] as usize];
    let (a, b, c, d) = (p(0), p(1), p(2), p(3));
    let e = |u: [f64; 3]| [u[0] - a[0], u[1] - a[1], u[2] - a[2]];
    let (u, v, w) = (e(b), e(c), e(d));
    let det = u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0])
        + u[2] * (v[0] * w[1] - v[1] * w[0]);
    assert!((det - 1.0).abs() < 1e-12, "6 × volume {det}");
    assert_eq!(m.num_cells_of(CellKind::Triangle), 4);
    assert_eq!(m.tag_name(3, 2), Some("Solid"));
    assert_eq!(m.tag_name(2, 3), Some("Skin"));
    // Every boundary triangle points out: its normal away from the centroid.
    for t in m.blocks.iter().filter(|b| b.kind == CellKind::Triangle).flat_map(|b| b.cells()) {
        let q = |i: usize| m.points[t[i] as usize];
        let (x, y) = (e2(q(0), q(1)), e2(q(0), q(2)));
        let n = [x[1] * y[2] - x[2] * y[1], x[2] * y[0] - x[0] * y[2], x[0] * y[1] - x[1] * y[0]];
        let out = e2([0.25; 3], q(0));
        assert!(n[0] * out[0] + n[1] * out[1] + n[2] * out[2] > 0.0, "{t:?}");
    }
}

/// Truncated anywhere or with a byte changed: Ok or an error, no panic.
fn damaged_binary_never_panics() {
    let bytes = binary_tetra();
    for cut in 0..bytes.len() {
        let _ = read_bytes(Format::Fluent, &bytes[..cut], &ReadContext::alone("msh"));
    }
    for i in 0..bytes.len() {
        for v in [0u8, 0xff, b'(', b')', 0x7f] {
            let mut b = bytes.clone();
            b[i] = v;
            if let Ok(m) = read_bytes(Format::Fluent, &b, &ReadContext::alone("msh")) {
                assert_eq!(m.validate(), Vec::new());
            }
        }
    }
}

fn e2(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [b[0] - a[0], b[1] - a[1], b[2] - a[2]]
}
