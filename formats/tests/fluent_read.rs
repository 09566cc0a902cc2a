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
    assert!(e.to_string().contains("refers to 9"), "{e}");
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
    assert!(e.to_string().contains("cell 1"), "{e}");
}
