//! Triangle's .node/.ele/.poly/.edge/.area: the public sample set, round trips, property
//! tests and malformed input.

use smartmesh_test_support::formats as common;

use std::collections::BTreeMap;

use common::{counts_per_tag, public_fixture, public_fixtures, read_file, roundtrip};
use proptest::prelude::*;
use smartmesh_formats::arbitrary::{arb_tagged_mesh, MeshFeatures};
use smartmesh_formats::{
    read_bytes, write_bytes, CellBlock, CellKind, DataArray, ErrorKind, Format, MemorySiblings,
    NoSiblings, ReadContext, RegionSeed, TaggedMesh, WriteOptions,
};

fn opts(main: &str) -> WriteOptions {
    WriteOptions { main_name: Some(main.to_string()), ..Default::default() }
}

fn counts(entries: &[(&str, i32, usize)]) -> BTreeMap<(String, i32), usize> {
    entries.iter().map(|&(k, t, n)| ((k.to_string(), t), n)).collect()
}

/// Count of each value of an integer point array.
fn histogram(a: &DataArray) -> BTreeMap<i64, usize> {
    let mut m = BTreeMap::new();
    for &v in &a.values {
        *m.entry(v as i64).or_insert(0) += 1;
    }
    m
}

fn read_mem(
    main_ext: &str,
    main: &str,
    siblings: &[(&str, &str)],
) -> smartmesh_formats::Result<TaggedMesh> {
    let sib = MemorySiblings {
        files: siblings.iter().map(|(e, s)| (e.to_string(), s.as_bytes().to_vec())).collect(),
    };
    let ctx = ReadContext { siblings: &sib, extension: main_ext.into() };
    read_bytes(Format::Triangle, main.as_bytes(), &ctx)
}

// -----------------------------------------------------------------------------------------
// Public fixtures. The expected numbers were counted with a 30-line Python script that
// strips `#` comments, splits lines into fields and tallies the segment markers of the
// .poly (or the edges and `-1` rays of the .edge), the triangles of the .ele, and the last
// field of each .node record; nothing of smartmesh is involved.
// -----------------------------------------------------------------------------------------

#[test]
fn box_pslg() {
    smartmesh_test_support::require_public_fixtures!();
    let m = read_file("triangle/box.poly");
    assert_eq!(m.points.len(), 8);
    assert_eq!(counts_per_tag(&m), counts(&[("line", 0, 3), ("line", 5, 1), ("line", 10, 1)]));
    assert_eq!(m.holes, vec![[1.5, 1.5]]);
    assert!(m.regions.is_empty());
    // The vertex markers: 0 0 0 33 0 0 0 0.
    assert_eq!(histogram(&m.point_data["triangle:marker"]), BTreeMap::from([(0, 7), (33, 1)]));
}

#[test]
fn box_meshes_from_every_main_file() {
    smartmesh_test_support::require_public_fixtures!();
    let expected = [
        ("box.1", 8, 8, vec![("line", 1, 6), ("line", 5, 1), ("line", 10, 1)]),
        ("box.2", 40, 62, vec![("line", 1, 14), ("line", 5, 3), ("line", 10, 1)]),
        ("box.3", 142, 251, vec![("line", 1, 25), ("line", 5, 7), ("line", 10, 1)]),
        ("box.4", 531, 992, vec![("line", 1, 52), ("line", 5, 15), ("line", 10, 3)]),
    ];
    for (base, np, ntri, lines) in expected {
        let reference = read_file(&format!("triangle/{base}.node"));
        let mut c = lines.clone();
        c.push(("triangle", 0, ntri));
        assert_eq!(reference.points.len(), np, "{base}");
        assert_eq!(counts_per_tag(&reference), counts(&c), "{base}");
        assert_eq!(reference.holes.len(), 1);
        for ext in ["ele", "poly"] {
            assert_eq!(read_file(&format!("triangle/{base}.{ext}")), reference, "{base}.{ext}");
        }
    }
}

#[test]
fn box_4_vertex_markers() {
    smartmesh_test_support::require_public_fixtures!();
    let m = read_file("triangle/box.4.ele");
    assert_eq!(
        histogram(&m.point_data["triangle:marker"]),
        BTreeMap::from([(0, 461), (1, 49), (5, 16), (10, 4), (33, 1)])
    );
}

#[test]
#[allow(clippy::excessive_precision)] // the values as the files print them
fn a_with_vertex_attributes() {
    smartmesh_test_support::require_public_fixtures!();
    let m = read_file("triangle/A.poly");
    assert_eq!(m.points.len(), 29);
    assert_eq!(counts_per_tag(&m), counts(&[("line", 0, 29)]));
    assert_eq!(m.holes, vec![[0.47, -0.5]]);
    // "1 0.200000 -0.776400 -0.57": one attribute per vertex, no markers.
    assert_eq!(m.point_data["triangle:attribute1"].values[0], -0.57);
    assert!(!m.point_data.contains_key("triangle:marker"));

    let m = read_file("triangle/A.1.node");
    assert_eq!(counts_per_tag(&m), counts(&[("line", 1, 29), ("triangle", 0, 29)]));
    assert_eq!(histogram(&m.point_data["triangle:marker"]), BTreeMap::from([(1, 29)]));
    assert_eq!(m.point_data["triangle:attribute1"].values[0], -0.56999999999999995);
    // The .ele has no attributes: no cell data, tags 0.
    assert!(m.cell_data.is_empty());
}

#[test]
fn bbox_area_constraints() {
    smartmesh_test_support::require_public_fixtures!();
    let m = read_file("triangle/bbox.1.area");
    assert_eq!(m.points.len(), 12);
    assert_eq!(counts_per_tag(&m), counts(&[("triangle", 0, 12)]));
    let area = &m.cell_data["triangle:area"].values;
    // Triangle 3 has bound 0.02, the others -1.
    assert_eq!(area[2], 0.02);
    assert_eq!(area.iter().filter(|&&a| a == -1.0).count(), 11);
    assert_eq!(
        histogram(&m.point_data["triangle:marker"]),
        BTreeMap::from([(1, 6), (5, 3), (10, 2), (33, 1)])
    );
    assert_eq!(read_file("triangle/bbox.1.node"), m);
}

#[test]
fn double_hex_family() {
    smartmesh_test_support::require_public_fixtures!();
    let lines = [("line", 1, 72), ("line", 2, 12), ("line", 3, 12)];
    let m = read_file("triangle/double_hex.poly");
    assert_eq!(m.points.len(), 96);
    assert_eq!(counts_per_tag(&m), counts(&lines));
    assert_eq!(m.holes.len(), 2);
    for (base, np, ntri) in
        [("double_hex.1", 96, 98), ("double_hex.2", 525, 956), ("double_hex3.1", 531, 968)]
    {
        let m = read_file(&format!("triangle/{base}.ele"));
        let mut c = lines.to_vec();
        c.push(("triangle", 0, ntri));
        assert_eq!(m.points.len(), np, "{base}");
        assert_eq!(counts_per_tag(&m), counts(&c), "{base}");
        assert_eq!(m.holes.len(), 2);
    }
    let small = [("line", 1, 36), ("line", 2, 6), ("line", 3, 6)];
    assert_eq!(counts_per_tag(&read_file("triangle/double_hex2.poly")), counts(&small));
    for (base, ntri) in [("double_hex2.1", 50), ("double_hex2.2", 236)] {
        let mut c = small.to_vec();
        c.push(("triangle", 0, ntri));
        assert_eq!(
            counts_per_tag(&read_file(&format!("triangle/{base}.node"))),
            counts(&c),
            "{base}"
        );
    }
}

#[test]
fn double_hex3_node_and_poly_agree() {
    smartmesh_test_support::require_public_fixtures!();
    // double_hex3.poly lists its own 16 vertices, the same as double_hex3.node.
    let from_poly = read_file("triangle/double_hex3.poly");
    let from_node = read_file("triangle/double_hex3.node");
    assert_eq!(from_poly.points, from_node.points);
    assert_eq!(
        counts_per_tag(&from_node),
        counts(&[("line", 1, 4), ("line", 2, 6), ("line", 3, 6)])
    );
    assert_eq!(from_node.holes.len(), 2);
}

#[test]
fn face_and_la() {
    smartmesh_test_support::require_public_fixtures!();
    let face = [("line", 2, 8), ("line", 3, 4), ("line", 4, 4), ("line", 5, 4), ("line", 6, 2)];
    let m = read_file("triangle/face.poly");
    assert_eq!(m.points.len(), 26);
    assert_eq!(counts_per_tag(&m), counts(&face));
    assert_eq!(m.holes.len(), 3);
    let mut c = face.to_vec();
    c.push(("triangle", 0, 36));
    assert_eq!(counts_per_tag(&read_file("triangle/face.1.ele")), counts(&c));

    let m = read_file("triangle/la.poly");
    assert_eq!(m.points.len(), 141);
    assert_eq!(
        counts_per_tag(&m),
        counts(&[
            ("line", 0, 12),
            ("line", 101, 2),
            ("line", 102, 18),
            ("line", 103, 25),
            ("line", 104, 32),
            ("line", 105, 26),
            ("line", 106, 33)
        ])
    );
    // "1 6 -0.2 0.05": no area column, so Triangle takes the attribute as the area too.
    assert_eq!(m.regions.len(), 6);
    assert_eq!(m.regions[0], RegionSeed { point: [6.0, -0.2], attribute: 0.05, max_area: 0.05 });

    let m = read_file("triangle/la.1.poly");
    assert_eq!(m.points.len(), 860);
    assert_eq!(
        counts_per_tag(&m),
        counts(&[
            ("line", 1, 16),
            ("line", 101, 120),
            ("line", 102, 126),
            ("line", 103, 72),
            ("line", 104, 57),
            ("line", 105, 48),
            ("line", 106, 60),
            ("triangle", 0, 1566)
        ])
    );
    assert_eq!(m.regions.len(), 6);
}

#[test]
fn point_sets_and_plain_meshes() {
    smartmesh_test_support::require_public_fixtures!();
    for (file, np) in [("diamond_02_00009.node", 9), ("dots.node", 100), ("spiral.node", 15)] {
        let m = read_file(&format!("triangle/{file}"));
        assert_eq!(m.points.len(), np, "{file}");
        assert_eq!(m.num_cells(), 0);
        assert!(m.point_data.is_empty());
    }
    for (file, np, ntri) in [
        ("diamond_02_00009.1.ele", 9, 12),
        ("ell.ele", 21, 24),
        ("spiral.1.ele", 15, 15),
        ("spiral.q.1.ele", 20, 23),
        ("spiral.r.1.ele", 27, 35),
        ("square_circle_hole.1.ele", 826, 1517),
    ] {
        let m = read_file(&format!("triangle/{file}"));
        assert_eq!(m.points.len(), np, "{file}");
        assert_eq!(counts_per_tag(&m), counts(&[("triangle", 0, ntri)]), "{file}");
    }
    assert_eq!(
        histogram(&read_file("triangle/ell.node").point_data["triangle:marker"]),
        BTreeMap::from([(0, 6), (1, 15)])
    );
    let m = read_file("triangle/square_circle_hole.poly");
    assert_eq!(m.points.len(), 826);
    assert_eq!(counts_per_tag(&m), counts(&[("line", 1, 112), ("line", 2, 23)]));
    assert_eq!(m.holes.len(), 1);
}

#[test]
fn voronoi_edges_and_rays() {
    smartmesh_test_support::require_public_fixtures!();
    let m = read_file("triangle/diamond_02_00009.1.v.edge");
    assert_eq!(m.points.len(), 12);
    assert_eq!(counts_per_tag(&m), counts(&[("line", 0, 16), ("vertex", 0, 4)]));
    // "3   1  -1   -1  0": the first ray starts at vertex 1 and goes along -x.
    let dir = &m.cell_data["triangle:ray_direction"];
    assert_eq!(dir.item(0), &[-1.0, 0.0, 0.0]);
    assert_eq!(m.blocks[0].nodes[0], 0);
    assert_eq!(read_file("triangle/diamond_02_00009.1.v.node"), m);

    let m = read_file("triangle/dots.1.v.edge");
    assert_eq!(m.points.len(), 187);
    assert_eq!(counts_per_tag(&m), counts(&[("line", 0, 275), ("vertex", 0, 11)]));
}

#[test]
fn greenland() {
    smartmesh_test_support::require_public_fixtures!();
    let m = read_file("triangle/greenland.ele");
    assert_eq!(m.points.len(), 33343);
    assert_eq!(counts_per_tag(&m), counts(&[("triangle", 0, 64125)]));
    let h = histogram(&m.point_data["triangle:marker"]);
    assert_eq!((h[&0], h[&1], h[&367], h.len()), (30784, 629, 24, 610));
}

/// Every file of the folder reads as a main file, and gives the same mesh as the other
/// main files of its set.
#[test]
fn every_public_file_reads() {
    smartmesh_test_support::require_public_fixtures!();
    let dir = public_fixtures().join("triangle");
    let mut by_base: BTreeMap<String, TaggedMesh> = BTreeMap::new();
    let mut names: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .collect();
    names.sort();
    assert!(names.len() >= 69, "{} files", names.len());
    for name in names {
        let path = public_fixture(&format!("triangle/{name}"));
        let m = smartmesh_formats::read_path(&path, None).unwrap_or_else(|e| panic!("{e}"));
        let base = name.rsplit_once('.').unwrap().0.to_string();
        match by_base.get(&base) {
            Some(first) => assert_eq!(first, &m, "{name}"),
            None => {
                by_base.insert(base, m);
            }
        }
    }
}

// -----------------------------------------------------------------------------------------
// Writing
// -----------------------------------------------------------------------------------------

/// A tagged mesh with everything Triangle holds.
fn full_mesh() -> TaggedMesh {
    let mut m = TaggedMesh::new();
    m.points = vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.5, 0.5, 0.0],
        [0.1, 1e-7, 0.0],
    ];
    m.blocks.push(CellBlock {
        kind: CellKind::Line,
        nodes: vec![0, 1, 1, 2, 2, 3, 3, 0],
        physical: vec![1, 2, -3, 4],
        geometrical: vec![1, 2, -3, 4],
    });
    m.blocks.push(CellBlock {
        kind: CellKind::Triangle,
        nodes: vec![0, 1, 4, 1, 2, 4, 2, 3, 4, 3, 0, 4],
        physical: vec![7, 7, 8, 8],
        geometrical: vec![7, 7, 8, 8],
    });
    m.point_data
        .insert("triangle:marker".into(), DataArray::new(1, vec![1.0, 2.0, 2.0, 4.0, 0.0, 0.0]));
    m.point_data.insert(
        "triangle:attribute1".into(),
        DataArray::new(1, vec![0.5, 1.5, 2.5, 3.5, 4.5, 1.0 / 3.0]),
    );
    // Cell data covers the lines too; they carry 0 attributes and no area bound.
    m.cell_data.insert(
        "triangle:attribute1".into(),
        DataArray::new(1, vec![0.0, 0.0, 0.0, 0.0, 7.0, 7.0, 8.0, 8.0]),
    );
    m.cell_data.insert(
        "triangle:attribute2".into(),
        DataArray::new(1, vec![0.0, 0.0, 0.0, 0.0, 0.25, -1.5, 1e300, 0.0]),
    );
    m.cell_data.insert(
        "triangle:area".into(),
        DataArray::new(1, vec![-1.0, -1.0, -1.0, -1.0, 0.01, -1.0, 0.5, -1.0]),
    );
    m.holes = vec![[0.25, 0.75]];
    m.regions = vec![
        RegionSeed { point: [0.5, 0.25], attribute: 7.0, max_area: 0.1 },
        RegionSeed { point: [0.5, 0.75], attribute: 8.0, max_area: -1.0 },
    ];
    m
}

#[test]
fn write_read_identity_every_main_file() {
    let m = full_mesh();
    for main in ["out.node", "out.ele", "out.poly", "out.area"] {
        let ext = main.rsplit_once('.').unwrap().1;
        let (written, back) = roundtrip(Format::Triangle, ext, &m, &opts(main));
        assert!(written.report.dropped.is_empty(), "{main}: {:?}", written.report.dropped);
        let mut exts: Vec<_> = written.siblings.iter().map(|(e, _)| e.as_str()).collect();
        exts.push(ext);
        exts.sort_unstable();
        assert_eq!(exts, ["area", "ele", "node", "poly"], "{main}");
        assert_eq!(back, m, "{main}");
        for (a, b) in back.points.iter().zip(&m.points) {
            assert_eq!(a.map(f64::to_bits), b.map(f64::to_bits));
        }
    }
}

#[test]
fn written_files_look_like_triangle_output() {
    let w = write_bytes(Format::Triangle, &full_mesh(), &opts("out.node")).unwrap();
    let text = String::from_utf8(w.main).unwrap();
    assert!(text.starts_with("6 2 1 1\n1 0.0 0.0 0.5 1\n"), "{text}");
    let poly = &w.siblings.iter().find(|(e, _)| e == "poly").unwrap().1;
    let poly = String::from_utf8(poly.clone()).unwrap();
    assert!(poly.starts_with("0 2 1 1\n4 1\n1 1 2 1\n"), "{poly}");
    assert!(
        poly.ends_with("1\n1 0.25 0.75\n2\n1 0.5 0.25 7.0 0.1\n2 0.5 0.75 8.0 -1.0\n"),
        "{poly}"
    );
    let ele =
        String::from_utf8(w.siblings.iter().find(|(e, _)| e == "ele").unwrap().1.clone()).unwrap();
    assert!(ele.starts_with("4 3 2\n1 1 2 5 7 0.25\n"), "{ele}");
}

#[test]
fn self_contained_pslg() {
    let mut m = full_mesh();
    m.blocks.retain(|b| b.kind == CellKind::Line);
    m.cell_data.clear();
    for main in [Some("pslg.poly"), None] {
        let o = WriteOptions { main_name: main.map(str::to_string), ..Default::default() };
        let w = write_bytes(Format::Triangle, &m, &o).unwrap();
        assert!(w.siblings.is_empty(), "{main:?}");
        assert!(w.report.dropped.is_empty());
        let back = read_bytes(
            Format::Triangle,
            &w.main,
            &ReadContext { siblings: &NoSiblings, extension: "poly".into() },
        )
        .unwrap();
        assert_eq!(back, m);
        // A stream without extension reads the same.
        let back = read_bytes(
            Format::Triangle,
            &w.main,
            &ReadContext { siblings: &NoSiblings, extension: String::new() },
        )
        .unwrap();
        assert_eq!(back, m);
    }
}

#[test]
fn mesh_to_stdout_needs_siblings() {
    let w = write_bytes(Format::Triangle, &full_mesh(), &WriteOptions::default()).unwrap();
    assert!(String::from_utf8_lossy(&w.main).starts_with("6 2 1 1\n"));
    assert!(!w.siblings.is_empty());
    // write_path refuses stdout for a set of files, saying why.
    let e = smartmesh_formats::write_path(
        std::path::Path::new("-"),
        &full_mesh(),
        Some(Format::Triangle),
        &WriteOptions::default(),
    )
    .unwrap_err();
    assert!(e.to_string().contains("sibling files"), "{e}");
}

#[test]
fn unknown_main_extension_is_refused() {
    let e = write_bytes(Format::Triangle, &full_mesh(), &opts("out.txt")).unwrap_err();
    assert!(matches!(e.kind, ErrorKind::CannotWrite { .. }), "{e}");
}

#[test]
fn voronoi_rays_round_trip_through_edge() {
    smartmesh_test_support::require_public_fixtures!();
    let m = read_file("triangle/dots.1.v.edge");
    let (w, back) = roundtrip(Format::Triangle, "edge", &m, &opts("dots.edge"));
    assert!(w.report.dropped.is_empty(), "{:?}", w.report.dropped);
    assert_eq!(back, m);
    // As a .node set the rays cannot be kept, and the report says so.
    let w = write_bytes(Format::Triangle, &m, &opts("dots.node")).unwrap();
    assert!(
        w.report.dropped.iter().any(|d| d.contains("11 vertex cells")),
        "{:?}",
        w.report.dropped
    );
}

#[test]
fn edges_as_main_file() {
    let mut m = full_mesh();
    m.holes.clear();
    m.regions.clear();
    let (w, back) = roundtrip(Format::Triangle, "edge", &m, &opts("x.edge"));
    assert!(w.report.dropped.is_empty(), "{:?}", w.report.dropped);
    assert_eq!(back, m);
    let w = write_bytes(Format::Triangle, &full_mesh(), &opts("x.edge")).unwrap();
    assert!(
        w.report.dropped.iter().any(|d| d.contains("1 holes and 2 regions")),
        "{:?}",
        w.report.dropped
    );
}

#[test]
fn second_order_triangles_round_trip() {
    let mut m = TaggedMesh::new();
    m.points = (0..6).map(|i| [i as f64, (i * i) as f64, 0.0]).collect();
    m.blocks.push(CellBlock {
        kind: CellKind::Triangle6,
        nodes: vec![0, 1, 2, 3, 4, 5],
        physical: vec![3],
        geometrical: vec![3],
    });
    let (w, back) = roundtrip(Format::Triangle, "ele", &m, &opts("p2.ele"));
    // Triangle's order: the 4th node lies opposite the 1st corner (our edge 2-3 node).
    assert!(
        String::from_utf8_lossy(&w.main).contains("\n1 1 2 3 5 6 4 3\n"),
        "{}",
        String::from_utf8_lossy(&w.main)
    );
    assert_eq!(back.blocks, m.blocks);
}

#[test]
fn what_triangle_cannot_hold_is_reported() {
    let mut m = full_mesh();
    m.points[0][2] = 1.0;
    m.blocks.push(CellBlock {
        kind: CellKind::Quad,
        nodes: vec![0, 1, 2, 3],
        physical: vec![1],
        geometrical: vec![2],
    });
    m.blocks[1].geometrical[0] = 99;
    m.point_data.insert("metric".into(), DataArray::new(9, vec![1.0; 54]));
    m.cell_data.insert("quality".into(), DataArray::new(1, vec![1.0; 9]));
    for v in m.cell_data.values_mut() {
        v.values.push(0.0);
    }
    m.cell_data.get_mut("quality").unwrap().values.pop();
    m.tag_names.insert((2, 7), "Fluid".into());
    m.point_sets.insert("Corners".into(), vec![0]);
    let w = write_bytes(Format::Triangle, &m, &opts("x.node")).unwrap();
    let d = w.report.dropped.join("\n");
    for needle in [
        "z coordinates of 1 points",
        "1 quad cells: written as 2 triangles",
        "point data `metric` (9 components)",
        "cell data `quality`",
        "1 tag names",
        "point set `Corners`",
        // The triangle of tag 99 and the two halves of the quad (geometrical tag 2).
        "geometrical tags of 3 triangles",
    ] {
        assert!(d.contains(needle), "missing `{needle}` in:\n{d}");
    }
}

#[test]
fn same_mesh_same_bytes() {
    let a = write_bytes(Format::Triangle, &full_mesh(), &opts("a.node")).unwrap();
    let b = write_bytes(Format::Triangle, &full_mesh(), &opts("a.node")).unwrap();
    assert_eq!(a.main, b.main);
    assert_eq!(a.siblings, b.siblings);
}

/// Features Triangle cannot hold turned off: quads, vertex cells, distinct geometrical
/// tags, names, point fields.
const TRIANGLE_FEATURES: MeshFeatures = MeshFeatures {
    quads: false,
    lines: true,
    vertices: false,
    geometrical: false,
    names: false,
    point_scalar: false,
    point_tensor: false,
    negative_tags: true,
};

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]
    #[test]
    fn prop_write_read_identity(m in arb_tagged_mesh(TRIANGLE_FEATURES), main in prop::sample::select(vec!["p.node", "p.ele", "p.poly"])) {
        let ext = main.rsplit_once('.').unwrap().1;
        let (w, mut back) = roundtrip(Format::Triangle, ext, &m, &opts(main));
        prop_assert!(w.report.dropped.is_empty(), "{:?}", w.report.dropped);
        // The tags come back as the first triangle attribute too (0 on lines); when every
        // triangle tag is 0, no attribute is written.
        let expected: Vec<f64> = m.cells().map(|(k, _, p, _)| if k == CellKind::Triangle { p as f64 } else { 0.0 }).collect();
        match back.cell_data.remove("triangle:attribute1") {
            Some(attr) => prop_assert_eq!(attr.values, expected),
            None => prop_assert!(expected.iter().all(|&v| v == 0.0)),
        }
        // Holes and regions the mesh lacks are derived from its triangles for the .poly
        // (`holes_and_regions_are_derived_for_the_poly_beside_an_ele` checks them).
        if m.holes.is_empty() && m.regions.is_empty() {
            back.holes.clear();
            back.regions.clear();
        }
        prop_assert_eq!(&back, &m);
        for (a, b) in back.points.iter().zip(&m.points) {
            prop_assert_eq!(a.map(f64::to_bits), b.map(f64::to_bits));
        }
    }
}

// -----------------------------------------------------------------------------------------
// Malformed input: every error names its line and what was expected.
// -----------------------------------------------------------------------------------------

fn err(main_ext: &str, main: &str, siblings: &[(&str, &str)]) -> smartmesh_formats::Error {
    read_mem(main_ext, main, siblings).expect_err("should fail")
}

const NODE: &str = "4 2 0 1\n1 0 0 1\n2 1 0 1\n3 1 1 1\n4 0 1 1\n";

#[test]
fn malformed_truncated_node() {
    let e = err("node", "3 2 0 0\n1 0.0 0.0\n2 1.0 0.0\n", &[]);
    assert!(matches!(e.kind, ErrorKind::UnexpectedEof { .. }), "{e}");
    assert_eq!(e.to_string(), "<stdin>:4: unexpected end of file: expected vertex 3 of 3");
}

#[test]
fn malformed_missing_coordinate() {
    let e = err("node", "2 2 0 0\n1 0 0\n2 1\n", &[]);
    assert_eq!(e.to_string(), "<stdin>:3: expected y coordinate of vertex 2, found end of line");
}

#[test]
fn malformed_nan_coordinate() {
    let e = err("node", "2 2 0 0\n1 0 0\n2 nan 0\n", &[]);
    assert!(matches!(e.kind, ErrorKind::NonFinite { .. }), "{e}");
    assert!(e.to_string().starts_with("<stdin>:3:"), "{e}");
}

#[test]
fn malformed_huge_count() {
    let e = err("node", "1000000000000 2 0 0\n1 0 0\n", &[]);
    assert!(matches!(e.kind, ErrorKind::ImplausibleCount { .. }), "{e}");
    let e = err("node", "2 2 4000000000000 0\n1 0 0\n2 0 0\n", &[]);
    assert!(matches!(e.kind, ErrorKind::ImplausibleCount { .. }), "{e}");
    let e = err("ele", "99999999999 3 0\n1 1 2 3\n", &[("node", NODE)]);
    assert!(matches!(e.kind, ErrorKind::ImplausibleCount { .. }), "{e}");
}

#[test]
fn malformed_negative_count() {
    let e = err("node", "-3 2 0 0\n", &[]);
    assert!(e.to_string().contains("non-negative"), "{e}");
}

#[test]
fn malformed_wrong_dimension() {
    let e = err("node", "1 4 0 0\n1 0 0 0 0\n", &[]);
    assert!(e.to_string().contains("dimension 2"), "{e}");
    // A 3D .node is TetGen's (see `tetgen`), read as such.
    let m = read_mem("node", "1 3 0 0\n1 0 0 0.5\n", &[]).unwrap();
    assert_eq!((m.coordinate_dim, m.points[0][2]), (3, 0.5));
}

#[test]
fn malformed_first_number() {
    let e = err("node", "1 2 0 0\n7 0 0\n", &[]);
    assert!(e.to_string().contains("0 or 1 as the number of the first vertex"), "{e}");
}

#[test]
fn malformed_not_a_number() {
    let e = err("node", "1 2 0 0\n1 0 zero\n", &[]);
    assert_eq!(e.to_string(), "<stdin>:2: expected y coordinate of vertex 1, found `zero`");
    let e = err("ele", "1 3 0\n1 1 2 x\n", &[("node", NODE)]);
    assert!(e.to_string().contains("expected vertex (an integer) of triangle 1, found `x`"), "{e}");
}

#[test]
fn malformed_index_out_of_range() {
    let e = err("ele", "1 3 0\n1 1 2 5\n", &[("node", NODE)]);
    assert!(matches!(e.kind, ErrorKind::IndexOutOfRange { index: 5, available: 4, .. }), "{e}");
    assert!(e.to_string().starts_with("<stdin>:2:"), "{e}");
    // 0 is out of range in a 1-based set.
    let e = err("ele", "1 3 0\n1 0 1 2\n", &[("node", NODE)]);
    assert!(matches!(e.kind, ErrorKind::IndexOutOfRange { index: 0, .. }), "{e}");
    let e = err("poly", "0 2 0 1\n1 1\n1 1 9 3\n0\n", &[("node", NODE)]);
    assert!(matches!(e.kind, ErrorKind::IndexOutOfRange { index: 9, .. }), "{e}");
}

#[test]
fn malformed_error_in_sibling_names_it() {
    let e = err("ele", "1 3 0\n1 1 2 3\n", &[("node", "4 2 0 0\n1 0 0\n2 1 0\n3 1 1\n4 0\n")]);
    assert_eq!(
        e.to_string(),
        "<memory>.node:5: expected y coordinate of vertex 4, found end of line"
    );
}

#[test]
fn malformed_missing_node_file() {
    let e = err("ele", "1 3 0\n1 1 2 3\n", &[]);
    assert!(e.to_string().contains("<memory>.node, which does not exist"), "{e}");
    let e = err("poly", "0 2 0 0\n0 0\n0\n", &[]);
    assert!(e.to_string().contains("lists 0 vertices"), "{e}");
}

#[test]
fn malformed_unsupported_triangle_order() {
    let e = err("ele", "1 4 0\n1 1 2 3 4\n", &[("node", NODE)]);
    assert!(matches!(e.kind, ErrorKind::Unsupported(_)), "{e}");
}

#[test]
fn malformed_area_count_disagrees() {
    let e = err("area", "2\n1 0.5\n2 0.5\n", &[("node", NODE), ("ele", "1 3 0\n1 1 2 3\n")]);
    assert!(matches!(e.kind, ErrorKind::Inconsistent(_)), "{e}");
    let e = err("area", "1\n1 0.5\n", &[("node", NODE)]);
    assert!(e.to_string().contains(".ele, which does not exist"), "{e}");
}

#[test]
fn malformed_poly_and_node_disagree() {
    let e = err("poly", "1 2 0 0\n1 5 5\n0 0\n0\n", &[("node", NODE)]);
    assert!(e.to_string().contains("differ"), "{e}");
}

#[test]
fn malformed_poly_without_holes_section() {
    let e = err("poly", "2 2 0 0\n1 0 0\n2 1 0\n1 0\n1 1 2\n", &[]);
    assert!(e.to_string().contains("expected the number of holes"), "{e}");
}

#[test]
fn malformed_bad_marker() {
    let e = err("node", "1 2 0 1\n1 0 0 99999999999\n", &[]);
    assert!(e.to_string().contains("32-bit"), "{e}");
    let e = err("node", "1 2 0 2\n1 0 0 1\n", &[]);
    assert!(e.to_string().contains("0 or 1 boundary markers"), "{e}");
}

#[test]
fn malformed_empty_file() {
    let e = err("node", "# nothing\n\n", &[]);
    assert!(matches!(e.kind, ErrorKind::UnexpectedEof { .. }), "{e}");
}

#[test]
fn comments_blank_lines_and_zero_based_numbering() {
    let m = read_mem(
        "ele",
        "# triangles\n\n2 3 1 # header\n0 0 1 2 5\n\n1 0 2 3 2.5 # second\n",
        &[("node", "4 2 0 0\n# zero-based\n0 0 0\n1 1 0\n2 1 1\n3 0 1\n")],
    )
    .unwrap();
    assert_eq!(m.blocks[0].nodes, vec![0, 1, 2, 0, 2, 3]);
    // 2.5 is not an integer, so the attribute is not a tag.
    assert_eq!(m.blocks[0].physical, vec![0, 0]);
    assert_eq!(m.cell_data["triangle:attribute1"].values, vec![5.0, 2.5]);
}

#[test]
fn malformed_error_after_fast_records() {
    // The first records go through the fast path; the error still names its own line.
    let node = "5 2 0 0\n1 0 0\n2 1 0\n3 1 1\n4 0 1\n5 0.5 0.5\n";
    let e = err("ele", "4 3 0\n1 1 2 5\n2 2 3 5\n3 3 4 5\n4 4 1 9\n", &[("node", node)]);
    assert!(matches!(e.kind, ErrorKind::IndexOutOfRange { index: 9, .. }), "{e}");
    assert_eq!(e.to_string().split(':').nth(1), Some("5"), "{e}");
    let e = err("node", "4 2 0 0\n1 0 0\n2 1 0\n\n# gap\n3 1 1\n4 0 inf\n", &[]);
    assert!(matches!(e.kind, ErrorKind::NonFinite { .. }), "{e}");
    assert!(e.to_string().starts_with("<stdin>:7:"), "{e}");
}

#[test]
fn records_mixing_fast_and_general_paths() {
    // Comments, missing optional fields and extra fields in the middle of a block.
    let m =
        read_mem("node", "6 2 1 1\n1 0 0 0.5 1\n2 1 0 0.5 1 # c\n3 1 1\n# comment line\n4 0 1 2.5 4 extra\n5 2 2 1 5\n6 3 3 1 6\n", &[])
            .unwrap();
    assert_eq!(m.points[5], [3.0, 3.0, 0.0]);
    assert_eq!(m.point_data["triangle:attribute1"].values, vec![0.5, 0.5, 0.0, 2.5, 1.0, 1.0]);
    assert_eq!(m.point_data["triangle:marker"].values, vec![1.0, 1.0, 0.0, 4.0, 5.0, 6.0]);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]
    /// Whatever the bytes, the reader returns a value or an error: no panic, no abort.
    #[test]
    fn prop_no_panic_on_damaged_files(edits in prop::collection::vec((any::<prop::sample::Index>(), any::<u8>()), 1..8), cut in any::<prop::sample::Index>(), which in 0usize..4) {
        let w = write_bytes(Format::Triangle, &full_mesh(), &opts("d.node")).unwrap();
        let mut files: BTreeMap<String, Vec<u8>> = w.siblings.into_iter().collect();
        files.insert("node".into(), w.main);
        let ext = ["node", "ele", "poly", "area"][which];
        let bytes = files.get_mut(ext).unwrap();
        for (at, byte) in edits {
            let i = at.index(bytes.len());
            bytes[i] = byte;
        }
        let keep = cut.index(bytes.len() + 1);
        bytes.truncate(keep);
        let main = files.remove(ext).unwrap();
        let sib = MemorySiblings { files };
        let _ = read_bytes(Format::Triangle, &main, &ReadContext { siblings: &sib, extension: ext.into() });
        let _ = read_bytes(Format::Triangle, &main, &ReadContext { siblings: &NoSiblings, extension: String::new() });
    }
}

#[test]
fn a_two_million_digit_coordinate_gives_a_short_error() {
    let huge = format!("1{}", "0".repeat(2_000_000));
    let e = err("node", &format!("1 2 0 0\n1 {huge} 0\n"), &[]);
    assert!(matches!(e.kind, ErrorKind::NonFinite { .. }), "{e}");
    assert!(e.to_string().len() < 200, "{} bytes of message", e.to_string().len());
    assert!(e.to_string().contains("…"), "{e}");
}

#[test]
fn a_cr_only_set_reads_as_its_lines() {
    let node = "# square\r4 2 0 1\r1 0 0 1\r2 1 0 1\r3 1 1 1\r4 0 1 1\r";
    let ele = "2 3 0\r1 1 2 3\r2 1 3 4\r";
    let m = read_mem("ele", ele, &[("node", node)]).unwrap();
    assert_eq!(m.points.len(), 4);
    assert_eq!(m.num_cells_of(CellKind::Triangle), 2);
}

#[test]
fn a_vertex_number_below_the_first_says_how_the_set_counts() {
    let e = err("ele", "1 3 0\n1 0 2 3\n", &[("node", NODE)]);
    let s = e.to_string();
    assert!(s.contains("numbered from 1") && s.contains("refers to 0"), "{s}");
}

/// Whether `p` is inside (or on) triangle `t` of `m`.
fn in_triangle(m: &TaggedMesh, t: &[u32], p: [f64; 2]) -> bool {
    let q = |k: usize| m.points[t[k] as usize];
    let side =
        |a: [f64; 3], b: [f64; 3]| (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0]);
    let s = [side(q(0), q(1)), side(q(1), q(2)), side(q(2), q(0))];
    s.iter().all(|&v| v >= 0.0) || s.iter().all(|&v| v <= 0.0)
}

#[test]
fn holes_and_regions_are_derived_for_the_poly_beside_an_ele() {
    // The bundled channel with a cylinder (Gmsh): no holes nor regions of its own.
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../fixtures/cylinder.msh");
    let mut m = smartmesh_formats::read_path(&path, None).unwrap();
    m.blocks.retain(|b| matches!(b.kind, CellKind::Line | CellKind::Triangle));
    assert!(m.holes.is_empty() && m.regions.is_empty());
    let w = write_bytes(Format::Triangle, &m, &opts("cyl.ele")).unwrap();
    let sib = MemorySiblings::from_written(&w);
    let back = read_bytes(
        Format::Triangle,
        &w.main,
        &ReadContext { siblings: &sib, extension: "ele".into() },
    )
    .unwrap();
    let tris: Vec<&[u32]> = m.cells().filter(|c| c.0 == CellKind::Triangle).map(|c| c.1).collect();
    // The cylinder's inside is a hole: one point in no triangle, within the cylinder's
    // bounding box; the outer loop's point is outside the channel.
    let inside: Vec<_> = back
        .holes
        .iter()
        .filter(|h| (0.8..1.2).contains(&h[0]) && (0.3..0.7).contains(&h[1]))
        .collect();
    assert_eq!(inside.len(), 1, "{:?}", back.holes);
    for h in &back.holes {
        assert!(!tris.iter().any(|t| in_triangle(&m, t, *h)), "hole {h:?} in a triangle");
    }
    // One region, the fluid (tag 10), seeded inside a triangle.
    assert_eq!(back.regions.len(), 1, "{:?}", back.regions);
    assert_eq!(back.regions[0].attribute, 10.0);
    assert!(tris.iter().any(|t| in_triangle(&m, t, back.regions[0].point)));
    // A mesh that has holes and regions of its own keeps them.
    let (_, again) = roundtrip(Format::Triangle, "ele", &full_mesh(), &opts("x.ele"));
    assert_eq!(again.holes, full_mesh().holes);
}
