//! Gmsh MSH with volume meshes: the public 3D fixtures written by Gmsh 4.15.2 read with
//! the counts, tags and names they declare and the volumes their geometry gives; they
//! and a mesh of one element of every 3D kind round trip through the four encodings
//! with their points, cells, tags, names, entities and data; the written `$Entities`
//! boxes are those read where they hold the nodes, else the nodes'; malformed and extreme 3D input is refused with its
//! position.

mod gmsh3d_support;

use std::collections::BTreeMap;

use gmsh3d_support as s3;
use smartmesh_formats::{
    gmsh, CellKind, DataArray, ErrorKind, Format, GmshVersion, GmshWrite, Position, ReadContext,
    TaggedMesh, WriteOptions,
};
use smartmesh_test_support::formats as common;

const ENCODINGS: [&str; 4] = ["v22_ascii", "v22_binary", "v41_ascii", "v41_binary"];

fn read_msh(bytes: &[u8]) -> smartmesh_formats::Result<TaggedMesh> {
    gmsh::read(bytes, &ReadContext::alone("msh"))
}

fn opts(version: GmshVersion, binary: bool) -> WriteOptions {
    WriteOptions { gmsh: GmshWrite { version, binary }, ..WriteOptions::default() }
}

const ALL: [(GmshVersion, bool); 4] = [
    (GmshVersion::V22, false),
    (GmshVersion::V22, true),
    (GmshVersion::V41, false),
    (GmshVersion::V41, true),
];

fn cell_list(m: &TaggedMesh) -> Vec<(CellKind, Vec<u32>, i32, i32)> {
    m.cells().map(|(k, n, p, g)| (k, n.to_vec(), p, g)).collect()
}

fn counts(list: &[(&str, i32, usize)]) -> BTreeMap<(String, i32), usize> {
    list.iter().map(|&(k, p, n)| ((k.to_string(), p), n)).collect()
}

fn names(list: &[(u8, i32, &str)]) -> BTreeMap<(u8, i32), String> {
    list.iter().map(|&(d, t, n)| ((d, t), n.to_string())).collect()
}

/// Points bit for bit, cells, names and data (NaN equal to NaN): everything but
/// `entities`, which only 4.1 files fill.
fn assert_same_mesh(a: &TaggedMesh, b: &TaggedMesh, what: &str) {
    assert_eq!(a.points.len(), b.points.len(), "{what}: points");
    for (i, (p, q)) in a.points.iter().zip(&b.points).enumerate() {
        assert!(p.iter().zip(q).all(|(x, y)| x.to_bits() == y.to_bits()), "{what}: point {i}");
    }
    assert_eq!(a.coordinate_dim, b.coordinate_dim, "{what}: coordinate_dim");
    assert!(cell_list(a) == cell_list(b), "{what}: cells differ");
    assert_eq!(a.tag_names, b.tag_names, "{what}: names");
    for (x, y, kind) in
        [(&a.point_data, &b.point_data, "point"), (&a.cell_data, &b.cell_data, "cell")]
    {
        assert_eq!(x.keys().collect::<Vec<_>>(), y.keys().collect::<Vec<_>>(), "{what}: {kind}");
        for (name, u) in x {
            let v = &y[name];
            assert_eq!(u.components, v.components, "{what}: {kind} `{name}`");
            let same = u
                .values
                .iter()
                .zip(&v.values)
                .all(|(s, t)| s.to_bits() == t.to_bits() || (s.is_nan() && t.is_nan()));
            assert!(same && u.values.len() == v.values.len(), "{what}: {kind} data `{name}`");
        }
    }
}

struct Expected {
    file: &'static str,
    nodes: usize,
    /// The `$Entities` header of the 4.1 file, summed.
    entities_41: usize,
    counts: BTreeMap<(String, i32), usize>,
    names: BTreeMap<(u8, i32), String>,
}

/// What `3d/MANIFEST` (the fixtures' description) declares: counts per kind and
/// physical tag, node counts and names; entity counts are the `$Entities` headers
/// (`18 24 10 1` for box_cyl, `16 28 16 3` for hex_prism_pyr).
fn expected() -> Vec<Expected> {
    let box_names = names(&[
        (1, 20, "CylinderEdges"),
        (2, 1, "Inlet"),
        (2, 2, "Outlet"),
        (2, 3, "Walls"),
        (2, 4, "Cylinder"),
        (3, 10, "Fluid"),
    ]);
    let box_counts = |tet: &'static str, tri: &'static str, line: &'static str| {
        counts(&[
            (line, 20, 16),
            (tri, 1, 90),
            (tri, 2, 90),
            (tri, 3, 714),
            (tri, 4, 118),
            (tet, 10, 2187),
        ])
    };
    let mut out: Vec<Expected> = ENCODINGS
        .iter()
        .map(|enc| Expected {
            file: Box::leak(format!("box_cyl.{enc}.msh").into_boxed_str()),
            nodes: 634,
            entities_41: 18 + 24 + 10 + 1,
            counts: box_counts("tetra", "triangle", "line"),
            names: box_names.clone(),
        })
        .collect();
    out.push(Expected {
        file: "box_cyl_o2.v41_ascii.msh",
        nodes: 3961,
        entities_41: 18 + 24 + 10 + 1,
        counts: box_counts("tetra10", "triangle6", "line3"),
        names: box_names.clone(),
    });
    for enc in ["v22_ascii", "v41_ascii"] {
        out.push(Expected {
            file: Box::leak(format!("hex_prism_pyr.{enc}.msh").into_boxed_str()),
            nodes: 161,
            entities_41: 16 + 28 + 16 + 3,
            counts: counts(&[
                ("hexa", 1, 27),
                ("wedge", 2, 54),
                ("tetra", 3, 152),
                ("pyramid", 3, 9),
                ("quad", 11, 9),
                ("triangle", 11, 18),
                ("triangle", 12, 44),
                ("quad", 13, 54),
                ("triangle", 13, 64),
                ("quad", 14, 18),
            ]),
            names: names(&[
                (2, 11, "Bottom"),
                (2, 12, "Top"),
                (2, 13, "Sides"),
                (2, 14, "Interface"),
                (3, 1, "Hexa"),
                (3, 2, "Prisms"),
                (3, 3, "TetPyr"),
            ]),
        });
    }
    out
}

fn fixture(file: &str) -> TaggedMesh {
    common::read_file(&format!("3d/{file}"))
}

#[test]
fn fixtures_3d_read_with_the_counts_tags_and_names_they_declare() {
    smartmesh_test_support::require_public_fixtures!();
    for e in expected() {
        let m = fixture(e.file);
        let what = e.file;
        assert_eq!(m.points.len(), e.nodes, "{what}: nodes");
        assert_eq!(common::counts_per_tag(&m), e.counts, "{what}: counts per tag");
        assert_eq!(m.tag_names, e.names, "{what}: names");
        assert_eq!(m.coordinate_dim, 3, "{what}");
        if what.contains("v41") {
            assert_eq!(m.entities.len(), e.entities_41, "{what}: entities");
            let volumes = m.entities.keys().filter(|k| k.0 == 3).count();
            assert_eq!(volumes, if what.starts_with("box") { 1 } else { 3 }, "{what}");
            for (k, _, p, g) in m.cells() {
                assert_eq!(m.entities[&(k.dim(), g)].first().copied().unwrap_or(0), p, "{what}");
            }
        } else {
            assert!(m.entities.is_empty(), "{what}: no entity in two groups");
        }
    }
}

/// Sum of the corner volumes of the volume cells of each physical tag; every one must
/// be positive (Gmsh's orientation, read in Gmsh's node order).
fn volumes_per_tag(m: &TaggedMesh, what: &str) -> BTreeMap<i32, f64> {
    let mut out = BTreeMap::new();
    for (k, cell, p, _) in m.cells().filter(|c| c.0.dim() == 3) {
        let v = s3::corner_volume(k, &s3::points_of(m, cell));
        assert!(v > 0.0, "{what}: a {} of volume {v}", k.name());
        *out.entry(p).or_insert(0.0) += v;
    }
    out
}

#[test]
fn fixtures_3d_have_the_volumes_of_their_geometry() {
    smartmesh_test_support::require_public_fixtures!();
    // hex_prism_pyr: three boxes with plane faces, 1 × 1 × 1, 1 × 1 × 1 and 1 × 1 × 0.6.
    for enc in ["v22_ascii", "v41_ascii"] {
        let m = fixture(&format!("hex_prism_pyr.{enc}.msh"));
        let v = volumes_per_tag(&m, enc);
        for (tag, want) in [(1, 1.0), (2, 1.0), (3, 0.6)] {
            assert!((v[&tag] - want).abs() < 1e-12, "{enc}: volume {tag} = {}", v[&tag]);
        }
    }
    // box_cyl: the box minus a polyhedral hole whose vertices lie on the cylinder of
    // radius 0.2 (height 1): the hole is inside the cylinder and holds the prism on the
    // regular octagon of the 8 points of each end circle (16 CylinderEdges lines), so
    // 2 − π 0.2² ≤ V ≤ 2 − 2√2 0.2².
    let (lo, hi) = (2.0 - std::f64::consts::PI * 0.04, 2.0 - 2.0 * 2f64.sqrt() * 0.04);
    let mut totals = Vec::new();
    for file in ["box_cyl.v41_ascii.msh", "box_cyl.v22_binary.msh", "box_cyl_o2.v41_ascii.msh"] {
        let m = fixture(file);
        let v = volumes_per_tag(&m, file)[&10];
        assert!(lo <= v && v <= hi, "{file}: volume {v} outside [{lo}, {hi}]");
        totals.push(v);
    }
    // The order-2 mesh is the same mesh: the same corners, the same volume.
    assert!((totals[0] - totals[2]).abs() < 1e-12, "{totals:?}");
    // Its high-order nodes on the cylinder lie on r = 0.2.
    let m = fixture("box_cyl_o2.v41_ascii.msh");
    let mut on = 0;
    for (k, cell, p, _) in m.cells() {
        if k == CellKind::Triangle6 && p == 4 {
            for &v in cell {
                let q = m.points[v as usize];
                let r = ((q[0] - 0.6).powi(2) + (q[1] - 0.5).powi(2)).sqrt();
                assert!((r - 0.2).abs() < 1e-9, "node {v} at r = {r}");
                on += 1;
            }
        }
    }
    assert_eq!(on, 118 * 6);
}

#[test]
fn the_four_encodings_of_box_cyl_read_the_same() {
    smartmesh_test_support::require_public_fixtures!();
    let meshes: Vec<TaggedMesh> =
        ENCODINGS.iter().map(|enc| fixture(&format!("box_cyl.{enc}.msh"))).collect();
    let a = &meshes[0];
    for (enc, b) in ENCODINGS.iter().zip(&meshes) {
        // Gmsh writes ASCII coordinates to 16 digits (MANIFEST: they agree to 4e-16).
        for (p, q) in a.points.iter().zip(&b.points) {
            assert!(p.iter().zip(q).all(|(x, y)| (x - y).abs() <= 4e-16 * 2.0), "{enc}");
        }
        let (mut ca, mut cb) = (cell_list(a), cell_list(b));
        ca.sort();
        cb.sort();
        assert!(ca == cb, "{enc}: cells differ");
        assert_eq!(a.tag_names, b.tag_names, "{enc}");
    }
    assert_eq!(meshes[2].entities, meshes[3].entities);
}

/// `m` with point data (a scalar, a vector and a tensor) and cell data (a scalar, NaN
/// on one cell), as `$NodeData` and `$ElementData` carry them.
fn with_data(mut m: TaggedMesh) -> TaggedMesh {
    let f: Vec<f64> = m.points.iter().map(|p| p[0] + 2.0 * p[1] + 3.0 * p[2]).collect();
    let v: Vec<f64> = m.points.iter().flat_map(|p| [p[1], -p[0], 0.5 * p[2]]).collect();
    let t: Vec<f64> = m
        .points
        .iter()
        .flat_map(|p| [1.0 + p[0], 0.1, 0.2, 0.1, 2.0 + p[1], 0.3, 0.2, 0.3, 3.0 + p[2]])
        .collect();
    m.point_data.insert("f".into(), DataArray::new(1, f));
    m.point_data.insert("v".into(), DataArray::new(3, v));
    m.point_data.insert("metric".into(), DataArray::new(9, t));
    let mut c: Vec<f64> = (0..m.num_cells()).map(|i| i as f64 * 0.5).collect();
    c[1] = f64::NAN;
    m.cell_data.insert("cell_id".into(), DataArray::new(1, c));
    m
}

#[test]
fn fixtures_3d_with_data_round_trip_through_every_encoding() {
    smartmesh_test_support::require_public_fixtures!();
    for file in
        ["box_cyl.v41_binary.msh", "box_cyl_o2.v41_ascii.msh", "hex_prism_pyr.v41_ascii.msh"]
    {
        let src = with_data(fixture(file));
        for (v, bin) in ALL {
            let what = format!("{file} as {v:?} binary={bin}");
            let (w, back) = common::roundtrip(Format::Gmsh, "msh", &src, &opts(v, bin));
            assert_same_mesh(&src, &back, &what);
            if v == GmshVersion::V41 {
                assert_eq!(back.entities, src.entities, "{what}: entities");
            }
            // The NaN left out, and for 2.2 the entities without cells: nothing else.
            for d in &w.report.dropped {
                assert!(d.contains("NaN") || d.contains("no entity table"), "{what}: {d}");
            }
            // Same mesh, same bytes; write → read → write a fixed point.
            assert!(gmsh::write(&src, &opts(v, bin)).unwrap().main == w.main, "{what}");
            assert!(gmsh::write(&back, &opts(v, bin)).unwrap().main == w.main, "{what}");
        }
    }
}

#[test]
fn one_element_of_every_3d_kind_round_trips_through_every_encoding() {
    let (m, maps) = s3::every_kind();
    let m = with_data(m);
    // The test's own mesh first: each cell the affine image of its reference element,
    // of the volume its map gives.
    for ((k, cell, _, _), map) in m.cells().zip(&maps) {
        if k.dim() == 3 {
            let v = s3::corner_volume(k, &s3::points_of(&m, cell));
            let want = map.det() * s3::reference_measure(k);
            assert!((v - want).abs() < 1e-12 * want, "{}: {v} vs {want}", k.name());
        }
    }
    for (v, bin) in ALL {
        let what = format!("{v:?} binary={bin}");
        let (w, back) = common::roundtrip(Format::Gmsh, "msh", &m, &opts(v, bin));
        assert_same_mesh(&m, &back, &what);
        assert_eq!(w.report.dropped.len(), 1, "{what}: only the NaN: {:?}", w.report.dropped);
        assert_eq!(read_msh(&w.main).unwrap().num_cells_of(CellKind::Pyramid14), 1);
    }
}

/// The boxes of a 4.1 ASCII file's `$Entities`: `(dim, tag)` → its six numbers (three
/// for points).
fn entity_boxes(text: &str) -> BTreeMap<(u8, i32), Vec<f64>> {
    let sec = &text[text.find("$Entities\n").unwrap() + 10..text.find("$EndEntities").unwrap()];
    let mut lines = sec.lines();
    let counts: Vec<usize> =
        lines.next().unwrap().split_whitespace().map(|t| t.parse().unwrap()).collect();
    let mut out = BTreeMap::new();
    for (d, &n) in counts.iter().enumerate() {
        for _ in 0..n {
            let w: Vec<&str> = lines.next().unwrap().split_whitespace().collect();
            let k = if d == 0 { 3 } else { 6 };
            let b = w[1..1 + k].iter().map(|t| t.parse().unwrap()).collect();
            out.insert((d as u8, w[0].parse().unwrap()), b);
        }
    }
    out
}

#[test]
fn written_entities_have_their_given_box_or_that_of_their_nodes() {
    smartmesh_test_support::require_public_fixtures!();
    let (every, _) = s3::every_kind();
    for m in [every, fixture("hex_prism_pyr.v41_ascii.msh"), fixture("box_cyl.v22_ascii.msh")] {
        let w = gmsh::write(&m, &opts(GmshVersion::V41, false)).unwrap();
        let boxes = entity_boxes(std::str::from_utf8(&w.main).unwrap());
        // The box of the nodes of each entity's cells, computed here.
        let mut want: BTreeMap<(u8, i32), [f64; 6]> = BTreeMap::new();
        for (k, cell, _, g) in m.cells() {
            let b = want.entry((k.dim(), g)).or_insert([
                f64::INFINITY,
                f64::INFINITY,
                f64::INFINITY,
                f64::NEG_INFINITY,
                f64::NEG_INFINITY,
                f64::NEG_INFINITY,
            ]);
            for &v in cell {
                for c in 0..3 {
                    b[c] = b[c].min(m.points[v as usize][c]);
                    b[c + 3] = b[c + 3].max(m.points[v as usize][c]);
                }
            }
        }
        let mut volumes = 0;
        for (key, b) in &want {
            if key.0 > 0 {
                // The box read with the mesh where it holds the nodes (Gmsh's model box).
                let holds = |g: &[f64; 6]| (0..3).all(|c| g[c] <= b[c] && b[c + 3] <= g[c + 3]);
                let b = match m.entity_boxes.get(key) {
                    Some(g) if holds(g) => g,
                    _ => b,
                };
                assert_eq!(boxes[key], b.to_vec(), "entity {key:?}");
                volumes += (key.0 == 3) as usize;
            }
        }
        assert!(volumes >= 1);
        // What the reader checks in a box, it accepts in ours.
        read_msh(&w.main).unwrap();
    }
}

/// Gmsh's `$Entities` boxes (its model's, with every point, curve, surface and volume)
/// round trip as read through 4.1 ASCII and binary; once the nodes leave them (the mesh
/// moved), the boxes written are the nodes'; an entity without nodes keeps its box.
#[test]
fn entity_boxes_round_trip_as_read_where_the_nodes_allow() {
    smartmesh_test_support::require_public_fixtures!();
    for file in ["box_cyl.v41_ascii.msh", "box_cyl.v41_binary.msh", "hex_prism_pyr.v41_ascii.msh"] {
        let m = fixture(file);
        let text = std::fs::read_to_string(common::public_fixtures().join("3d").join(file));
        if let Ok(text) = text {
            // The reader keeps the file's numbers (a point's coordinates twice).
            for (key, b) in entity_boxes(&text) {
                let got = m.entity_boxes[&key];
                let want: Vec<f64> = if key.0 == 0 { [&b[..], &b[..]].concat() } else { b };
                assert_eq!(got.to_vec(), want, "{file}: entity {key:?} as read");
            }
        }
        assert!(m.entity_boxes.len() >= 20, "{file}: {} boxes", m.entity_boxes.len());
        for binary in [false, true] {
            let w = gmsh::write(&m, &opts(GmshVersion::V41, binary)).unwrap();
            let back = read_msh(&w.main).unwrap();
            assert_eq!(back.entity_boxes.len(), m.entity_boxes.len());
            // A box is written otherwise only when its nodes stick out of it (Gmsh's
            // box of a circle's quarter ends at 0.4, its node at 0.39999999999999997):
            // the box written is then the nodes', which the given one does not hold.
            let holds =
                |g: &[f64; 6], b: &[f64; 6]| (0..3).all(|c| g[c] <= b[c] && b[c + 3] <= g[c + 3]);
            let mut differ = 0;
            for (k, given) in &m.entity_boxes {
                let written = &back.entity_boxes[k];
                if written != given {
                    assert!(
                        !holds(given, written),
                        "{file}, binary {binary}: {k:?} {given:?} {written:?}"
                    );
                    differ += 1;
                }
            }
            assert!(differ * 10 <= m.entity_boxes.len(), "{file}: {differ} boxes differ");
        }
    }
    // Moved past its boxes, the mesh is written with its nodes' boxes.
    let mut m = fixture("box_cyl.v41_ascii.msh");
    for p in &mut m.points {
        p[0] += 10.0;
    }
    let w = gmsh::write(&m, &opts(GmshVersion::V41, false)).unwrap();
    let back = read_msh(&w.main).unwrap();
    let (lo, hi) = m
        .points
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), p| (l.min(p[0]), h.max(p[0])));
    let volume = back.entity_boxes[&(3, 1)];
    assert_eq!((volume[0], volume[3]), (lo, hi));
    // A point entity without a node (added here) keeps its given point; a curve
    // without cells keeps its box.
    m.entities.insert((0, 999), vec![]);
    m.entity_boxes.insert((0, 999), [1.0, 2.0, 3.0, 1.0, 2.0, 3.0]);
    m.entities.insert((1, 999), vec![]);
    m.entity_boxes.insert((1, 999), [-1.0, -2.0, -3.0, 1.0, 2.0, 3.0]);
    for binary in [false, true] {
        let back =
            read_msh(&gmsh::write(&m, &opts(GmshVersion::V41, binary)).unwrap().main).unwrap();
        assert_eq!(back.entity_boxes[&(0, 999)], [1.0, 2.0, 3.0, 1.0, 2.0, 3.0]);
        assert_eq!(back.entity_boxes[&(1, 999)], [-1.0, -2.0, -3.0, 1.0, 2.0, 3.0]);
    }
}

/// Untagged volume cells beside tagged ones get a 3D group of their own, one above the
/// largest physical volume tag, and read back untagged (the policy of `untagged.rs`, in
/// dimension 3).
#[test]
fn untagged_volume_cells_beside_tagged_ones_get_a_3d_group() {
    let (mut m, _) = s3::every_kind();
    // The hexahedra and the tetrahedra (volume tags 1, 2, 5, 6, 7) lose their group.
    for b in &mut m.blocks {
        if b.kind.linear() == CellKind::Hexa || b.kind.linear() == CellKind::Tetra {
            b.physical.fill(0);
        }
    }
    let top = m.tag_names.keys().filter(|k| k.0 == 3).map(|k| k.1).max().unwrap();
    for (v, bin) in ALL {
        let what = format!("{v:?} binary={bin}");
        let w = gmsh::write(&m, &opts(v, bin)).unwrap();
        let said: Vec<_> =
            w.report.dropped.iter().filter(|l| l.contains("without a physical tag")).collect();
        assert_eq!(said.len(), 1, "{what}: {:?}", w.report.dropped);
        let group =
            format!("5 3D cell(s) without a physical tag written as physical group {}", top + 1);
        assert!(said[0].contains(&group), "{what}: {said:?}");
        if !bin {
            let text = String::from_utf8_lossy(&w.main);
            assert!(text.contains(&format!("3 {} \"smartmesh:untagged\"", top + 1)), "{what}");
        }
        let back = read_msh(&w.main).unwrap();
        let tags = |m: &TaggedMesh| -> Vec<_> {
            cell_list(m).into_iter().map(|(k, n, p, _)| (k, n, p)).collect()
        };
        assert_eq!(tags(&back), tags(&m), "{what}");
        assert_eq!(back.tag_names, m.tag_names, "{what}");
    }
}

// ---------------------------------------------------------------------------------
// Malformed and extreme 3D input: an error with a position, no panic, no huge allocation

const HEAD41: &str = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n";
const HEAD22: &str = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n";
const TET_NODES41: &str =
    "$Nodes\n1 4 1 4\n3 1 0 4\n1\n2\n3\n4\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n$EndNodes\n";
const TET_NODES22: &str = "$Nodes\n4\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n$EndNodes\n";
const VOLUME_ENTITY: &str = "$Entities\n0 0 0 1\n1 0 0 0 1 1 1 1 7 0\n$EndEntities\n";

fn err(bytes: &[u8]) -> smartmesh_formats::Error {
    match read_msh(bytes) {
        Ok(_) => panic!("expected an error"),
        Err(e) => {
            assert!(e.at.is_some(), "error without a position: {e}");
            e
        }
    }
}

fn err_text(s: &str) -> smartmesh_formats::Error {
    err(s.as_bytes())
}

#[test]
fn a_minimal_41_tetrahedron_reads_with_its_physical_volume() {
    let m = read_msh(format!("{HEAD41}{VOLUME_ENTITY}{TET_NODES41}$Elements\n1 1 1 1\n3 1 4 1\n1 1 2 3 4\n$EndElements\n").as_bytes()).unwrap();
    assert_eq!(cell_list(&m), vec![(CellKind::Tetra, vec![0, 1, 2, 3], 7, 1)]);
    assert_eq!(m.entities[&(3, 1)], vec![7]);
}

#[test]
fn malformed_header_announcing_1e15_tetrahedra() {
    let start = std::time::Instant::now();
    let n = "1000000000000000";
    // 4.1: the section header, then a block header.
    let e = err_text(&format!(
        "{HEAD41}{TET_NODES41}$Elements\n1 {n} 1 {n}\n3 1 4 {n}\n1 1 2 3 4\n$EndElements\n"
    ));
    assert!(matches!(e.kind, ErrorKind::ImplausibleCount { .. }), "{e}");
    assert_eq!(e.at, Some(Position::Line(17)), "{e}");
    let e = err_text(&format!(
        "{HEAD41}{TET_NODES41}$Elements\n1 1 1 1\n3 1 4 {n}\n1 1 2 3 4\n$EndElements\n"
    ));
    assert!(matches!(e.kind, ErrorKind::ImplausibleCount { .. }), "{e}");
    // 2.2.
    let e = err_text(&format!(
        "{HEAD22}{TET_NODES22}$Elements\n{n}\n1 4 2 1 1 1 2 3 4\n$EndElements\n"
    ));
    assert!(matches!(e.kind, ErrorKind::ImplausibleCount { .. }), "{e}");
    assert_eq!(e.at, Some(Position::Line(12)), "{e}");
    // Binary 4.1 and 2.2: the counts of a written file replaced.
    let (m, _) = s3::every_kind();
    let w = gmsh::write(&m, &opts(GmshVersion::V41, true)).unwrap().main;
    let at = w.windows(10).position(|x| x == b"$Elements\n").unwrap() + 10;
    let mut bad = w.clone();
    bad[at + 8..at + 16].copy_from_slice(&1_000_000_000_000_000u64.to_le_bytes());
    let e = err(&bad);
    assert!(matches!(e.kind, ErrorKind::ImplausibleCount { .. }), "{e}");
    assert_eq!(e.at, Some(Position::Byte((at + 8) as u64)), "{e}");
    let w = gmsh::write(&m, &opts(GmshVersion::V22, true)).unwrap().main;
    let at = w.windows(10).position(|x| x == b"$Elements\n").unwrap() + 10;
    let mut bad = w[..at].to_vec();
    bad.extend_from_slice(format!("{n}\n").as_bytes());
    bad.extend_from_slice(&w[w[at..].iter().position(|&c| c == b'\n').unwrap() + at + 1..]);
    let e = err(&bad);
    assert!(matches!(e.kind, ErrorKind::ImplausibleCount { .. }), "{e}");
    assert!(start.elapsed().as_secs() < 5, "refused without allocating");
}

#[test]
fn malformed_block_too_short_for_its_27_node_hexahedra() {
    // The 4.1 block header passes the count of 4 bytes per element, not of a 27-node
    // hexahedron's: refused at the block, before the block's arrays are made.
    let filler = format!("$Comments\n{}\n$EndComments\n", "x".repeat(400));
    let e = err_text(&format!("{HEAD41}{TET_NODES41}$Elements\n1 100 1 100\n3 1 12 100\n1 1 2 3 4\n$EndElements\n{filler}"));
    assert!(matches!(e.kind, ErrorKind::ImplausibleCount { .. }), "{e}");
    assert!(e.to_string().contains("hexa27"), "{e}");
    assert_eq!(e.at, Some(Position::Line(18)), "{e}");
}

#[test]
fn malformed_tetrahedron_with_three_nodes() {
    let e = err_text(&format!(
        "{HEAD41}{TET_NODES41}$Elements\n1 1 1 1\n3 1 4 1\n1 1 2 3\n$EndElements\n"
    ));
    // The last record of the section: said at its own line, not at `$EndElements`.
    assert_eq!(e.at, Some(Position::Line(19)), "{e}");
    assert!(e.to_string().contains("4 node tags after element 1 (a tetra)"), "{e}");
    let e =
        err_text(&format!("{HEAD22}{TET_NODES22}$Elements\n1\n1 4 2 1 1 1 2 3\n$EndElements\n"));
    assert_eq!(e.at, Some(Position::Line(13)), "{e}");
    assert!(e.to_string().contains("4 node numbers (a tetra)"), "{e}");
    // The next record's number taken for a node.
    let e = err_text(&format!(
        "{HEAD41}{TET_NODES41}$Elements\n1 2 1 2\n3 1 4 2\n1 1 2 3\n9 1 2 3 4\n$EndElements\n"
    ));
    assert_eq!(e.at, Some(Position::Line(19)), "{e}");
    let e = err_text(&format!(
        "{HEAD22}{TET_NODES22}$Elements\n2\n1 4 2 1 1 1 2 3\n2 4 2 1 1 1 2 3 4\n$EndElements\n"
    ));
    assert_eq!(e.at, Some(Position::Line(13)), "{e}");
    assert!(e.to_string().contains("tetra"), "{e}");
    // Binary 2.2: the last element cut short.
    let (m, _) = s3::every_kind();
    let w = gmsh::write(&m, &opts(GmshVersion::V22, true)).unwrap().main;
    let end = w.windows(13).position(|x| x == b"$EndElements\n").unwrap();
    let mut bad = w[..end - 5].to_vec();
    bad.extend_from_slice(&w[end - 1..]);
    let e = err(&bad);
    assert!(matches!(e.at, Some(Position::Byte(_))), "{e}");
}

#[test]
fn malformed_27_node_hexahedron_with_20_nodes_in_22() {
    let nodes: String = (1..=27).map(|i| format!("{i} {i} 0 0\n")).collect();
    let tags: String = (1..=20).map(|i| format!(" {i}")).collect();
    let e = err_text(&format!(
        "{HEAD22}$Nodes\n27\n{nodes}$EndNodes\n$Elements\n1\n1 12 2 1 1{tags}\n$EndElements\n"
    ));
    assert!(e.at.is_some(), "{e}");
}

#[test]
fn malformed_volume_entity_bounding_boxes() {
    let elements = "$Elements\n1 1 1 1\n3 1 4 1\n1 1 2 3 4\n$EndElements\n";
    // Minimum above maximum.
    let e = err_text(&format!(
        "{HEAD41}$Entities\n0 0 0 1\n1 0 0 2 1 1 1 1 7 0\n$EndEntities\n{TET_NODES41}{elements}"
    ));
    assert_eq!(e.at, Some(Position::Line(6)), "{e}");
    assert!(e.to_string().contains("volume 1") && e.to_string().contains("along z"), "{e}");
    // Not a number, infinite.
    for bad in ["nan", "inf", "1e999"] {
        let e = err_text(&format!(
            "{HEAD41}$Entities\n0 0 0 1\n1 0 0 0 1 {bad} 1 1 7 0\n$EndEntities\n{TET_NODES41}{elements}"
        ));
        assert_eq!(e.at, Some(Position::Line(6)), "{bad}: {e}");
    }
    // Binary: a NaN in the box of a written volume entity.
    let (m, _) = s3::every_kind();
    let w = gmsh::write(&m, &opts(GmshVersion::V41, true)).unwrap().main;
    let at = w.windows(10).position(|x| x == b"$Entities\n").unwrap() + 10;
    // 4 counts, then 5 surfaces (tag, 6 doubles, 1 + 1 tags, no bounding entity), the
    // first volume's tag: its box.
    let surface = 4 + 48 + 8 + 4 + 8;
    let bx = at + 32 + 5 * surface + 4;
    let mut bad = w.clone();
    bad[bx + 16..bx + 24].copy_from_slice(&f64::NAN.to_le_bytes());
    let e = err(&bad);
    assert_eq!(e.at, Some(Position::Byte(bx as u64)), "{e}");
    let mut bad = w.clone();
    bad[bx..bx + 8].copy_from_slice(&1e9f64.to_le_bytes());
    let e = err(&bad);
    assert!(e.to_string().contains("along x"), "{e}");
    // Gmsh's empty box (zeros) and meshio's (zeros always) are boxes.
    read_msh(format!("{HEAD41}$Entities\n0 0 0 1\n1 0 0 0 0 0 0 1 7 0\n$EndEntities\n{TET_NODES41}{elements}").as_bytes()).unwrap();
}

#[test]
fn malformed_tetrahedra_on_a_surface_entity() {
    let e = err_text(&format!(
        "{HEAD41}{TET_NODES41}$Elements\n1 1 1 1\n2 1 4 1\n1 1 2 3 4\n$EndElements\n"
    ));
    assert_eq!(e.at, Some(Position::Line(18)), "{e}");
    assert!(e.to_string().contains("dimension 3") && e.to_string().contains("dimension 2"), "{e}");
}

#[test]
fn malformed_element_type_of_order_3_names_itself() {
    let e =
        err_text(&format!("{HEAD22}{TET_NODES22}$Elements\n1\n1 29 2 1 1 1 2 3 4\n$EndElements\n"));
    assert!(e.to_string().contains("type 29 (high-order tetrahedron)"), "{e}");
    assert!(e.to_string().contains("tetrahedra, hexahedra, prisms and pyramids"), "{e}");
}

/// Every prefix of every encoding of the every-kind mesh is refused with a position or
/// read, never a panic (the binary record code of each node count is crossed).
#[test]
fn truncations_of_every_encoding_never_panic() {
    let (m, _) = s3::every_kind();
    let m = with_data(m);
    for (v, bin) in ALL {
        let w = gmsh::write(&m, &opts(v, bin)).unwrap().main;
        for cut in (0..w.len()).step_by(7) {
            if let Err(e) = read_msh(&w[..cut]) {
                assert!(e.at.is_some() || cut == 0, "{v:?} {bin} at {cut}: {e}");
            }
        }
    }
}
