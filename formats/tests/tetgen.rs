//! TetGen's files: the mesh set (.node/.ele/.face/.edge) and PLCs (.smesh/.poly), read,
//! written and read back; told apart from Triangle's by their headers; refused when
//! malformed; read by meshio and tetrahedralised by TetGen itself (PyPI `tetgen`), whose
//! output we read. Interop tests skip when their Python modules are missing, unless
//! interop is required (CI), where they fail.

use std::collections::BTreeSet;
use std::path::Path;

use smartmesh_formats::{
    read_bytes, read_bytes_reported, read_path, write_bytes, write_path, CellKind, ErrorKind,
    Format, MemorySiblings, Position, ReadContext, TaggedMesh, WriteOptions,
};
use smartmesh_test_support::formats::{counts_per_tag, python_with, read_file, run_python};

fn named(name: &str) -> WriteOptions {
    WriteOptions { main_name: Some(name.into()), ..Default::default() }
}

/// Writes `m` as TetGen with main file `name` and reads it back from memory.
fn roundtrip(m: &TaggedMesh, name: &str) -> (Vec<String>, TaggedMesh) {
    let w = write_bytes(Format::TetGen, m, &named(name)).unwrap_or_else(|e| panic!("{e}"));
    let sib = MemorySiblings::from_written(&w);
    let ext = Path::new(name).extension().unwrap().to_str().unwrap();
    let ctx = ReadContext { siblings: &sib, extension: ext.into() };
    let back = read_bytes(Format::TetGen, &w.main, &ctx).unwrap_or_else(|e| panic!("{e}"));
    (w.report.dropped, back)
}

fn same_cells(a: &TaggedMesh, b: &TaggedMesh) {
    let bits = |m: &TaggedMesh| -> Vec<u64> {
        m.points.iter().flat_map(|p| p.iter().map(|c| c.to_bits())).collect()
    };
    assert!(bits(a) == bits(b), "points differ");
    let cells = |m: &TaggedMesh| -> Vec<(CellKind, Vec<u32>, i32)> {
        let mut v: Vec<_> = m.cells().map(|(k, n, p, _)| (k, n.to_vec(), p)).collect();
        v.sort();
        v
    };
    assert!(cells(a) == cells(b), "cells differ");
}

#[test]
fn mesh_set_round_trips_with_tags() {
    smartmesh_test_support::require_public_fixtures!();
    let m = read_file("3d/box_cyl_input.mesh");
    for name in ["x.node", "x.ele", "x.face", "x.edge"] {
        let (dropped, back) = roundtrip(&m, name);
        same_cells(&m, &back);
        assert_eq!(counts_per_tag(&back), counts_per_tag(&m));
        // What TetGen cannot hold is said: the vertex references and the metric.
        assert!(dropped.iter().any(|d| d.contains("medit:ref")), "{dropped:?}");
        assert!(dropped.iter().any(|d| d.contains("metric")), "{dropped:?}");
    }
}

#[test]
fn plc_round_trips_with_markers_and_seeds() {
    smartmesh_test_support::require_public_fixtures!();
    let surf = read_file("3d/box_cyl_surf_input.mesh");
    for name in ["s.smesh", "s.poly"] {
        let (_, back) = roundtrip(&surf, name);
        same_cells(&surf, &back);
    }
    // A volume mesh as a PLC: its boundary, and one seed per tetrahedron tag (dropped
    // on reading, said so).
    let m = read_file("3d/box_cyl_input.mesh");
    let w = write_bytes(Format::TetGen, &m, &named("v.smesh")).unwrap();
    let text = String::from_utf8(w.main.clone()).unwrap();
    let last: Vec<&str> = text.lines().rev().take(2).collect();
    assert_eq!(last[1], "1", "{last:?}");
    assert!(last[0].ends_with(" 10 -1"), "{last:?}");
    assert!(w.report.dropped.iter().any(|d| d.contains("2187 tetra")), "{:?}", w.report.dropped);
    let (back, report) =
        read_bytes_reported(Format::TetGen, &w.main, &ReadContext::alone("smesh")).unwrap();
    assert_eq!(back.num_cells_of(CellKind::Triangle), 1012);
    assert_eq!(back.num_cells_of(CellKind::Tetra), 0);
    assert!(report.notes.iter().any(|n| n.contains("1 region seeds")), "{report:?}");
}

#[test]
fn a_3d_node_or_ele_is_read_as_tetgen() {
    let node =
        "# a tetrahedron\n4 3 1 1\n0 0 0 0 0.5 7\n1 1 0 0 0.5 7\n2 0 1 0 0.5 7\n3 0 0 1 0.5 8\n";
    let ele = "1 4 1\n0 0 1 2 3 5\n";
    let face = "1 1\n0 0 2 1 3\n";
    let mut sib = MemorySiblings::default();
    sib.files.insert("node".into(), node.as_bytes().to_vec());
    sib.files.insert("face".into(), face.as_bytes().to_vec());
    // By extension .ele, which the table gives to Triangle: its header says 4 nodes.
    assert_eq!(Format::from_path("x.ele"), Some(Format::Triangle));
    let ctx = ReadContext { siblings: &sib, extension: "ele".into() };
    let m = read_bytes(Format::Triangle, ele.as_bytes(), &ctx).unwrap();
    assert_eq!(m.blocks.len(), 2);
    assert_eq!(m.cells().find(|c| c.0 == CellKind::Tetra).unwrap().1, &[0, 1, 2, 3]);
    assert_eq!(counts_per_tag(&m)[&("tetra".to_string(), 5)], 1);
    assert_eq!(counts_per_tag(&m)[&("triangle".to_string(), 3)], 1);
    assert_eq!(m.point_data["tetgen:marker"].values, vec![7.0, 7.0, 7.0, 8.0]);
    assert_eq!(m.point_data["tetgen:attribute1"].values, vec![0.5; 4]);
    // And the .node alone, by its dimension.
    let m = read_bytes(Format::Triangle, node.as_bytes(), &ReadContext::alone("node")).unwrap();
    assert_eq!((m.points.len(), m.coordinate_dim), (4, 3));
    // A 2D .node stays Triangle's.
    let m = read_bytes(Format::Triangle, b"1 2 0 0\n1 0.5 0.25\n", &ReadContext::alone("node"));
    assert_eq!(m.unwrap().coordinate_dim, 2);
    // Written back and read again: the same cells, tags and point arrays.
    let orig = read_bytes(Format::Triangle, ele.as_bytes(), &ctx).unwrap();
    let (dropped, back) = roundtrip(&orig, "y.ele");
    assert!(dropped.is_empty(), "{dropped:?}");
    same_cells(&orig, &back);
    assert_eq!(back.point_data, orig.point_data);
}

#[test]
fn triangle_refuses_volume_cells_with_the_reason() {
    smartmesh_test_support::require_public_fixtures!();
    let m = read_file("3d/box_cyl_input.mesh");
    let e = write_bytes(Format::Triangle, &m, &named("x.ele")).unwrap_err();
    let text = e.to_string();
    assert!(text.contains("2187 tetra cells") && text.contains("--to tetgen"), "{text}");
}

#[test]
fn malformed_tetgen_files() {
    let alone = |s: &str, ext: &str| {
        read_bytes(Format::TetGen, s.as_bytes(), &ReadContext::alone(ext)).unwrap_err()
    };
    let mut sib = MemorySiblings::default();
    sib.files.insert("node".into(), b"4 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n".to_vec());
    let ele = |s: &str| {
        let ctx = ReadContext { siblings: &sib, extension: "ele".into() };
        read_bytes(Format::TetGen, s.as_bytes(), &ctx).unwrap_err()
    };
    // 10^15 tetrahedra announced in a few bytes: refused at the header's line.
    let e = ele("# big\n1000000000000000 4 0\n1 1 2 3 4\n");
    assert!(matches!(e.kind, ErrorKind::ImplausibleCount { .. }), "{e}");
    assert_eq!(e.at, Some(Position::Line(2)));
    let e = alone("1000000000000000 3 0 0\n1 0 0 0\n", "node");
    assert!(matches!(e.kind, ErrorKind::ImplausibleCount { .. }), "{e}");
    // A vertex past the list, on its line.
    let e = ele("1 4 0\n1 1 2 3 5\n");
    assert!(matches!(e.kind, ErrorKind::IndexOutOfRange { .. }), "{e}");
    assert_eq!(e.at, Some(Position::Line(2)));
    // Other node counts and 2D vertices: said so.
    let e = ele("1 6 0\n1 1 2 3 4 1 2\n");
    assert!(e.to_string().contains("4 or 10 nodes per tetrahedron"), "{e}");
    let e = alone("1 2 0 0\n1 0 0\n", "node");
    assert!(e.to_string().contains("dimension 3"), "{e}");
    // A pentagon facet; a record cut short; a .ele without its .node.
    let e =
        alone("5 3 0 0\n1 0 0 0\n2 1 0 0\n3 1 1 0\n4 0 1 0\n5 0 0 1\n1 0\n5 1 2 3 4 5\n", "smesh");
    assert!(matches!(e.kind, ErrorKind::Unsupported(_)), "{e}");
    assert_eq!(e.at, Some(Position::Line(8)));
    let e = alone("2 3 0 0\n1 0 0 0\n2 1 0\n", "node");
    assert_eq!(e.at, Some(Position::Line(3)), "{e}");
    let e = alone("1 4 0\n1 1 2 3 4\n", "ele");
    assert!(e.to_string().contains(".node"), "{e}");
}

// -----------------------------------------------------------------------------------------
// The owners' tools
// -----------------------------------------------------------------------------------------

/// meshio reads our .node/.ele: prints the number of points, the tetrahedra's sum of
/// |volume| and their distinct region attributes.
const MESHIO_READ: &str = r#"
import sys, meshio, numpy as np
m = meshio.read(sys.argv[1])
t = m.cells_dict["tetra"]; p = m.points
a, b, c, d = (p[t[:, k]] for k in range(4))
v = np.einsum("ij,ij->i", np.cross(b - a, c - a), d - a) / 6
print(len(p), len(t), repr(float(abs(v).sum())), sorted(set(int(x) for x in m.cell_data["tetgen:ref"][0])))
"#;

fn volume(m: &TaggedMesh) -> f64 {
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
                .abs()
                / 6.0
        })
        .sum()
}

#[test]
fn meshio_reads_our_node_and_ele() {
    smartmesh_test_support::require_public_fixtures!();
    let Some(py) = python_with(&["meshio"]) else { return };
    let m = read_file("3d/box_cyl_input.mesh");
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("box.ele");
    write_path(&path, &m, Some(Format::TetGen), &WriteOptions::default()).unwrap();
    let out = run_python(&py, MESHIO_READ, &[path.to_str().unwrap()]);
    let f: Vec<&str> = out.split_whitespace().collect();
    assert_eq!((f[0], f[1]), ("634", "2187"), "{out}");
    let v: f64 = f[2].parse().unwrap();
    assert!((v - volume(&m)).abs() < 1e-12, "{v} vs {}", volume(&m));
    assert_eq!(f[3], "[10]", "{out}");
}

/// Reads the PLC we wrote (a .smesh: vertices, triangle facets with markers, no holes,
/// region seeds) with a few lines of Python, since the PyPI `tetgen` API takes arrays and
/// reads no file; tetrahedralises it with TetGen (`-pqA`), and writes TetGen's nodes,
/// tetrahedra and region attributes with meshio's TetGen writer, for us to read.
const TETGEN_RUN: &str = r##"
import sys, numpy as np, tetgen, meshio
recs = [l.split("#")[0].split() for l in open(sys.argv[1])]
recs = [r for r in recs if r]
n = int(recs[0][0]); pts = np.array([[float(x) for x in r[1:4]] for r in recs[1:1 + n]])
nf = int(recs[1 + n][0]); facets = recs[2 + n:2 + n + nf]
tris = np.array([[int(x) - 1 for x in f[1:4]] for f in facets if f[0] == "3"], dtype=np.int32)
rest = recs[2 + n + nf:]
nh = int(rest[0][0]); nr = int(rest[1 + nh][0]); regions = rest[2 + nh:2 + nh + nr]
tg = tetgen.TetGen(pts, tris)
for r in regions:
    tg.add_region(int(r[4]), [float(x) for x in r[1:4]])
node, elem, attr, _ = tg.tetrahedralize(switches="pq1.4AQ")
meshio.write(sys.argv[2], meshio.Mesh(node, [("tetra", elem)], cell_data={"tetgen:ref": [attr.astype(int).ravel()]}), file_format="tetgen")
print(len(node), len(elem), sorted(set(int(a) for a in attr.ravel())))
"##;

#[test]
fn tetgen_tetrahedralises_our_plc_and_we_read_its_mesh() {
    smartmesh_test_support::require_public_fixtures!();
    let Some(py) = python_with(&["tetgen", "meshio"]) else { return };
    let m = read_file("3d/box_cyl_input.mesh");
    let dir = tempfile::tempdir().unwrap();
    let plc = dir.path().join("box.smesh");
    write_path(&plc, &m, None, &WriteOptions::default()).unwrap();
    let out_node = dir.path().join("out.node");
    let out = run_python(&py, TETGEN_RUN, &[plc.to_str().unwrap(), out_node.to_str().unwrap()]);
    // TetGen prints its progress on stdout: ours is the last line.
    let f: Vec<&str> = out.lines().last().unwrap_or_default().split_whitespace().collect();
    // The same domain, with our tag as the region attribute of every tetrahedron.
    assert_eq!(f[2], "[10]", "{out}");
    let back = read_path(&dir.path().join("out.ele"), None).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(back.points.len().to_string(), f[0]);
    assert_eq!(back.num_cells_of(CellKind::Tetra).to_string(), f[1]);
    assert_eq!(back.cells().map(|c| c.2).collect::<BTreeSet<_>>(), BTreeSet::from([10]));
    // TetGen filled the volume we gave it: the same as the input mesh's, whose boundary
    // the PLC is (the facets are kept, so the volume is exact to rounding).
    let (a, b) = (volume(&back), volume(&m));
    assert!((a - b).abs() < 1e-9 * b, "{a} vs {b}");
}

#[test]
fn damaged_tetgen_files_are_refused_or_read_never_panic() {
    smartmesh_test_support::require_public_fixtures!();
    let m = read_file("3d/box_cyl_input.mesh");
    let set = write_bytes(Format::TetGen, &m, &named("x.ele")).unwrap();
    let plc = write_bytes(Format::TetGen, &m, &named("x.poly")).unwrap();
    let sib = MemorySiblings::from_written(&set);
    let mut state = 0x0007_e79e_5eed_u64;
    let mut below = |n: usize| {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state % n.max(1) as u64) as usize
    };
    let mut refused = 0;
    let mut total = 0;
    for (bytes, ext) in [(&set.main, "ele"), (&plc.main, "poly")] {
        let n = bytes.len();
        for k in 0..48 {
            let mut d = bytes[..if k < 16 { k * n / 16 } else { n }].to_vec();
            if k >= 16 {
                for _ in 0..1 + below(4) {
                    let i = below(n);
                    d[i] = [b'9', b'-', 0xff, b'\n', b' ', b'#', 0][below(7)];
                }
            }
            let ctx = ReadContext { siblings: &sib, extension: ext.into() };
            let read = || read_bytes(Format::TetGen, &d, &ctx);
            let r = std::panic::catch_unwind(std::panic::AssertUnwindSafe(read));
            total += 1;
            match r {
                Ok(Ok(_)) => {}
                Ok(Err(_)) => refused += 1,
                Err(_) => panic!("the TetGen reader panicked on a damaged .{ext}"),
            }
        }
    }
    assert!(refused > total / 4, "{refused} of {total} refused");
}

/// Tetrahedralises a unit cube at second order with TetGen (`-pq1.2a0.01o2`) and writes
/// its arrays as the `.node` and `.ele` TetGen writes, numbered from 0 (`-z`): the rows
/// of the arrays are the records of the files.
const TETGEN_O2: &str = r#"
import sys, numpy as np, tetgen
pts = np.array([[0,0,0],[1,0,0],[1,1,0],[0,1,0],[0,0,1.],[1,0,1],[1,1,1],[0,1,1]])
q = [[0,3,2,1],[4,5,6,7],[0,1,5,4],[1,2,6,5],[2,3,7,6],[3,0,4,7]]
faces = np.array([t for f in q for t in ([f[0],f[1],f[2]],[f[0],f[2],f[3]])], dtype=np.int32)
node, elem, _, _ = tetgen.TetGen(pts, faces).tetrahedralize(switches="pq1.2a0.01o2Q")
with open(sys.argv[1] + ".node", "w") as f:
    f.write(f"{len(node)} 3 0 0\n")
    for i, p in enumerate(node):
        f.write(f"{i} {float(p[0])!r} {float(p[1])!r} {float(p[2])!r}\n")
with open(sys.argv[1] + ".ele", "w") as f:
    f.write(f"{len(elem)} 10 0\n")
    for i, e in enumerate(elem):
        f.write(f"{i} " + " ".join(str(int(v)) for v in e) + "\n")
print(len(node), len(elem))
"#;

#[test]
fn tetgen_second_order_tetrahedra_read_in_gmsh_order() {
    let Some(py) = python_with(&["tetgen"]) else { return };
    let dir = tempfile::tempdir().unwrap();
    let base = dir.path().join("cube");
    let out = run_python(&py, TETGEN_O2, &[base.to_str().unwrap()]);
    let counts: Vec<usize> =
        out.lines().last().unwrap().split_whitespace().map(|t| t.parse().unwrap()).collect();
    let m = read_path(&dir.path().join("cube.ele"), None).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!((m.points.len(), m.num_cells_of(CellKind::Tetra10)), (counts[0], counts[1]));
    // Gmsh's edge nodes: 0-1, 1-2, 2-0, 3-0, 3-2, 3-1, each the midpoint of its edge.
    const EDGES: [(usize, usize); 6] = [(0, 1), (1, 2), (2, 0), (3, 0), (3, 2), (3, 1)];
    let mut total = 0.0;
    for (_, c, _, _) in m.cells() {
        let p = |j: usize| m.points[c[j] as usize];
        for (j, &(a, b)) in EDGES.iter().enumerate() {
            for k in 0..3 {
                assert!((p(4 + j)[k] - 0.5 * (p(a)[k] + p(b)[k])).abs() < 1e-12, "edge node {j}");
            }
        }
        let lin = TaggedMesh {
            points: (0..4).map(p).collect(),
            blocks: vec![{
                let mut b = smartmesh_formats::CellBlock::new(CellKind::Tetra);
                b.push(&[0u32, 1, 2, 3], 0, 0);
                b
            }],
            ..Default::default()
        };
        let v = volume(&lin);
        total += v;
    }
    assert!((total - 1.0).abs() < 1e-12, "{total}");
    // Written back: TetGen's order again, read back the same.
    let (_, back) = roundtrip(&m, "o2.ele");
    same_cells(&m, &back);
}
