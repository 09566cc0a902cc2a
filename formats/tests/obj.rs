//! Wavefront OBJ: the public fixtures with their counts per group, write → read
//! identity, property tests, malformed inputs, and meshio / tobj reading what we write.

use smartmesh_test_support::formats as common;

use std::collections::BTreeMap;

use proptest::prelude::*;
use smartmesh_formats::arbitrary::{arb_tagged_mesh, MeshFeatures};
use smartmesh_formats::{
    read_bytes, write_bytes, CellBlock, CellKind, DataArray, ErrorKind, Format, Position,
    ReadContext, RegionSeed, TaggedMesh, WriteOptions,
};

fn read_str(s: &str) -> smartmesh_formats::Result<TaggedMesh> {
    read_bytes(Format::Obj, s.as_bytes(), &ReadContext::alone("obj"))
}

fn write(mesh: &TaggedMesh) -> smartmesh_formats::Written {
    write_bytes(Format::Obj, mesh, &WriteOptions::default()).unwrap_or_else(|e| panic!("{e}"))
}

/// The error of reading `s`, with the line it names.
fn error_of(s: &str) -> (ErrorKind, u64) {
    let e = read_str(s).expect_err("malformed input was accepted");
    match e.at {
        Some(Position::Line(l)) => (e.kind, l),
        other => panic!("error without a line ({other:?}): {e}"),
    }
}

/// Cells per (kind, physical tag), in order: what OBJ keeps (it regroups cells by tag).
fn by_tag(m: &TaggedMesh) -> BTreeMap<(CellKind, i32), Vec<Vec<u32>>> {
    let mut out: BTreeMap<_, Vec<Vec<u32>>> = BTreeMap::new();
    for (k, n, p, _) in m.cells() {
        out.entry((k, p)).or_default().push(n.to_vec());
    }
    out
}

/// Cells per (kind, group name), in order: `tag<N>` for unnamed tags, "" for tag 0.
fn by_name(m: &TaggedMesh) -> BTreeMap<(CellKind, String), Vec<Vec<u32>>> {
    let mut out: BTreeMap<_, Vec<Vec<u32>>> = BTreeMap::new();
    for (k, n, p, _) in m.cells() {
        let name = match (p, m.tag_name(k.dim(), p)) {
            (0, _) => String::new(),
            (_, Some(s)) => s.to_string(),
            (_, None) => format!("tag{p}"),
        };
        out.entry((k, name)).or_default().push(n.to_vec());
    }
    out
}

fn assert_points_bitwise(a: &TaggedMesh, b: &TaggedMesh) {
    assert_eq!(a.points.len(), b.points.len());
    for (i, (p, q)) in a.points.iter().zip(&b.points).enumerate() {
        assert!(
            p.iter().zip(q).all(|(x, y)| x.to_bits() == y.to_bits()),
            "point {i}: {p:?} vs {q:?}"
        );
    }
}

// ---------------------------------------------------------------------------------
// Public fixtures. Expected numbers counted independently of this reader with awk over
// the files' statements, per current `g` group:
//   awk '/^g /{g=$2} /^f /{c[g" f"(NF-1)]++} /^l /{c[g" l"(NF-1)]++} /^v /{nv++} END{...}'
// (every `l` in these files has 2 vertices, every `f` 3 or 4; no `v` has z ≠ 0).

#[test]
fn fixture_square_hole_groups() {
    smartmesh_test_support::require_public_fixtures!();
    let m = common::read_file("obj/square_hole_groups.obj");
    assert_eq!(m.points.len(), 435);
    assert_eq!(m.coordinate_dim, 2);
    // Groups in order of first use: Domain (faces), Walls, Hole (line elements).
    let expected: BTreeMap<(String, i32), usize> =
        [(("triangle".into(), 1), 774), (("line".into(), 2), 52), (("line".into(), 3), 44)]
            .into_iter()
            .collect();
    assert_eq!(common::counts_per_tag(&m), expected);
    let names: BTreeMap<(u8, i32), String> = [
        ((2, 1), "Domain".to_string()),
        ((1, 2), "Walls".to_string()),
        ((1, 3), "Hole".to_string()),
    ]
    .into_iter()
    .collect();
    assert_eq!(m.tag_names, names);
    assert!(m.blocks.iter().all(|b| b.physical == b.geometrical));
    // `l 1 9` is the first line element: 0-based 0 and 8.
    let first_line = m.blocks.iter().find(|b| b.kind == CellKind::Line).unwrap();
    assert_eq!(first_line.cell(0), &[0, 8]);
}

#[test]
fn fixture_square_hole_vtn_negative() {
    smartmesh_test_support::require_public_fixtures!();
    let m = common::read_file("obj/square_hole_vtn_negative.obj");
    assert_eq!(m.points.len(), 435);
    assert_eq!(m.coordinate_dim, 2);
    let expected: BTreeMap<(String, i32), usize> =
        [(("triangle".into(), 1), 774)].into_iter().collect();
    assert_eq!(common::counts_per_tag(&m), expected);
    assert_eq!(m.tag_name(2, 1), Some("Domain"));
    // The same triangles as the file with positive indices: negative indices resolved
    // against the vertices read so far.
    let plain = common::read_file("obj/square_hole_groups.obj");
    assert_points_bitwise(&m, &plain);
    assert_eq!(by_tag(&m)[&(CellKind::Triangle, 1)], by_tag(&plain)[&(CellKind::Triangle, 1)]);
}

#[test]
fn fixture_two_domains_mixed() {
    smartmesh_test_support::require_public_fixtures!();
    let m = common::read_file("obj/two_domains_mixed.obj");
    assert_eq!(m.points.len(), 274);
    assert_eq!(m.coordinate_dim, 2);
    let expected: BTreeMap<(String, i32), usize> =
        [(("quad".into(), 1), 119), (("triangle".into(), 2), 248)].into_iter().collect();
    assert_eq!(common::counts_per_tag(&m), expected);
    assert_eq!(m.tag_name(2, 1), Some("Left"));
    assert_eq!(m.tag_name(2, 2), Some("Right"));
}

#[test]
fn fixtures_write_read_identity() {
    smartmesh_test_support::require_public_fixtures!();
    for rel in [
        "obj/square_hole_groups.obj",
        "obj/square_hole_vtn_negative.obj",
        "obj/two_domains_mixed.obj",
    ] {
        let m = common::read_file(rel);
        let (written, back) = common::roundtrip(Format::Obj, "obj", &m, &WriteOptions::default());
        assert!(written.report.dropped.is_empty(), "{rel}: {:?}", written.report.dropped);
        assert_points_bitwise(&m, &back);
        assert_eq!(by_tag(&m), by_tag(&back), "{rel}");
        assert_eq!(m.tag_names, back.tag_names, "{rel}");
        assert_eq!(m.coordinate_dim, back.coordinate_dim);
        // Same mesh, same bytes.
        assert_eq!(write(&back).main, written.main, "{rel}: second write differs");
    }
}

// ---------------------------------------------------------------------------------
// The written file.

fn small_mesh() -> TaggedMesh {
    let mut m = TaggedMesh::new();
    m.points = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.1]];
    m.blocks.push(CellBlock {
        kind: CellKind::Triangle,
        nodes: vec![0, 1, 2, 0, 2, 3],
        physical: vec![2, 0],
        geometrical: vec![2, 0],
    });
    m.blocks.push(CellBlock {
        kind: CellKind::Line,
        nodes: vec![0, 1, 1, 2],
        physical: vec![1, 1],
        geometrical: vec![1, 1],
    });
    m.blocks.push(CellBlock {
        kind: CellKind::Vertex,
        nodes: vec![3],
        physical: vec![2],
        geometrical: vec![2],
    });
    m.tag_names.insert((1, 1), "Walls".into());
    m
}

#[test]
fn written_layout_groups_by_tag_without_timestamp() {
    let w = write(&small_mesh());
    let text = String::from_utf8(w.main).unwrap();
    let expected = "# written by smartmesh-formats 0.1.0 (Wavefront OBJ)\n\
                    v 0.0 0.0 0\nv 1.0 0.0 0\nv 1.0 1.0 0\nv 0.0 1.0 0.1\n\
                    f 1 3 4\n\
                    g Walls\nl 1 2\nl 2 3\n\
                    g tag2\nf 1 2 3\np 4\n";
    assert_eq!(text, expected);
    assert!(w.report.dropped.is_empty(), "{:?}", w.report.dropped);
    let back = read_str(&text).unwrap();
    assert_eq!(by_tag(&back), by_tag(&small_mesh()));
    assert_eq!(back.tag_names, small_mesh().tag_names);
    assert_eq!(back.coordinate_dim, 3);
}

#[test]
fn report_lists_what_obj_cannot_hold() {
    let mut m = small_mesh();
    m.point_data.insert("metric".into(), DataArray::new(9, vec![1.0; 36]));
    m.blocks[0].geometrical = vec![7, 0];
    m.blocks.push(CellBlock {
        kind: CellKind::Triangle6,
        nodes: vec![0, 1, 2, 0, 1, 2],
        physical: vec![2],
        geometrical: vec![2],
    });
    m.cell_data.insert("quality".into(), DataArray::new(1, vec![1.0; 6]));
    m.point_sets.insert("Corners".into(), vec![0]);
    m.cell_sets.insert("Ridges".into(), vec![0]);
    m.holes.push([0.5, 0.5]);
    m.regions.push(RegionSeed { point: [0.2, 0.2], attribute: 1.0, max_area: -1.0 });
    m.entities.insert((1, 1), vec![1]);
    m.tag_names.insert((2, 9), "Nobody".into());
    let w = write(&m);
    let all = w.report.dropped.join("\n");
    for needle in [
        "`metric` (9 components)",
        "`quality`",
        "geometrical tags of 1 cells",
        "1 triangle6 cells written by their 3 corner",
        "`Corners`",
        "`Ridges`",
        "1 hole",
        "1 region",
        "entity table",
        "`Nobody`",
    ] {
        assert!(all.contains(needle), "report lacks {needle}:\n{all}");
    }
    // The second-order triangle is still there, by its corners.
    let back = read_str(std::str::from_utf8(&w.main).unwrap()).unwrap();
    assert_eq!(back.num_cells_of(CellKind::Triangle), 3);
}

#[test]
fn report_says_when_named_tags_are_renumbered() {
    let mut m = TaggedMesh::new();
    m.points = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
    m.blocks.push(CellBlock {
        kind: CellKind::Triangle,
        nodes: vec![0, 1, 2],
        physical: vec![100],
        geometrical: vec![100],
    });
    m.tag_names.insert((2, 100), "Fluid".into());
    let w = write(&m);
    assert!(
        w.report.dropped.iter().any(|d| d.contains("tag 100") && d.contains("reads back as tag 1")),
        "{:?}",
        w.report.dropped
    );
    let back = read_str(std::str::from_utf8(&w.main).unwrap()).unwrap();
    assert_eq!(back.tag_name(2, 1), Some("Fluid"));
    // Unnamed tags keep their numbers through `tag<N>`.
    m.tag_names.clear();
    let w = write(&m);
    assert!(w.report.dropped.is_empty());
    let back = read_str(std::str::from_utf8(&w.main).unwrap()).unwrap();
    assert_eq!(back.blocks[0].physical, vec![100]);
    assert!(back.tag_names.is_empty());
}

#[test]
fn names_obj_cannot_hold_are_cleaned_and_reported() {
    let mut m = TaggedMesh::new();
    m.points = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
    m.blocks.push(CellBlock {
        kind: CellKind::Triangle,
        nodes: vec![0, 1, 2],
        physical: vec![1],
        geometrical: vec![1],
    });
    m.tag_names.insert((2, 1), "left  part #2\nx".into());
    let w = write(&m);
    let back = read_str(std::str::from_utf8(&w.main).unwrap()).unwrap();
    assert_eq!(back.tag_name(2, 1), Some("left part _2_x"));
    assert!(
        w.report.dropped.iter().any(|d| d.contains("written as `left part _2_x`")),
        "{:?}",
        w.report.dropped
    );
}

// ---------------------------------------------------------------------------------
// What the spec allows.

#[test]
fn negative_indices_count_back_from_the_latest_vertex() {
    let m = read_str("v 0 0\nv 1 0\nv 0 1\nf -3 -2 -1\nv 1 1\nf -3 -1 -2\n").unwrap();
    assert_eq!(m.blocks[0].nodes, vec![0, 1, 2, 1, 3, 2]);
}

#[test]
fn face_vertex_forms_v_vt_vn() {
    let m = read_str("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvt 0 0\nvn 0 0 1\nf 1/1 2/1 3/1\nf 2//1 4//1 3//1\nf 1/1/1 2/1/1 4/1/1 3/1/1\n").unwrap();
    assert_eq!(m.num_cells_of(CellKind::Triangle), 2);
    assert_eq!(m.num_cells_of(CellKind::Quad), 1);
}

#[test]
fn polylines_become_segments_and_points_vertices() {
    let m =
        read_str("v 0 0\nv 1 0\nv 1 1\nv 0 1\nl 1 2 3 4 1\np 1 3\nl 2/1 4/1\nvt 0 0\n").unwrap();
    let b = by_tag(&m);
    assert_eq!(
        b[&(CellKind::Line, 0)],
        vec![vec![0, 1], vec![1, 2], vec![2, 3], vec![3, 0], vec![1, 3]]
    );
    assert_eq!(b[&(CellKind::Vertex, 0)], vec![vec![0], vec![2]]);
}

#[test]
fn vertices_with_two_to_four_numbers_or_colours() {
    let m = read_str("v 1 2\nv 1 2 0\nv 1 2 0 0.5\nv 1 2 0 0.1 0.2 0.3\n").unwrap();
    assert_eq!(m.points, vec![[1.0, 2.0, 0.0]; 4]);
    assert_eq!(m.coordinate_dim, 2);
    let m = read_str("v 1 2 3 2\n").unwrap();
    // The weight is for rational free-form curves: not a homogeneous divisor.
    assert_eq!(m.points, vec![[1.0, 2.0, 3.0]]);
    assert_eq!(m.coordinate_dim, 3);
}

#[test]
fn groups_objects_and_the_default_group() {
    let src = "v 0 0\nv 1 0\nv 0 1\n\
               f 1 2 3\n\
               o body\nf 1 2 3\n\
               g wing left\nf 1 2 3\nl 1 2\n\
               g default\nf 1 2 3\n\
               g\nf 1 2 3\n\
               g body\nf 1 2 3\n\
               o other\np 1\n";
    let m = read_str(src).unwrap();
    let tags: Vec<i32> = m.cells().map(|c| c.2).collect();
    assert_eq!(tags, vec![0, 1, 2, 2, 0, 0, 1, 3]);
    let names: BTreeMap<(u8, i32), String> =
        [((2, 1), "body"), ((2, 2), "wing left"), ((1, 2), "wing left"), ((0, 3), "other")]
            .into_iter()
            .map(|(k, v)| (k, v.to_string()))
            .collect();
    assert_eq!(m.tag_names, names);
}

#[test]
fn default_named_groups_keep_their_numbers() {
    // `tag<N>` groups are tag N; the other groups are numbered around them.
    let m = read_str("v 0 0\nv 1 0\nv 0 1\ng A\nf 1 2 3\ng tag1\nf 1 2 3\ng tag-4\nf 1 2 3\ng B\nf 1 2 3\ng tag07\nf 1 2 3\n").unwrap();
    let tags: Vec<i32> = m.cells().map(|c| c.2).collect();
    assert_eq!(tags, vec![2, 1, -4, 3, 4]);
    assert_eq!(m.tag_name(2, 2), Some("A"));
    assert_eq!(m.tag_name(2, 3), Some("B"));
    assert_eq!(m.tag_name(2, 4), Some("tag07"), "not canonical: an ordinary name");
    assert_eq!(m.tag_name(2, 1), None);
}

#[test]
fn ignored_statements_comments_crlf_and_continuations() {
    let src = "# comment\r\nmtllib a.mtl\r\nusemtl red\r\ns off\r\nvp 0.5\r\nmg 1 0.5\r\n\
               v 0 0 # inline comment\r\nv 1 \\\r\n 0\r\nv 0 1\r\nf 1 2 \\\n3\r\nf 1\\\n 2 3\n";
    let m = read_str(src).unwrap();
    assert_eq!(m.points, vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
    assert_eq!(m.blocks[0].nodes, vec![0, 1, 2, 0, 1, 2]);
    // Lines keep counting through continuations.
    let (_, line) = error_of("v 0 0\nf 1 \\\n 2 \\\n 3 9\n");
    assert_eq!(line, 4);
}

#[test]
fn forward_references_are_allowed() {
    let m = read_str("f 1 2 3\nv 0 0\nv 1 0\nv 0 1\n").unwrap();
    assert_eq!(m.blocks[0].nodes, vec![0, 1, 2]);
}

#[test]
fn empty_file_is_an_empty_mesh() {
    let m = read_str("# nothing\n\n").unwrap();
    assert!(m.points.is_empty() && m.blocks.is_empty());
}

// ---------------------------------------------------------------------------------
// Malformed inputs: each an error naming its line.

#[test]
fn malformed_index_out_of_range() {
    let (k, l) = error_of("v 0 0\nv 1 0\nv 0 1\nf 1 2 3\nf 1 2 4\n");
    assert!(matches!(k, ErrorKind::IndexOutOfRange { index: 4, available: 3, .. }), "{k}");
    assert_eq!(l, 5);
}

#[test]
fn malformed_negative_index_before_the_first_vertex() {
    let (k, l) = error_of("v 0 0\nv 1 0\nf -1 -2 -3\n");
    assert!(matches!(k, ErrorKind::IndexOutOfRange { index: -3, available: 2, .. }), "{k}");
    assert_eq!(l, 3);
}

#[test]
fn malformed_index_zero() {
    let (k, l) = error_of("v 0 0\nv 1 0\nv 0 1\nl 0 1\n");
    assert!(matches!(k, ErrorKind::Expected { .. }), "{k}");
    assert!(k.to_string().contains("1-based"), "{k}");
    assert_eq!(l, 4);
}

#[test]
fn malformed_nan_coordinate() {
    let (k, l) = error_of("v 0 0\nv nan 0\n");
    assert!(matches!(k, ErrorKind::NonFinite { .. }), "{k}");
    assert_eq!(l, 2);
    let (k, _) = error_of("v 0 1e400\n");
    assert!(matches!(k, ErrorKind::NonFinite { .. }), "{k}");
    let (k, _) = error_of("v 0 zero\n");
    assert!(matches!(k, ErrorKind::Expected { .. }), "{k}");
}

#[test]
fn malformed_truncated_face() {
    let (k, l) = error_of("v 0 0\nv 1 0\nv 0 1\nf 1 2\nf 1 2 3\n");
    assert!(k.to_string().contains("3 or 4 vertices"), "{k}");
    assert_eq!(l, 4);
    // The file ends in the middle of the statement.
    let (_, l) = error_of("v 0 0\nv 1 0\nv 0 1\nf 1");
    assert_eq!(l, 4);
    let (_, l) = error_of("v 0 0\nv 1 0\nf");
    assert_eq!(l, 3);
}

#[test]
fn malformed_polygon_of_five_vertices() {
    let (k, l) = error_of("v 0 0\nv 1 0\nv 2 1\nv 1 2\nv 0 1\nf 1 2 3 4 5\n");
    assert!(k.to_string().contains("5 vertices") && k.to_string().contains("triangulate"), "{k}");
    assert_eq!(l, 6);
}

#[test]
fn malformed_unknown_statement() {
    let (k, l) = error_of("v 0 0\nvx 1 2\n");
    assert!(matches!(k, ErrorKind::Expected { .. }) && k.to_string().contains("`vx`"), "{k}");
    assert_eq!(l, 2);
}

#[test]
fn malformed_free_form_geometry_is_unsupported() {
    let (k, l) = error_of("v 0 0\nv 1 0\ncstype bspline\ncurv 0 1 1 2\n");
    assert!(matches!(k, ErrorKind::Unsupported(_)), "{k}");
    assert_eq!(l, 3);
    let (k, _) = error_of("call other.obj\n");
    assert!(matches!(k, ErrorKind::Unsupported(_)), "{k}");
}

#[test]
fn malformed_line_of_one_vertex_and_empty_point() {
    let (_, l) = error_of("v 0 0\nl 1\n");
    assert_eq!(l, 2);
    let (_, l) = error_of("v 0 0\n\np\n");
    assert_eq!(l, 3);
}

#[test]
fn malformed_vertex_coordinate_count() {
    let (k, l) = error_of("v 0 0\nv 1\n");
    assert!(k.to_string().contains("2 to 4 numbers"), "{k}");
    assert_eq!(l, 2);
    let (_, l) = error_of("v 1 2 3 4 5\n");
    assert_eq!(l, 1);
}

#[test]
fn malformed_vertex_references() {
    for (src, line) in [
        ("v 0 0\nv 1 0\nv 0 1\nf 1/x 2 3\n", 4),
        ("v 0 0\nv 1 0\nv 0 1\nf 1/ 2 3\n", 4),
        ("v 0 0\np 1/1\n", 2),
        ("v 0 0\nv 1 0\nvn 0 0 1\nl 1//1 2//1\n", 4),
        ("v 0 0\nv 1 0\nv 0 1\nf one 2 3\n", 4),
        ("v 0 0\nv 1 0\nv 0 1\nf 1/1/1/1 2 3\n", 4),
    ] {
        let (k, l) = error_of(src);
        assert!(matches!(k, ErrorKind::Expected { .. }), "{src:?}: {k}");
        assert_eq!(l, line, "{src:?}");
    }
}

#[test]
fn malformed_texture_and_normal_indices_out_of_range() {
    let (k, l) = error_of("v 0 0\nv 1 0\nv 0 1\nvt 0 0\nf 1/1 2/2 3/1\n");
    assert!(matches!(k, ErrorKind::IndexOutOfRange { index: 2, available: 1, .. }), "{k}");
    assert_eq!(l, 5);
    let (k, _) = error_of("v 0 0\nv 1 0\nv 0 1\nf 1//1 2//1 3//1\n");
    assert!(matches!(k, ErrorKind::IndexOutOfRange { .. }), "{k}");
}

#[test]
fn malformed_forward_reference_past_the_end() {
    let (k, l) = error_of("v 0 0\nf 1 2 3\nv 1 0\nf 1 2 9\nv 0 1\n");
    assert!(matches!(k, ErrorKind::IndexOutOfRange { index: 9, available: 3, .. }), "{k}");
    assert_eq!(l, 4);
}

#[test]
fn malformed_errors_read_like_a_compiler() {
    let e = read_str("v 0 0\nv 1 0\nv 0 1\nf 1 2 4\n").unwrap_err();
    assert_eq!(e.to_string(), "<stdin>:4: vertex index refers to 4, but only 3 exist");
}

// ---------------------------------------------------------------------------------
// Properties.

const OBJ_FEATURES: MeshFeatures = MeshFeatures {
    quads: true,
    lines: true,
    vertices: true,
    geometrical: false,
    names: false,
    point_scalar: false,
    point_tensor: false,
    negative_tags: true,
};

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn prop_write_read_identity(mesh in arb_tagged_mesh(OBJ_FEATURES)) {
        let (written, back) = common::roundtrip(Format::Obj, "obj", &mesh, &WriteOptions::default());
        prop_assert!(written.report.dropped.is_empty(), "{:?}", written.report.dropped);
        assert_points_bitwise(&mesh, &back);
        prop_assert_eq!(by_tag(&mesh), by_tag(&back));
        prop_assert!(back.tag_names.is_empty());
        prop_assert!(back.blocks.iter().all(|b| b.physical == b.geometrical));
        prop_assert_eq!(write(&back).main, written.main);
    }

    #[test]
    fn prop_named_groups_survive_by_name(mesh in arb_tagged_mesh(MeshFeatures { names: true, ..OBJ_FEATURES })) {
        let (written, back) = common::roundtrip(Format::Obj, "obj", &mesh, &WriteOptions::default());
        assert_points_bitwise(&mesh, &back);
        prop_assert_eq!(by_name(&mesh), by_name(&back));
        // Tag numbers change only where the report says so.
        if !written.report.dropped.iter().any(|d| d.contains("reads back as")) {
            prop_assert_eq!(by_tag(&mesh), by_tag(&back));
        }
    }

    #[test]
    fn prop_arbitrary_bytes_never_panic(bytes in prop::collection::vec(any::<u8>(), 0..400)) {
        let _ = read_bytes(Format::Obj, &bytes, &ReadContext::alone("obj"));
    }

    #[test]
    fn prop_statement_soup_never_panics(lines in prop::collection::vec(
        prop_oneof![
            Just("v 0 0".to_string()), Just("v 1 2 3".to_string()), Just("vt 0 0".to_string()), Just("g a".to_string()),
            Just("g".to_string()), Just("o b".to_string()), Just("\\".to_string()), Just("# c".to_string()),
            (1i64..6, -6i64..6, -6i64..6).prop_map(|(a, b, c)| format!("f {a} {b} {c}")),
            (-6i64..6, -6i64..6).prop_map(|(a, b)| format!("l {a}/1 {b}")),
            (-9i64..9).prop_map(|a| format!("p {a}")),
        ], 0..30)) {
        let _ = read_str(&lines.join("\n"));
    }
}

// ---------------------------------------------------------------------------------
// Other readers of what we write.

#[test]
fn interop_meshio_reads_our_obj() {
    smartmesh_test_support::require_public_fixtures!();
    let Some(py) = common::python_with(&["meshio"]) else { return };
    let dir = tempfile::tempdir().unwrap();
    for rel in ["obj/square_hole_groups.obj", "obj/two_domains_mixed.obj"] {
        let m = common::read_file(rel);
        let path = dir.path().join("out.obj");
        smartmesh_formats::write_path(&path, &m, None, &WriteOptions::default()).unwrap();
        let script = "import sys, meshio\n\
                      m = meshio.read(sys.argv[1])\n\
                      for p in m.points: print('v', *[repr(float(x)) for x in p])\n\
                      for b, g in zip(m.cells, m.cell_data['obj:group_ids']):\n\
                      \x20   for c, gid in zip(b.data, g): print(b.type, int(gid), *[int(i) for i in c])\n";
        let out = common::run_python(&py, script, &[path.to_str().unwrap()]);
        let mut points = Vec::new();
        let mut cells: BTreeMap<(String, i64), Vec<Vec<u32>>> = BTreeMap::new();
        for line in out.lines() {
            let w: Vec<&str> = line.split_whitespace().collect();
            if w[0] == "v" {
                let p: Vec<f64> = w[1..]
                    .iter()
                    .map(|s| smartmesh_formats::text::parse_f64(s.as_bytes()).unwrap())
                    .collect();
                points.push([p[0], p[1], p[2]]);
            } else {
                let gid: i64 = w[1].parse().unwrap();
                cells
                    .entry((w[0].to_string(), gid))
                    .or_default()
                    .push(w[2..].iter().map(|s| s.parse().unwrap()).collect());
            }
        }
        let theirs = TaggedMesh { points, ..TaggedMesh::new() };
        assert_points_bitwise(&m, &theirs);
        // meshio numbers `g` statements from 0 and reads faces only (no `l`, no `p`): our
        // face groups are the groups with faces, in tag order.
        let ours = by_tag(&m);
        let face_groups: Vec<i32> = {
            let mut tags: Vec<i32> = m.cells().map(|c| c.2).collect();
            tags.sort_unstable();
            tags.dedup();
            tags.retain(|&t| t != 0);
            tags
        };
        for ((name, gid), list) in &cells {
            let kind = if name == "triangle" { CellKind::Triangle } else { CellKind::Quad };
            let tag = if *gid < 0 { 0 } else { face_groups[*gid as usize] };
            assert_eq!(&ours[&(kind, tag)], list, "{rel}: meshio group {gid}");
        }
        let faces: usize = cells.values().map(Vec::len).sum();
        assert_eq!(
            faces,
            m.num_cells_of(CellKind::Triangle) + m.num_cells_of(CellKind::Quad),
            "{rel}"
        );
    }
}

#[test]
fn interop_tobj_reads_our_obj() {
    smartmesh_test_support::require_public_fixtures!();
    // tobj (a Rust OBJ loader) gives each group its own vertex copy: compare positions
    // through its indices, in f32 as tobj stores them.
    let m = common::read_file("obj/two_domains_mixed.obj");
    let w = write(&m);
    let opts = tobj::LoadOptions {
        single_index: true,
        triangulate: false,
        ignore_points: true,
        ignore_lines: true,
    };
    let (models, _) =
        tobj::load_obj_buf(&mut std::io::Cursor::new(&w.main), &opts, |_| Ok(Default::default()))
            .unwrap();
    let names: Vec<&str> = models.iter().map(|x| x.name.as_str()).collect();
    assert_eq!(names, ["Left", "Right"]);
    let ours = by_tag(&m);
    for (model, (kind, tag)) in models.iter().zip([(CellKind::Quad, 1), (CellKind::Triangle, 2)]) {
        let k = kind.nodes_per_cell();
        let cells = &ours[&(kind, tag)];
        assert_eq!(model.mesh.indices.len(), cells.len() * k);
        for (c, theirs) in cells.iter().zip(model.mesh.indices.chunks(k)) {
            for (&v, &t) in c.iter().zip(theirs) {
                let p = &model.mesh.positions[3 * t as usize..3 * t as usize + 3];
                assert_eq!(
                    [p[0], p[1], p[2]],
                    [
                        m.points[v as usize][0] as f32,
                        m.points[v as usize][1] as f32,
                        m.points[v as usize][2] as f32
                    ]
                );
            }
        }
    }
}

#[test]
fn a_cr_only_file_reads_as_its_lines() {
    // Old Mac line ends: a lone CR ends a line (and a comment), as tobj reads it.
    let text = "# a triangle\rv 0 0 0\rv 1 0 0\rv 0 1 0\rg Domain\rf 1 2 3\r";
    let m = read_str(text).unwrap();
    assert_eq!(m.points.len(), 3);
    assert_eq!(m.num_cells_of(CellKind::Triangle), 1);
    // Lines are counted at the CRs.
    let (_, line) = error_of("v 0 0 0\rv 1 0 0\rf 1 2 9\r");
    assert_eq!(line, 3);
}

#[test]
fn invisible_characters_are_named_in_errors() {
    let e = read_str("v 0\u{a0}0 0\n").unwrap_err();
    assert!(e.to_string().contains("no-break space (U+00A0)"), "{e}");
    let e = read_str("\u{feff}v 0 0 0\n").unwrap_err();
    assert!(e.to_string().contains("byte order mark (U+FEFF)"), "{e}");
}

// ---------------------------------------------------------------------------------
// Surfaces in space and volume meshes

/// Two unit hexahedra stacked along z (a 1 x 1 x 2 block) tagged 1 `block`, with a
/// bottom quad tagged 5 `floor`, coordinates off the axes planes so z matters.
fn two_hexahedra() -> TaggedMesh {
    let mut m = TaggedMesh::new();
    m.coordinate_dim = 3;
    for z in 0..3 {
        for &(x, y) in &[(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)] {
            m.points.push([x + 0.1, y - 0.3, 0.7 + z as f64]);
        }
    }
    m.block_mut(CellKind::Hexa).push(&[0u32, 1, 2, 3, 4, 5, 6, 7], 1, 1);
    m.block_mut(CellKind::Hexa).push(&[4u32, 5, 6, 7, 8, 9, 10, 11], 1, 1);
    m.block_mut(CellKind::Quad).push(&[0u32, 3, 2, 1], 5, 5);
    m.tag_names.insert((3, 1), "block".into());
    m.tag_names.insert((2, 5), "floor".into());
    m
}

/// The volume enclosed by the triangles and quads of `m` (divergence theorem): the
/// block's volume when the skin is closed and every face points outwards.
fn enclosed_volume(m: &TaggedMesh) -> f64 {
    let det = |a: [f64; 3], b: [f64; 3], c: [f64; 3]| {
        a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
            + a[2] * (b[0] * c[1] - b[1] * c[0])
    };
    m.cells()
        .filter(|c| c.0.dim() == 2)
        .map(|(_, n, _, _)| {
            let p = |i: usize| m.points[n[i] as usize];
            (1..n.len() - 1).map(|i| det(p(0), p(i), p(i + 1)) / 6.0).sum::<f64>()
        })
        .sum()
}

/// A volume mesh is written as its boundary, outward, with z kept bit for bit: the
/// floor keeps its own group, the other faces take the block's name.
#[test]
fn a_volume_mesh_is_written_as_its_boundary_with_z() {
    let m = two_hexahedra();
    let w = write(&m);
    assert!(
        w.report.dropped.iter().any(|d| d.contains("2 hexa") && d.contains("10 faces")),
        "{:?}",
        w.report.dropped
    );
    let back = read_bytes(Format::Obj, &w.main, &ReadContext::alone("obj")).unwrap();
    assert_eq!(back.coordinate_dim, 3);
    assert_points_bitwise(&m, &back);
    let names = by_name(&back);
    assert_eq!(names[&(CellKind::Quad, "floor".to_string())], vec![vec![0, 3, 2, 1]]);
    assert_eq!(names[&(CellKind::Quad, "block".to_string())].len(), 9);
    assert_eq!(back.num_cells(), 10);
    assert!((enclosed_volume(&back) - 2.0).abs() < 1e-12, "{}", enclosed_volume(&back));
}

/// meshio reads the boundary we write with its z (3D points) and its 10 quads.
#[test]
fn meshio_reads_a_volume_mesh_boundary() {
    let Some(py) = common::python_with(&["meshio"]) else { return };
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("block.obj");
    smartmesh_formats::write_path(&out, &two_hexahedra(), None, &WriteOptions::default()).unwrap();
    let script = r#"
import sys, json, warnings
warnings.simplefilter("ignore")
import meshio
m = meshio.read(sys.argv[1])
cells = {}
for b in m.cells:
    cells[b.type] = cells.get(b.type, 0) + len(b.data)
print(json.dumps({"z": m.points[:, 2].tolist(), "cells": cells}))
"#;
    let got: serde_json::Value =
        serde_json::from_str(&common::run_python(&py, script, &[out.to_str().unwrap()])).unwrap();
    let z: Vec<f64> = serde_json::from_value(got["z"].clone()).unwrap();
    let want: Vec<f64> = two_hexahedra().points.iter().map(|p| p[2]).collect();
    assert_eq!(z, want);
    let quads: u64 = got["cells"]["quad"].as_u64().unwrap();
    assert_eq!(quads, 10);
}
