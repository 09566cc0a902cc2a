//! STL, ASCII and binary: exact merging of coincident vertices, solids as named tags,
//! round trips, a volume mesh written as its skin, malformed and extreme files, and
//! meshio and Gmsh reading what we write (skipped, saying so, without them, unless
//! `SMARTMESH_REQUIRE_INTEROP=1`).

use smartmesh_test_support::formats as common;

use std::collections::BTreeMap;
use std::panic::{catch_unwind, AssertUnwindSafe};

use smartmesh_formats::{
    read_bytes, read_bytes_reported, write_bytes, CellKind, ErrorKind, Format, Position,
    ReadContext, StlWrite, TaggedMesh, WriteOptions,
};

fn read(s: &[u8]) -> smartmesh_formats::Result<TaggedMesh> {
    read_bytes(Format::Stl, s, &ReadContext::alone("stl"))
}

fn opts(binary: bool) -> WriteOptions {
    WriteOptions { stl: StlWrite { binary }, ..Default::default() }
}

fn write(mesh: &TaggedMesh, binary: bool) -> smartmesh_formats::Written {
    write_bytes(Format::Stl, mesh, &opts(binary)).unwrap_or_else(|e| panic!("{e}"))
}

/// Two solids: a square of two triangles in z = 1 (`top`), a triangle below it
/// (`bottom`, upper-case keywords, a vertex with -0.0 that is the top's 0.0).
const TWO_SOLIDS: &str = "solid top
  facet normal 0 0 1
    outer loop
      vertex 0 0 1
      vertex 1 0 1
      vertex 1 1 1
    endloop
  endfacet
  facet normal 0 0 1
    outer loop
      vertex 0 0 1
      vertex 1 1 1
      vertex 0 1 1
    endloop
  endfacet
endsolid top
SOLID bottom part
FACET NORMAL 0 0 -1
OUTER LOOP
VERTEX -0.0 0 1
VERTEX 0.5 0.5 0.25
VERTEX 1 0 1
ENDLOOP
ENDFACET
ENDSOLID
";

/// The triangles of `m` by tag name (`tag<N>` unnamed, "" for tag 0), as coordinates.
fn triangles_by_name(m: &TaggedMesh) -> BTreeMap<String, Vec<[[f64; 3]; 3]>> {
    let mut out: BTreeMap<String, Vec<[[f64; 3]; 3]>> = BTreeMap::new();
    for (k, n, p, _) in m.cells() {
        assert_eq!(k, CellKind::Triangle);
        let name = match (p, m.tag_name(2, p)) {
            (0, _) => String::new(),
            (_, Some(s)) => s.to_string(),
            (_, None) => format!("tag{p}"),
        };
        out.entry(name).or_default().push([0, 1, 2].map(|i| m.points[n[i] as usize]));
    }
    out
}

#[test]
fn solids_are_named_tags_and_vertices_merge_exactly_in_first_seen_order() {
    let m = read(TWO_SOLIDS.as_bytes()).unwrap();
    assert_eq!(m.coordinate_dim, 3);
    assert_eq!(
        m.points,
        vec![[0., 0., 1.], [1., 0., 1.], [1., 1., 1.], [0., 1., 1.], [0.5, 0.5, 0.25]]
    );
    let cells: Vec<(Vec<u32>, i32)> = m.cells().map(|c| (c.1.to_vec(), c.2)).collect();
    assert_eq!(cells, vec![(vec![0, 1, 2], 1), (vec![0, 2, 3], 1), (vec![0, 4, 1], 2)]);
    assert_eq!(m.tag_name(2, 1), Some("top"));
    assert_eq!(m.tag_name(2, 2), Some("bottom part"));
}

/// Vertices a hair apart stay apart: no tolerance.
#[test]
fn vertices_one_ulp_apart_are_two_points() {
    let s = "solid\nfacet normal 0 0 0\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nfacet normal 0 0 0\nouter loop\nvertex 1.0000000000000002 0 0\nvertex 1 1 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid\n";
    let m = read(s.as_bytes()).unwrap();
    assert_eq!(m.points.len(), 5);
    assert_eq!(m.cells().next().unwrap().2, 0, "an unnamed solid is tag 0");
}

/// A mesh with tags 0, 3 (named) and 7 (unnamed), quads split: ASCII gives the same
/// coordinates bit for bit and the names; binary the tags in the attribute word.
#[test]
fn ascii_and_binary_round_trips() {
    let mut m = TaggedMesh::new();
    m.coordinate_dim = 3;
    m.points = vec![
        [0.1, 0.2, 0.3],
        [1.0 / 3.0, 0.0, -2.5],
        [1.0, 1.0, 1e-300],
        [0.0, 1.0, 7.0],
        [5.0, 5.0, 5.0],
    ];
    m.block_mut(CellKind::Triangle).push(&[0u32, 1, 2], 3, 3);
    m.block_mut(CellKind::Quad).push(&[0u32, 1, 2, 3], 7, 7);
    m.block_mut(CellKind::Triangle).push(&[1u32, 4, 2], 0, 0);
    m.tag_names.insert((2, 3), "wall".into());
    let w = write(&m, false);
    assert!(w.report.dropped.iter().any(|d| d.contains("1 quadrilaterals")), "{:?}", w.report);
    let back = read(&w.main).unwrap();
    let by = triangles_by_name(&back);
    let p = |i: usize| m.points[i];
    assert_eq!(by["wall"], vec![[p(0), p(1), p(2)]]);
    assert_eq!(by["tag7"], vec![[p(0), p(1), p(2)], [p(0), p(2), p(3)]]);
    assert_eq!(by[""], vec![[p(1), p(4), p(2)]]);
    assert!(back.cells().any(|c| c.2 == 7) && back.tag_name(2, 7).is_none());

    // Binary: coordinates exact in f32 read back exactly, tags in the attribute word.
    for q in &mut m.points {
        *q = q.map(|c| f64::from(c as f32));
    }
    let w = write(&m, true);
    assert_eq!(w.main.len(), 84 + 50 * 4);
    assert!(w.report.dropped.iter().any(|d| d.contains("`wall`")), "{:?}", w.report);
    let back = read(&w.main).unwrap();
    let tags: Vec<i32> = back.cells().map(|c| c.2).collect();
    assert_eq!(tags, vec![0, 3, 7, 7]);
    assert_eq!(back.points.len(), 5);
    // The same bytes again: deterministic.
    assert_eq!(write(&m, true).main, w.main);
}

/// A binary file whose header starts with `solid` is still binary (told by its size).
#[test]
fn a_binary_file_starting_with_solid_is_binary() {
    let mut b = vec![b' '; 80];
    b[..5].copy_from_slice(b"solid");
    b.extend_from_slice(&1u32.to_le_bytes());
    for v in [0f32, 0., 1., 0., 0., 0., 1., 0., 0., 0., 1., 0.] {
        b.extend_from_slice(&v.to_le_bytes());
    }
    b.extend_from_slice(&0u16.to_le_bytes());
    let m = read(&b).unwrap();
    assert_eq!(m.points.len(), 3);
    assert_eq!(m.points[2], [0.0, 1.0, 0.0]);
}

/// A volume mesh is written as its boundary, outward; the report says so.
#[test]
fn a_volume_mesh_is_written_as_its_boundary() {
    let mut m = TaggedMesh::new();
    m.coordinate_dim = 3;
    m.points = vec![[0., 0., 0.], [1., 0., 0.], [0., 1., 0.], [0., 0., 1.], [1., 1., 1.]];
    m.block_mut(CellKind::Tetra).push(&[0u32, 1, 2, 3], 4, 4);
    m.block_mut(CellKind::Tetra).push(&[1u32, 2, 3, 4], 4, 4);
    m.tag_names.insert((3, 4), "body".into());
    let w = write(&m, false);
    assert!(w.report.dropped.iter().any(|d| d.contains("6 faces")), "{:?}", w.report);
    let back = read(&w.main).unwrap();
    let tris = &triangles_by_name(&back)["body"];
    assert_eq!(tris.len(), 6);
    let det = |[a, b, c]: [[f64; 3]; 3]| {
        (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
            + a[2] * (b[0] * c[1] - b[1] * c[0]))
            / 6.0
    };
    let vol: f64 = tris.iter().map(|&t| det(t)).sum();
    assert!((vol - 0.5).abs() < 1e-15, "{vol}");
}

fn error(s: &[u8]) -> (Option<Position>, String) {
    let e = read(s).expect_err("a malformed file must be refused");
    (e.at, e.to_string())
}

#[test]
fn malformed_files_are_refused_at_their_position() {
    let facet = "facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\n";
    let cases: Vec<(String, u64, &str)> = vec![
        (format!("solid a\n{facet}"), 9, "`facet` or `endsolid`"),
        (
            format!("solid a\n{}", facet.replace("vertex 1 0 0", "vertex 1 nan 0")),
            5,
            "not a finite",
        ),
        (format!("solid a\n{}", facet.replace("vertex 1 0 0", "vertex 1 0")), 6, "vertex's z"),
        (
            format!("solid a\n{}", facet.replace("endloop", "vertex 1 1 1\nendloop")),
            7,
            "more than 3 vertices",
        ),
        (format!("solid a\n{}", facet.replace("outer loop", "outer")), 4, "`loop`"),
        (format!("solid a\n{}", facet.replace("normal 0 0 1", "normal 0 x 1")), 2, "normal's y"),
        (format!("solid a\n{facet}endsolid a\nfacet"), 10, "`solid`"),
    ];
    for (text, line, what) in cases {
        let (at, msg) = error(text.as_bytes());
        assert_eq!(at, Some(Position::Line(line)), "{msg}\n{text}");
        assert!(msg.contains(what), "{msg} lacks {what}");
    }
    let (at, msg) = error(b"\x00\x01garbage");
    assert_eq!(at, Some(Position::Line(1)), "{msg}");
}

/// A binary header announcing 4 294 967 295 triangles (214 GB) in a 100-byte file is
/// refused at byte 80, before anything is allocated.
#[test]
fn a_huge_triangle_count_allocates_nothing() {
    let mut b = vec![0u8; 80];
    b.extend_from_slice(&u32::MAX.to_le_bytes());
    b.extend_from_slice(&[0u8; 16]);
    let e = read(&b).unwrap_err();
    assert_eq!(e.at, Some(Position::Byte(80)));
    assert!(matches!(e.kind, ErrorKind::Inconsistent(_)));
    assert!(e.to_string().contains("4294967295 triangles"), "{e}");
}

#[test]
fn damaged_copies_never_panic() {
    let mut m = read(TWO_SOLIDS.as_bytes()).unwrap();
    m.points[4][2] = 0.3;
    let bin = write(&m, true).main;
    for good in [TWO_SOLIDS.as_bytes().to_vec(), bin] {
        for cut in 0..good.len() {
            let r = catch_unwind(AssertUnwindSafe(|| read(&good[..cut]).map(|_| ())));
            assert!(r.is_ok(), "panic on a copy cut at {cut}");
        }
        for i in (0..good.len()).step_by(3) {
            let mut bad = good.clone();
            bad[i] = bad[i].wrapping_add(0x41);
            let r = catch_unwind(AssertUnwindSafe(|| {
                if let Err(e) = read(&bad) {
                    assert!(e.at.is_some(), "error without a position: {e}");
                }
            }));
            assert!(r.is_ok(), "panic on a copy damaged at {i}");
        }
    }
    let (_, report) =
        read_bytes_reported(Format::Stl, TWO_SOLIDS.as_bytes(), &ReadContext::alone("stl"))
            .unwrap();
    assert!(report.notes.is_empty(), "{report:?}");
}

// ---------------------------------------------------------------------------------
// The owners' tools

/// box_cyl's boundary (1012 triangles, 4 named groups); the caller required the
/// public fixtures.
fn box_cyl_surface() -> TaggedMesh {
    let mut m = common::read_file("3d/box_cyl.v41_ascii.msh");
    m.blocks.retain(|b| b.kind == CellKind::Triangle);
    m.entities.clear();
    m
}

/// meshio reads what we write, ASCII and binary: the same points in the same order
/// (it merges exactly, first seen first, as we do) and the same triangles.
#[test]
fn meshio_reads_what_we_write() {
    let Some(py) = common::python_with(&["meshio"]) else { return };
    smartmesh_test_support::require_public_fixtures!();
    let m = box_cyl_surface();
    let dir = tempfile::tempdir().unwrap();
    for binary in [false, true] {
        let out = dir.path().join(format!("box_cyl_{binary}.stl"));
        smartmesh_formats::write_path(&out, &m, None, &opts(binary)).unwrap();
        let ours = smartmesh_formats::read_path(&out, None).unwrap();
        let script = r#"
import sys, json, warnings
warnings.simplefilter("ignore")
import meshio
m = meshio.read(sys.argv[1])
# The coordinates' bits, which JSON carries exactly.
bits = m.points.astype("<f8").view("<u8").tolist()
print(json.dumps({"points": bits, "triangles": m.cells_dict["triangle"].tolist()}))
"#;
        let got: serde_json::Value =
            serde_json::from_str(&common::run_python(&py, script, &[out.to_str().unwrap()]))
                .unwrap();
        let bits: Vec<[u64; 3]> = serde_json::from_value(got["points"].clone()).unwrap();
        let points: Vec<[f64; 3]> = bits.iter().map(|b| b.map(f64::from_bits)).collect();
        let tris: Vec<[u32; 3]> = serde_json::from_value(got["triangles"].clone()).unwrap();
        assert_eq!(points.len(), ours.points.len());
        assert_eq!(tris.len(), 1012);
        let our_tris: Vec<[u32; 3]> = ours.cells().map(|c| [c.1[0], c.1[1], c.1[2]]).collect();
        assert_eq!(tris, our_tris, "binary {binary}");
        for (p, q) in points.iter().zip(&ours.points) {
            for k in 0..3 {
                // meshio parses ASCII with Python's float (correctly rounded): equal.
                assert_eq!(p[k].to_bits(), q[k].to_bits(), "binary {binary}: {p:?} {q:?}");
            }
        }
    }
}

/// Gmsh merges our ASCII STL into one discrete surface per solid, named by nothing but
/// holding each group's triangles.
#[test]
fn gmsh_reads_what_we_write() {
    let Some(py) = common::python_with(&["gmsh"]) else { return };
    smartmesh_test_support::require_public_fixtures!();
    let m = box_cyl_surface();
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("box_cyl.stl");
    smartmesh_formats::write_path(&out, &m, None, &opts(false)).unwrap();
    let script = r#"
import sys, json, gmsh
gmsh.initialize(); gmsh.option.setNumber("General.Terminal", 0)
gmsh.merge(sys.argv[1])
counts = []
for dim, tag in gmsh.model.getEntities(2):
    types, tags, nodes = gmsh.model.mesh.getElements(dim, tag)
    counts.append(sum(len(t) for t in tags))
print(json.dumps(counts))
"#;
    let got: Vec<usize> =
        serde_json::from_str(&common::run_python(&py, script, &[out.to_str().unwrap()])).unwrap();
    // Solids in tag order: Inlet 90, Outlet 90, Walls 714, Cylinder 118.
    assert_eq!(got, vec![90, 90, 714, 118]);
}

// ---------------------------------------------------------------------------------
// Property tests

use proptest::prelude::*;
use smartmesh_formats::arbitrary::{arb_tagged_mesh, MeshFeatures};

const STL_FEATURES: MeshFeatures = MeshFeatures {
    quads: false,
    lines: false,
    vertices: false,
    geometrical: false,
    names: true,
    point_scalar: false,
    point_tensor: false,
    negative_tags: false,
};

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    /// ASCII keeps every triangle's coordinates bit for bit under its tag's name (when
    /// the report says no name was changed or shared); binary keeps each triangle's tag
    /// and its coordinates rounded to f32.
    #[test]
    fn prop_round_trips_keep_triangles_by_tag(mesh in arb_tagged_mesh(STL_FEATURES)) {
        let mut mesh = mesh;
        mesh.coordinate_dim = 3;
        let w = write(&mesh, false);
        let back = read(&w.main).unwrap();
        let changed = w.report.dropped.iter().any(|d| d.contains("written as") || d.contains("share"));
        if !changed {
            prop_assert_eq!(triangles_by_name(&back), triangles_by_name(&mesh));
        }
        let w = write(&mesh, true);
        let back = read(&w.main).unwrap();
        let tags = |m: &TaggedMesh| -> Vec<(i32, Vec<[f32; 3]>)> {
            let mut v: Vec<_> = m
                .cells()
                .map(|(_, n, p, _)| (p, n.iter().map(|&i| m.points[i as usize].map(|c| c as f32)).collect()))
                .collect();
            v.sort_by(|a, b| a.partial_cmp(b).unwrap());
            v
        };
        prop_assert_eq!(tags(&back), tags(&mesh));
    }

    #[test]
    fn prop_arbitrary_bytes_never_panic(bytes in prop::collection::vec(any::<u8>(), 0..400)) {
        let _ = read(&bytes);
        let mut with_header = b"solid x\n".to_vec();
        with_header.extend_from_slice(&bytes);
        let _ = read(&with_header);
    }
}
