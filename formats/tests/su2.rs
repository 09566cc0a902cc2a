//! SU2 (`.su2`): a mesh written by hand after the SU2 documentation's *Mesh File* page,
//! round trips with every marker name, the errors of malformed files, and meshio's SU2
//! reader and writer on both sides (skipped, saying so, without Python's meshio, unless
//! `SMARTMESH_REQUIRE_INTEROP=1`).

use smartmesh_test_support::formats as common;

use std::collections::BTreeMap;
use std::panic::{catch_unwind, AssertUnwindSafe};

use proptest::prelude::*;
use smartmesh_formats::arbitrary::{arb_tagged_mesh, MeshFeatures};
use smartmesh_formats::{
    read_bytes, read_bytes_reported, write_bytes, CellBlock, CellKind, ErrorKind, Format, Position,
    ReadContext, TaggedMesh, WriteOptions,
};

/// A unit square of 2 quads and 4 triangles with 4 named markers, in the layout of the
/// documentation's example: comment headers, element and point indices at line ends.
const SQUARE: &str = "\
%
% Problem dimension
%
NDIME= 2
%
% Inner element connectivity
%
NELEM= 6
9 0 1 4 3 0
9 1 2 5 4 1
5 3 4 7 2
5 3 7 6 3
5 4 5 8 4
5 4 8 7 5
%
% Node coordinates
%
NPOIN= 9
0.0 0.0 0
0.5 0.0 1
1.0 0.0 2
0.0 0.5 3
0.5 0.5 4
1.0 0.5 5
0.0 1.0 6
0.5 1.0 7
1.0 1.0 8
%
% Boundary elements
%
NMARK= 4
MARKER_TAG= lower
MARKER_ELEMS= 2
3 0 1
3 1 2
MARKER_TAG= right
MARKER_ELEMS= 2
3 2 5
3 5 8
MARKER_TAG= upper
MARKER_ELEMS= 2
3 8 7
3 7 6
MARKER_TAG= left
MARKER_ELEMS= 2
3 6 3
3 3 0
";

fn read(s: &[u8]) -> smartmesh_formats::Result<TaggedMesh> {
    read_bytes(Format::Su2, s, &ReadContext::alone("su2"))
}

fn write(mesh: &TaggedMesh) -> smartmesh_formats::Written {
    write_bytes(Format::Su2, mesh, &WriteOptions::default()).unwrap_or_else(|e| panic!("{e}"))
}

/// Line cells per marker name (`tag<N>` for an unnamed tag N), each as its node pairs.
fn lines_by_name(m: &TaggedMesh) -> BTreeMap<String, Vec<[u32; 2]>> {
    let mut out: BTreeMap<String, Vec<[u32; 2]>> = BTreeMap::new();
    for (kind, nodes, p, _) in m.cells() {
        if kind == CellKind::Line {
            let name = m.tag_name(1, p).map_or_else(|| format!("tag{p}"), str::to_owned);
            out.entry(name).or_default().push([nodes[0], nodes[1]]);
        }
    }
    out
}

/// The interior cells, as (kind, nodes), in mesh order.
fn interior(m: &TaggedMesh) -> Vec<(CellKind, Vec<u32>)> {
    m.cells().filter(|c| c.0.dim() == 2).map(|(k, n, _, _)| (k, n.to_vec())).collect()
}

/// The error of reading `s`: its line and message.
fn error(s: &str) -> (Option<Position>, String) {
    let e = read(s.as_bytes()).expect_err("a malformed file must be refused");
    (e.at, e.to_string())
}

#[test]
fn the_documented_layout_reads_with_its_markers() {
    let m = read(SQUARE.as_bytes()).unwrap();
    assert_eq!(m.points.len(), 9);
    assert_eq!(m.points[4], [0.5, 0.5, 0.0]);
    assert_eq!(m.num_cells_of(CellKind::Quad), 2);
    assert_eq!(m.num_cells_of(CellKind::Triangle), 4);
    assert_eq!(m.num_cells_of(CellKind::Line), 8);
    // Markers numbered 1.. in file order, named; interior cells in zone 1.
    let names: Vec<_> = m.tag_names.iter().map(|(&(d, t), n)| (d, t, n.as_str())).collect();
    assert_eq!(names, [(1, 1, "lower"), (1, 2, "right"), (1, 3, "upper"), (1, 4, "left")]);
    assert!(m.cells().filter(|c| c.0.dim() == 2).all(|c| c.2 == 1 && c.3 == 1));
    assert_eq!(lines_by_name(&m)["upper"], [[8, 7], [7, 6]]);
    assert_eq!(interior(&m)[1], (CellKind::Quad, vec![1, 2, 5, 4]));
}

#[test]
fn keywords_without_spaces_sections_in_another_order_and_extra_columns_read() {
    let s = "NDIME=2\nNPOIN = 3 3\n0 0 0 0\n1 0\n0 1 2\nNELEM=1\n5 0 1 2\nNMARK=1\nMARKER_TAG=wall\nMARKER_ELEMS=1\n3 0 1 0\n";
    let m = read(s.as_bytes()).unwrap();
    assert_eq!(m.points.len(), 3);
    assert_eq!(m.num_cells_of(CellKind::Triangle), 1);
    assert_eq!(m.tag_name(1, 1), Some("wall"));
}

#[test]
fn the_cylinder_round_trips_with_every_name() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../fixtures/cylinder.msh");
    let mesh = smartmesh_formats::read_path(&path, None).unwrap();
    let written = write(&mesh);
    let back = read(&written.main).unwrap();
    assert_eq!(back.points.len(), mesh.points.len());
    for (a, b) in mesh.points.iter().zip(&back.points) {
        assert_eq!([a[0].to_bits(), a[1].to_bits()], [b[0].to_bits(), b[1].to_bits()]);
    }
    assert_eq!(interior(&back), interior(&mesh));
    assert_eq!(lines_by_name(&back), lines_by_name(&mesh));
    assert!(lines_by_name(&back).contains_key("Cylinder"), "{:?}", back.tag_names);
    // The face tag (10, Fluid) is said to be lost.
    assert!(written.report.dropped.iter().any(|d| d.contains("Fluid")), "{:?}", written.report);
    // Writing what was read gives the same bytes.
    assert_eq!(write(&back).main, written.main);
}

#[test]
fn an_unnamed_tag_gets_a_stable_name_that_reads_back_as_its_number() {
    let mut m = read(SQUARE.as_bytes()).unwrap();
    m.tag_names.remove(&(1, 3));
    let written = write(&m);
    let text = String::from_utf8(written.main.clone()).unwrap();
    assert!(text.contains("MARKER_TAG= tag3\n"), "{text}");
    assert!(
        written
            .report
            .dropped
            .iter()
            .any(|d| d.contains("tag 3 has no name") && d.contains("`tag3`")),
        "{:?}",
        written.report
    );
    let back = read(&written.main).unwrap();
    assert_eq!(back.tag_name(1, 3), None);
    assert_eq!(lines_by_name(&back), lines_by_name(&m));
    // The named ones are numbered around it.
    assert_eq!(back.tag_name(1, 4), Some("left"));
}

#[test]
fn names_with_blanks_become_one_word_and_the_report_says_so() {
    let mut m = read(SQUARE.as_bytes()).unwrap();
    m.tag_names.insert((1, 1), "far field (x=0)".into());
    let written = write(&m);
    let back = read(&written.main).unwrap();
    assert_eq!(back.tag_name(1, 1), Some("far_field__x_0_"));
    assert!(written.report.dropped.iter().any(|d| d.contains("far_field__x_0_")));
}

#[test]
fn two_tags_of_one_name_stay_apart() {
    let mut m = read(SQUARE.as_bytes()).unwrap();
    m.tag_names.insert((1, 2), "lower".into());
    let written = write(&m);
    let back = read(&written.main).unwrap();
    assert_eq!(back.num_cells_of(CellKind::Line), 8);
    assert_eq!(lines_by_name(&back)["lower"].len(), 2);
    assert_eq!(lines_by_name(&back)["lower_tag2"].len(), 2);
}

#[test]
fn what_su2_cannot_hold_is_reported() {
    let mut m = read(SQUARE.as_bytes()).unwrap();
    m.points[0][2] = 1.0;
    let mut v = CellBlock::new(CellKind::Vertex);
    v.push(&[0u32], 5, 5);
    m.blocks.push(v);
    m.point_data.insert("h".into(), smartmesh_formats::DataArray::new(1, vec![1.0; 9]));
    let written = write(&m);
    let dropped = written.report.dropped.join("\n");
    for what in ["z coordinates of 1 points", "1 vertex cells", "point data `h`"] {
        assert!(dropped.contains(what), "{what}: {dropped}");
    }
    // A mesh SU2 holds entirely is written without a word.
    assert_eq!(write(&read(SQUARE.as_bytes()).unwrap()).report.dropped, Vec::<String>::new());
}

#[test]
fn several_zones_are_read_each_with_its_points_and_tag() {
    let zone = SQUARE.replace("MARKER_TAG= right", "MARKER_TAG= interface");
    let s = format!("NZONE= 2\nIZONE= 1\n{SQUARE}IZONE= 2\n{zone}");
    let (m, report) =
        read_bytes_reported(Format::Su2, s.as_bytes(), &ReadContext::alone("su2")).unwrap();
    assert_eq!(m.points.len(), 18);
    assert_eq!(m.num_cells_of(CellKind::Triangle), 8);
    let zone2: Vec<_> = m.cells().filter(|c| c.0.dim() == 2 && c.2 == 2).collect();
    assert_eq!(zone2.len(), 6);
    assert_eq!(zone2[0].1, [9, 10, 13, 12]);
    // A name used in both zones is one tag; the new one is numbered after.
    assert_eq!(lines_by_name(&m)["lower"].len(), 4);
    assert_eq!(m.tag_name(1, 5), Some("interface"));
    assert!(report.notes.iter().any(|n| n.contains("2 zones")), "{report:?}");
}

#[test]
fn zone_counts_that_disagree_are_refused() {
    let s = format!("NZONE= 3\nIZONE= 1\n{SQUARE}IZONE= 2\n{SQUARE}");
    let (at, msg) = error(&s);
    assert_eq!(at, Some(Position::Line(1)), "{msg}");
    assert!(msg.contains("NZONE= 3 but the file has 2 zones"), "{msg}");
    let s = format!("NZONE= 2\nIZONE= 1\n{SQUARE}IZONE= 3\n{SQUARE}");
    assert!(error(&s).1.contains("expected `IZONE= 2`"));
}

#[test]
fn free_form_deformation_boxes_end_the_mesh_with_a_note() {
    let s = format!("{SQUARE}FFD_NBOX= 1\nFFD_NLEVEL= 1\nFFD_TAG= 0\n");
    let (m, report) =
        read_bytes_reported(Format::Su2, s.as_bytes(), &ReadContext::alone("su2")).unwrap();
    assert_eq!(m.points.len(), 9);
    assert!(report.notes[0].contains("free-form deformation"), "{report:?}");
}

#[test]
fn malformed_files_are_refused_at_their_line() {
    let line_of = |needle: &str| SQUARE.lines().position(|l| l == needle).unwrap() as u64 + 1;
    let cases: Vec<(String, u64, &str)> = vec![
        (
            SQUARE.replace("NDIME= 2", "NDIME= 3"),
            line_of("9 0 1 4 3 0"),
            "an interior element of a 3D mesh",
        ),
        (SQUARE.replace("NDIME= 2", "NDIME= 4"), line_of("NDIME= 2"), "`NDIME= 4`"),
        (SQUARE.replace("5 3 4 7 2", "10 3 4 7 2"), line_of("5 3 4 7 2"), "tetrahedron"),
        (SQUARE.replace("5 3 4 7 2", "12 3 4 7 2 1 1 1 1"), line_of("5 3 4 7 2"), "hexahedron"),
        (SQUARE.replace("5 3 4 7 2", "7 3 4 7 2"), line_of("5 3 4 7 2"), "does not define"),
        (SQUARE.replace("5 3 4 7 2", "3 3 4 2"), line_of("5 3 4 7 2"), "interior element"),
        (SQUARE.replace("3 5 8", "5 5 8 2"), line_of("3 5 8"), "marker element"),
        (SQUARE.replace("5 3 4 7 2", "5 3 4"), line_of("5 3 4 7 2"), "3 point indices"),
        (SQUARE.replace("5 3 4 7 2", "5 3 4 x"), line_of("5 3 4 7 2"), "point index"),
        (SQUARE.replace("5 4 8 7 5", "5 4 9 7 5"), line_of("5 4 8 7 5"), "refers to 9"),
        (SQUARE.replace("\n3 7 6\n", "\n3 7 60\n"), line_of("3 7 6"), "refers to 60"),
        (SQUARE.replace("0.5 0.5 4", "0.5 nan 4"), line_of("0.5 0.5 4"), "not a finite"),
        (SQUARE.replace("0.5 0.5 4", "0.5 0.5 0.25"), line_of("0.5 0.5 4"), "optional point index"),
        (SQUARE.replace("0.5 0.5 4", "0.5"), line_of("0.5 0.5 4"), "y coordinate"),
        (SQUARE.replace("NMARK= 4", "NMARK= 3"), line_of("NMARK= 4"), "NMARK= 3 but"),
        (SQUARE.replace("NELEM= 6", "NELEM= 99999999999"), line_of("NELEM= 6"), "cannot hold"),
        (
            SQUARE.replace("NPOIN= 9", "NPOIN= 12"),
            line_of("NMARK= 4"),
            "expected an x coordinate, found `NMARK=`",
        ),
        (SQUARE.replace("NPOIN= 9", "NPOIN= -9"), line_of("NPOIN= 9"), "non-negative"),
        (
            SQUARE.replace("MARKER_TAG= upper", "MARKER_ELEMS= 1"),
            line_of("MARKER_TAG= upper"),
            "`MARKER_TAG=` before",
        ),
        (SQUARE.replace("NMARK= 4", "NSTUFF= 4"), line_of("NMARK= 4"), "`NSTUFF=`"),
        (SQUARE.replace("NMARK= 4", "garbage"), line_of("NMARK= 4"), "SU2 keyword"),
    ];
    for (text, line, what) in cases {
        let (at, msg) = error(&text);
        assert!(msg.contains(what), "expected `{what}` in: {msg}");
        assert_eq!(at, Some(Position::Line(line)), "{msg}");
    }
    assert!(read(b"").is_err());
    assert!(read(b"% only a comment\n").is_err());
}

#[test]
fn a_huge_count_allocates_nothing() {
    let e = read(b"NDIME= 2\nNPOIN= 18446744073709551\n0 0\n").unwrap_err();
    assert!(
        matches!(e.kind, ErrorKind::ImplausibleCount { .. } | ErrorKind::Expected { .. }),
        "{e}"
    );
    let e = read(b"NDIME= 2\nNPOIN= 100000000000\n0 0\n").unwrap_err();
    assert!(matches!(e.kind, ErrorKind::ImplausibleCount { .. }), "{e}");
}

#[test]
fn damaged_copies_never_panic_and_errors_have_a_line() {
    let bytes = SQUARE.as_bytes();
    let mut copies: Vec<Vec<u8>> = (0..bytes.len()).map(|n| bytes[..n].to_vec()).collect();
    let mut seed = 0x9e37_79b9_7f4a_7c15u64;
    for _ in 0..2000 {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        let mut b = bytes.to_vec();
        let i = (seed % b.len() as u64) as usize;
        b[i] = [b'9', b'-', b'\n', b' ', b'=', b'%', 0xff, b'x'][(seed >> 40) as usize % 8];
        copies.push(b);
    }
    for b in copies {
        match catch_unwind(AssertUnwindSafe(|| read(&b))) {
            Ok(Ok(m)) => assert_eq!(m.validate(), Vec::new()),
            Ok(Err(e)) => assert!(e.at.is_some(), "no position: {e}"),
            Err(_) => panic!("the reader panicked on {:?}", String::from_utf8_lossy(&b)),
        }
    }
}

const SU2_FEATURES: MeshFeatures = MeshFeatures {
    quads: true,
    lines: true,
    vertices: false,
    geometrical: false,
    names: true,
    point_scalar: false,
    point_tensor: false,
    negative_tags: false,
};

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    #[test]
    fn prop_round_trip_keeps_points_cells_and_marker_names(mesh in arb_tagged_mesh(SU2_FEATURES)) {
        let (written, back) = common::roundtrip(Format::Su2, "su2", &mesh, &WriteOptions::default());
        prop_assert_eq!(back.points.len(), mesh.points.len());
        for (a, b) in mesh.points.iter().zip(&back.points) {
            prop_assert_eq!([a[0].to_bits(), a[1].to_bits()], [b[0].to_bits(), b[1].to_bits()]);
        }
        let mut a = interior(&mesh);
        let mut b = interior(&back);
        a.sort();
        b.sort();
        prop_assert_eq!(a, b);
        // Names as written (the report says which ones changed), each with its cells.
        let renamed = written.report.dropped.iter().any(|d| d.contains("written as"));
        if !renamed {
            let count = |m: &TaggedMesh| lines_by_name(m).into_iter().map(|(k, v)| (k, v.len())).collect::<Vec<_>>();
            prop_assert_eq!(count(&mesh), count(&back));
        }
        prop_assert_eq!(back.num_cells_of(CellKind::Line), mesh.num_cells_of(CellKind::Line));
        prop_assert_eq!(write(&back).main, written.main);
    }

    #[test]
    fn prop_arbitrary_bytes_never_panic(bytes in prop::collection::vec(any::<u8>(), 0..400)) {
        let _ = read(&bytes);
    }
}

// ---------------------------------------------------------------------------------
// meshio's SU2 reader and writer

/// meshio reads what we write: counts, cell kinds, points and the markers' cells.
#[test]
fn meshio_reads_what_we_write() {
    let Some(py) = common::python_with(&["meshio"]) else { return };
    let dir = tempfile::tempdir().unwrap();
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../fixtures/cylinder.msh");
    let cylinder = smartmesh_formats::read_path(&path, None).unwrap();
    for (name, mesh) in [("cylinder", cylinder), ("square", read(SQUARE.as_bytes()).unwrap())] {
        meshio_reads(&py, &dir.path().join(format!("{name}.su2")), &mesh);
    }
}

fn meshio_reads(py: &str, out: &std::path::Path, mesh: &TaggedMesh) {
    smartmesh_formats::write_path(out, mesh, None, &WriteOptions::default()).unwrap();
    let script = r#"
import sys, json, warnings
warnings.simplefilter("ignore")
import meshio
m = meshio.read(sys.argv[1])
cells = {}
for b, t in zip(m.cells, m.cell_data["su2:tag"]):
    cells.setdefault(b.type, []).extend(b.data.tolist())
print(json.dumps({"points": m.points.tolist(), "cells": cells}))
"#;
    let got: serde_json::Value =
        serde_json::from_str(&common::run_python(py, script, &[out.to_str().unwrap()])).unwrap();
    let points = got["points"].as_array().unwrap();
    assert_eq!(points.len(), mesh.points.len());
    // numpy's `fromfile(sep=" ")`, which meshio reads points with, is not correctly
    // rounded: a last bit may differ.
    for (p, q) in mesh.points.iter().zip(points) {
        for k in 0..2 {
            let v = q[k].as_f64().unwrap();
            assert!((p[k] - v).abs() <= 4.0 * f64::EPSILON * p[k].abs().max(1.0), "{p:?} {q:?}");
        }
    }
    let cells = |kind: &str| -> Vec<Vec<u64>> {
        got["cells"][kind]
            .as_array()
            .map(|a| a.iter().map(|c| serde_json::from_value(c.clone()).unwrap()).collect())
            .unwrap_or_default()
    };
    let ours = |kind: CellKind| -> Vec<Vec<u64>> {
        let mut v: Vec<Vec<u64>> = mesh
            .cells()
            .filter(|c| c.0 == kind)
            .map(|c| c.1.iter().map(|&n| n as u64).collect())
            .collect();
        v.sort();
        v
    };
    let mut tri = cells("triangle");
    tri.sort();
    assert_eq!(tri, ours(CellKind::Triangle));
    let mut quads = cells("quad");
    quads.sort();
    assert_eq!(quads, ours(CellKind::Quad));
    let mut lines = cells("line");
    lines.sort();
    assert_eq!(lines, ours(CellKind::Line));
}

/// We read what meshio writes (without markers: meshio's marker writing fails on
/// names), a mixed mesh of triangles and quads.
#[test]
fn we_read_what_meshio_writes() {
    let Some(py) = common::python_with(&["meshio", "numpy"]) else { return };
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("meshio.su2");
    let script = r#"
import sys, warnings
warnings.simplefilter("ignore")
import meshio, numpy as np
pts = np.array([[0, 0], [0.5, 0], [1, 0], [0, 1], [0.5, 1], [1, 1], [0.25, 0.5]], dtype=float)
cells = [("quad", np.array([[1, 2, 5, 4]])), ("triangle", np.array([[0, 1, 6], [1, 4, 6], [4, 3, 6], [3, 0, 6]]))]
meshio.write(sys.argv[1], meshio.Mesh(pts, cells), file_format="su2")
"#;
    common::run_python(&py, script, &[out.to_str().unwrap()]);
    let m = smartmesh_formats::read_path(&out, None).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(m.points.len(), 7);
    assert_eq!(m.points[6], [0.25, 0.5, 0.0]);
    assert_eq!(m.num_cells_of(CellKind::Quad), 1);
    assert_eq!(m.num_cells_of(CellKind::Triangle), 4);
    assert_eq!(interior(&m)[0], (CellKind::Quad, vec![1, 2, 5, 4]));
}

/// The layout of SU2's own QuickStart mesh (`mesh_NACA0012_inv.su2`: 5233 points,
/// 10216 triangles, markers `airfoil` and `farfield`): tab-separated columns, points
/// indented by a tab with their index last, no comments, markers without indices.
#[test]
fn the_layout_of_su2s_quickstart_mesh_reads() {
    let s = "NDIME= 2\nNELEM= 2\n5\t0\t1\t2\t0\n5\t0\t2\t3\t1\nNPOIN= 4\n\t0.000000000000000e+00\t0.000000000000000e+00\t0\n\t1.000000000000000e+00\t-7.189878803616799e-01\t1\n\t1.0e+00\t1.0e+00\t2\n\t0.0e+00\t1.0e+00\t3\nNMARK= 2\nMARKER_TAG= airfoil\nMARKER_ELEMS= 2\n3\t0\t1\n3\t1\t2\nMARKER_TAG= farfield\nMARKER_ELEMS= 2\n3\t2\t3\n3\t3\t0\n";
    let m = read(s.as_bytes()).unwrap();
    assert_eq!(m.points[1], [1.0, -7.189878803616799e-01, 0.0]);
    assert_eq!(m.num_cells_of(CellKind::Triangle), 2);
    assert_eq!(lines_by_name(&m)["farfield"], [[2, 3], [3, 0]]);
    assert_eq!(m.tag_name(1, 1), Some("airfoil"));
}

// ---------------------------------------------------------------------------------
// 3D meshes

/// Cells as their corners' coordinates, with their kind and the name of their tag
/// (`None` for the interior cells, whose tags SU2 does not name), sorted: what must
/// agree whatever the point numbering.
fn cells_by_coordinates(
    m: &TaggedMesh,
    named: bool,
) -> Vec<(CellKind, Option<String>, Vec<[u64; 3]>)> {
    let mut v: Vec<_> = m
        .cells()
        .filter(|c| c.0.dim() >= 2)
        .map(|(k, n, p, _)| {
            let name = (named && k.dim() == 2).then(|| m.tag_name(2, p).unwrap_or("?").to_string());
            (k, name, n.iter().map(|&i| m.points[i as usize].map(f64::to_bits)).collect())
        })
        .collect();
    v.sort();
    v
}

/// The volume of each cell of a kind of Gmsh order, by its outward faces (a pyramid
/// or prism with an inverted node order would come out negative).
fn volumes(m: &TaggedMesh) -> Vec<f64> {
    m.cells()
        .filter(|c| c.0.dim() == 3)
        .map(|(k, n, _, _)| {
            let p = |i: usize| m.points[n[i] as usize];
            let tet = |a: [f64; 3], b: [f64; 3], c: [f64; 3], d: [f64; 3]| {
                let u = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
                let v = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
                let w = [d[0] - a[0], d[1] - a[1], d[2] - a[2]];
                (u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0])
                    + u[2] * (v[0] * w[1] - v[1] * w[0]))
                    / 6.0
            };
            // Each kind cut into tetrahedra of Gmsh's orientation.
            let cut: &[[usize; 4]] = match k {
                CellKind::Tetra => &[[0, 1, 2, 3]],
                CellKind::Pyramid => &[[0, 1, 2, 4], [0, 2, 3, 4]],
                CellKind::Wedge => &[[0, 1, 2, 3], [1, 2, 3, 4], [2, 3, 4, 5]],
                CellKind::Hexa => {
                    &[[0, 1, 3, 4], [1, 2, 3, 6], [1, 3, 4, 6], [1, 4, 5, 6], [3, 4, 6, 7]]
                }
                _ => &[],
            };
            cut.iter().map(|t| tet(p(t[0]), p(t[1]), p(t[2]), p(t[3]))).sum()
        })
        .collect()
}

/// Gmsh's three boxes of hexahedra, prisms, tetrahedra and pyramids with four named
/// surface groups: written as SU2 and read back, the same points bit for bit, the same
/// cells in the same order (the prisms' nodes turned to VTK's order and back), a marker
/// per surface group with its name.
#[test]
fn a_mixed_3d_mesh_round_trips_with_its_markers() {
    smartmesh_test_support::require_public_fixtures!();
    let m = common::read_file("3d/hex_prism_pyr.v41_ascii.msh");
    let w = write(&m);
    let text = String::from_utf8(w.main.clone()).unwrap();
    assert!(text.contains("NDIME= 3\n") && text.contains("NELEM= 242\n"), "{}", &text[..200]);
    assert!(text.contains("MARKER_TAG= Interface\nMARKER_ELEMS= 18\n"));
    let back = read(&w.main).unwrap();
    assert_eq!(back.coordinate_dim, 3);
    assert_eq!(back.points.len(), m.points.len());
    for (a, b) in m.points.iter().zip(&back.points) {
        assert_eq!(a.map(f64::to_bits), b.map(f64::to_bits));
    }
    let vol = |m: &TaggedMesh| -> Vec<(CellKind, Vec<u32>)> {
        m.cells().filter(|c| c.0.dim() == 3).map(|(k, n, _, _)| (k, n.to_vec())).collect()
    };
    assert_eq!(vol(&back), vol(&m));
    assert_eq!(cells_by_coordinates(&back, true), cells_by_coordinates(&m, true));
    let total: f64 = volumes(&back).iter().sum();
    assert!(volumes(&back).iter().all(|&v| v > 0.0));
    assert!((total - 2.6).abs() < 1e-12, "{total}");
    // The volume tags 1-3 are not SU2's to hold; the report says so.
    assert!(w.report.dropped.iter().any(|d| d.contains("volume tags")), "{:?}", w.report);
    // Writing what was read gives the same bytes.
    assert_eq!(write(&back).main, w.main);
}

/// A 3D SU2 file made by Gmsh's own SU2 export reads with the counts it declares and
/// the cells Gmsh's `.msh` of the same mesh has, prisms included (Gmsh writes them in
/// VTK's order).
#[test]
fn gmsh_s_own_3d_su2_export_reads_as_its_msh() {
    smartmesh_test_support::require_public_fixtures!();
    let Some(py) = common::python_with(&["gmsh"]) else { return };
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("gmsh.su2");
    for fixture in ["3d/hex_prism_pyr.v41_ascii.msh", "3d/box_cyl.v41_ascii.msh"] {
        let script = r#"
import sys, gmsh
gmsh.initialize(); gmsh.option.setNumber("General.Terminal", 0)
gmsh.open(sys.argv[1])
gmsh.write(sys.argv[2])
"#;
        let src = common::public_fixture(fixture);
        common::run_python(&py, script, &[src.to_str().unwrap(), out.to_str().unwrap()]);
        let text = std::fs::read_to_string(&out).unwrap();
        let declared = |key: &str| -> usize {
            text.lines()
                .filter_map(|l| l.strip_prefix(key))
                .map(|v| v.split_whitespace().next().unwrap().parse::<usize>().unwrap())
                .sum()
        };
        let ours = smartmesh_formats::read_path(&out, None).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(ours.points.len(), declared("NPOIN="), "{fixture}");
        let interior = ours.cells().filter(|c| c.0.dim() == 3).count();
        assert_eq!(interior, declared("NELEM="), "{fixture}");
        let boundary = ours.cells().filter(|c| c.0.dim() == 2).count();
        assert_eq!(boundary, declared("MARKER_ELEMS="), "{fixture}");
        let msh = common::read_file(fixture);
        assert_eq!(
            cells_by_coordinates(&ours, true),
            cells_by_coordinates(&msh, true),
            "{fixture}"
        );
        assert!(volumes(&ours).iter().all(|&v| v > 0.0), "{fixture}");
    }
}

/// meshio reads our 3D SU2 files: the same points and, per kind, the same cells in
/// VTK's node order (our prisms reordered), boundary triangles and quads included.
#[test]
fn meshio_reads_our_3d_files() {
    smartmesh_test_support::require_public_fixtures!();
    let Some(py) = common::python_with(&["meshio"]) else { return };
    let dir = tempfile::tempdir().unwrap();
    for fixture in ["3d/hex_prism_pyr.v41_ascii.msh", "3d/box_cyl.v41_ascii.msh"] {
        let m = common::read_file(fixture);
        let out = dir.path().join("m.su2");
        smartmesh_formats::write_path(&out, &m, None, &WriteOptions::default()).unwrap();
        let script = r#"
import sys, json, warnings
warnings.simplefilter("ignore")
import meshio
m = meshio.read(sys.argv[1])
cells = {}
for b in m.cells:
    cells.setdefault(b.type, []).extend(b.data.tolist())
print(json.dumps({"points": m.points.astype("<f8").view("<u8").tolist(), "cells": cells}))
"#;
        let got: serde_json::Value =
            serde_json::from_str(&common::run_python(&py, script, &[out.to_str().unwrap()]))
                .unwrap();
        let points: Vec<[u64; 3]> = serde_json::from_value(got["points"].clone()).unwrap();
        let ours: Vec<[u64; 3]> = m.points.iter().map(|p| p.map(f64::to_bits)).collect();
        assert_eq!(points, ours, "{fixture}");
        for (name, kind) in [
            ("tetra", CellKind::Tetra),
            ("hexahedron", CellKind::Hexa),
            ("wedge", CellKind::Wedge),
            ("pyramid", CellKind::Pyramid),
            ("triangle", CellKind::Triangle),
            ("quad", CellKind::Quad),
        ] {
            let mut theirs: Vec<Vec<u32>> =
                serde_json::from_value(got["cells"][name].clone()).unwrap_or_default();
            let mut want: Vec<Vec<u32>> = m
                .cells()
                .filter(|c| c.0 == kind)
                .map(|c| match kind {
                    CellKind::Wedge => [0, 2, 1, 3, 5, 4].iter().map(|&k| c.1[k]).collect(),
                    _ => c.1.to_vec(),
                })
                .collect();
            theirs.sort();
            want.sort();
            assert_eq!(theirs, want, "{fixture}: {name}");
        }
    }
}

#[test]
fn malformed_3d_files_are_refused_at_their_line() {
    let good = "NDIME= 3\nNELEM= 1\n10 0 1 2 3 0\nNPOIN= 4\n0 0 0 0\n1 0 0 1\n0 1 0 2\n0 0 1 3\nNMARK= 1\nMARKER_TAG= wall\nMARKER_ELEMS= 1\n5 0 2 1\n";
    let m = read(good.as_bytes()).unwrap();
    assert_eq!(m.num_cells_of(CellKind::Tetra), 1);
    assert_eq!(m.tag_name(2, 1), Some("wall"));
    let cases: Vec<(String, u64, &str)> = vec![
        (good.replace("10 0 1 2 3 0", "5 0 1 2"), 3, "an interior element of a 3D mesh"),
        (good.replace("5 0 2 1", "3 0 2"), 12, "a marker element of a 3D mesh"),
        (good.replace("10 0 1 2 3 0", "12 0 1 2 3"), 3, "8 point indices"),
        (good.replace("0 1 0 2", "0 1"), 7, "a z coordinate"),
        (good.replace("0 1 0 2", "0 1 nan 2"), 7, "not a finite"),
        (good.replace("10 0 1 2 3 0", "10 0 1 2 9 0"), 3, "refers to 9"),
        (good.replace("NDIME= 3\nNELEM= 1", "NELEM= 1"), 1, "`NDIME=` before"),
        (format!("NPOIN= 0\n{good}"), 2, "`NDIME=` first"),
    ];
    for (text, line, what) in cases {
        let (at, msg) = error(&text);
        assert!(msg.contains(what), "expected `{what}` in: {msg}");
        assert_eq!(at, Some(Position::Line(line)), "{msg}");
    }
}
