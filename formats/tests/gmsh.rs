//! Gmsh MSH reader and writer: the public fixtures written by Gmsh 4.15.2, round trips
//! in the four encodings, properties on random meshes, and malformed inputs.

use smartmesh_formats::GmshWrite;
use smartmesh_test_support::formats as common;

use std::collections::BTreeMap;

use smartmesh_formats::{
    gmsh, CellBlock, CellKind, DataArray, ErrorKind, Format, GmshVersion, Position, ReadContext,
    TaggedMesh, WriteOptions,
};

const ENCODINGS: [&str; 4] = ["v22_ascii", "v22_binary", "v41_ascii", "v41_binary"];

fn read_msh(bytes: &[u8]) -> smartmesh_formats::Result<TaggedMesh> {
    gmsh::read(bytes, &ReadContext::alone("msh"))
}

fn opts(version: GmshVersion, binary: bool) -> WriteOptions {
    WriteOptions { gmsh: GmshWrite { version, binary }, ..WriteOptions::default() }
}

fn all_options() -> [(GmshVersion, bool); 4] {
    [
        (GmshVersion::V22, false),
        (GmshVersion::V22, true),
        (GmshVersion::V41, false),
        (GmshVersion::V41, true),
    ]
}

/// Points compared bit for bit.
fn assert_points_bitwise(a: &TaggedMesh, b: &TaggedMesh, what: &str) {
    assert_eq!(a.points.len(), b.points.len(), "{what}: point count");
    for (i, (p, q)) in a.points.iter().zip(&b.points).enumerate() {
        for k in 0..3 {
            assert_eq!(
                p[k].to_bits(),
                q[k].to_bits(),
                "{what}: point {i} coordinate {k}: {p:?} vs {q:?}"
            );
        }
    }
}

/// Cells compared as cells: kind, nodes and tags in order, whatever the block splits.
fn cell_list(m: &TaggedMesh) -> Vec<(CellKind, Vec<u32>, i32, i32)> {
    m.cells().map(|(k, n, p, g)| (k, n.to_vec(), p, g)).collect()
}

fn assert_data_bitwise(
    a: &BTreeMap<String, DataArray>,
    b: &BTreeMap<String, DataArray>,
    what: &str,
) {
    assert_eq!(a.keys().collect::<Vec<_>>(), b.keys().collect::<Vec<_>>(), "{what}: array names");
    for (name, x) in a {
        let y = &b[name];
        assert_eq!(x.components, y.components, "{what}: `{name}` components");
        assert_eq!(x.values.len(), y.values.len(), "{what}: `{name}` length");
        for (i, (u, v)) in x.values.iter().zip(&y.values).enumerate() {
            assert!(
                u.to_bits() == v.to_bits() || (u.is_nan() && v.is_nan()),
                "{what}: `{name}` value {i}: {u} vs {v}"
            );
        }
    }
}

/// Everything but `entities` (which a 4.1 file always fills).
fn assert_same_mesh(a: &TaggedMesh, b: &TaggedMesh, what: &str) {
    assert_points_bitwise(a, b, what);
    assert_eq!(a.coordinate_dim, b.coordinate_dim, "{what}: coordinate_dim");
    assert_eq!(cell_list(a), cell_list(b), "{what}: cells");
    assert_eq!(a.tag_names, b.tag_names, "{what}: tag names");
    assert_data_bitwise(&a.point_data, &b.point_data, &format!("{what}: point data"));
    assert_data_bitwise(&a.cell_data, &b.cell_data, &format!("{what}: cell data"));
}

fn names(list: &[(u8, i32, &str)]) -> BTreeMap<(u8, i32), String> {
    list.iter().map(|&(d, t, n)| ((d, t), n.to_string())).collect()
}

fn counts(list: &[(&str, i32, usize)]) -> BTreeMap<(String, i32), usize> {
    list.iter().map(|&(k, p, n)| ((k.to_string(), p), n)).collect()
}

struct Expected {
    model: &'static str,
    nodes: usize,
    /// Entities listed in the 4.1 `$Entities` section.
    entities_41: usize,
    counts: BTreeMap<(String, i32), usize>,
    names: BTreeMap<(u8, i32), String>,
}

/// Counts per (cell kind, physical tag) found independently with Gmsh's Python API
/// (gmsh 4.15.2: `gmsh.open(file)`, then for every entity `getElements` counted under
/// the entity's first physical group, `getNodes` for the node count,
/// `getPhysicalGroups`/`getPhysicalName` for the names); the same for all four
/// encodings of each model. Entity counts are the `$Entities` header of the 4.1 files
/// (`123 4 1 0` for naca0012, ...).
fn expected() -> Vec<Expected> {
    vec![
        Expected {
            model: "naca0012",
            nodes: 1904,
            entities_41: 123 + 4 + 1,
            counts: counts(&[
                ("vertex", 4, 1),
                ("vertex", 5, 1),
                ("line", 1, 104),
                ("line", 2, 64),
                ("triangle", 3, 3640),
            ]),
            names: names(&[
                (0, 4, "LeadingEdge"),
                (0, 5, "TrailingEdge"),
                (1, 1, "Airfoil"),
                (1, 2, "Farfield"),
                (2, 3, "Fluid"),
            ]),
        },
        Expected {
            model: "square_hole",
            nodes: 435,
            entities_41: 9 + 8 + 1,
            counts: counts(&[
                ("vertex", 4, 4),
                ("line", 1, 52),
                ("line", 2, 44),
                ("triangle", 3, 774),
            ]),
            names: names(&[(0, 4, "Corners"), (1, 1, "Walls"), (1, 2, "Hole"), (2, 3, "Domain")]),
        },
        Expected {
            model: "two_domains",
            nodes: 276,
            entities_41: 6 + 7 + 2,
            counts: counts(&[
                ("line", 1, 10),
                ("line", 2, 60),
                ("triangle", 3, 242),
                ("triangle", 4, 248),
            ]),
            names: names(&[(1, 1, "Interface"), (1, 2, "Outer"), (2, 3, "Left"), (2, 4, "Right")]),
        },
        Expected {
            model: "two_domains_quads",
            nodes: 274,
            entities_41: 6 + 7 + 2,
            counts: counts(&[
                ("line", 1, 10),
                ("line", 2, 60),
                ("quad", 3, 119),
                ("triangle", 4, 248),
            ]),
            names: names(&[(1, 1, "Interface"), (1, 2, "Outer"), (2, 3, "Left"), (2, 4, "Right")]),
        },
    ]
}

fn fixture(model: &str, enc: &str) -> TaggedMesh {
    common::read_file(&format!("gmsh/{model}.{enc}.msh"))
}

#[test]
fn fixtures_have_the_expected_counts_per_tag() {
    smartmesh_test_support::require_public_fixtures!();
    for e in expected() {
        for enc in ENCODINGS {
            let m = fixture(e.model, enc);
            let what = format!("{}.{enc}", e.model);
            assert_eq!(m.points.len(), e.nodes, "{what}: nodes");
            assert_eq!(common::counts_per_tag(&m), e.counts, "{what}: counts per tag");
            assert_eq!(m.tag_names, e.names, "{what}: names");
            assert_eq!(m.coordinate_dim, 2, "{what}: planar");
            assert!(m.point_data.is_empty() && m.cell_data.is_empty(), "{what}");
            if enc.starts_with("v41") {
                assert_eq!(m.entities.len(), e.entities_41, "{what}: entities");
                // Every cell's physical tag is its entity's first group.
                for (k, _, p, g) in m.cells() {
                    assert_eq!(
                        m.entities[&(k.dim(), g)].first().copied().unwrap_or(0),
                        p,
                        "{what}"
                    );
                }
            } else {
                // No entity of these models is in two groups: no copies to merge.
                assert!(m.entities.is_empty(), "{what}");
            }
        }
    }
}

#[test]
fn naca_entities_and_geometrical_tags() {
    smartmesh_test_support::require_public_fixtures!();
    // naca0012.v41_ascii.msh, `$Entities`: point 1 in group 4 (LeadingEdge), point 2 in
    // 5, points 3.. in none; curves 1-2 (the airfoil) in group 1, 3-4 in 2.
    let m = fixture("naca0012", "v41_ascii");
    assert_eq!(m.entities[&(0, 1)], vec![4]);
    assert_eq!(m.entities[&(0, 2)], vec![5]);
    assert_eq!(m.entities[&(0, 3)], Vec::<i32>::new());
    // The surface is entity 1000 (`1000 -19.5 ... 1 3 4 3 4 -2 -1`).
    assert_eq!(m.entities[&(2, 1000)], vec![3]);
    let geo: std::collections::BTreeSet<(u8, i32)> =
        m.cells().map(|(k, _, _, g)| (k.dim(), g)).collect();
    assert!(geo.contains(&(2, 1000)) && geo.contains(&(0, 1)) && geo.contains(&(0, 2)));
}

/// Whether `b` is `a` to the 16 significant digits of C's `%.16g`.
fn same_to_16_digits(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-15 * a.abs()
}

#[test]
fn the_four_encodings_of_a_model_read_the_same() {
    smartmesh_test_support::require_public_fixtures!();
    // Two things Gmsh itself does differently between its four files of one mesh:
    // - it writes ASCII coordinates with `%.16g`, 16 significant digits, one short of
    //   what every double needs, so its ASCII and binary files differ in the last bits
    //   of some coordinates: files of the same number encoding agree bit for bit, ASCII
    //   and binary ones to the 16 digits;
    // - it numbers elements in another order in 2.2 (all triangles of all surfaces, then
    //   all quadrangles) than in 4.1 (by entity, then type): cells come in element-tag
    //   order, so the two versions give the same cells, in the same order for
    //   two_domains_quads only up to that.
    for e in expected() {
        let meshes: Vec<(&str, TaggedMesh)> =
            ENCODINGS.iter().map(|enc| (*enc, fixture(e.model, enc))).collect();
        let mut differ = 0;
        for (ea, a) in &meshes {
            for (eb, b) in &meshes {
                let what = format!("{} {ea} vs {eb}", e.model);
                assert_eq!(a.points.len(), b.points.len(), "{what}");
                for (p, q) in a.points.iter().zip(&b.points) {
                    for k in 0..3 {
                        if ea.ends_with("ascii") == eb.ends_with("ascii") {
                            assert_eq!(p[k].to_bits(), q[k].to_bits(), "{what}: {p:?} vs {q:?}");
                        } else {
                            assert!(same_to_16_digits(p[k], q[k]), "{what}: {p:?} vs {q:?}");
                            differ += (p[k].to_bits() != q[k].to_bits()) as usize;
                        }
                    }
                }
                let (mut ca, mut cb) = (cell_list(a), cell_list(b));
                if ea[..3] != eb[..3] && e.model == "two_domains_quads" {
                    ca.sort();
                    cb.sort();
                }
                assert!(ca == cb, "{what}: cells differ");
                assert_eq!(a.tag_names, b.tag_names, "{what}");
                if ea[..3] == eb[..3] {
                    assert_eq!(a.entities, b.entities, "{what}");
                }
            }
        }
        eprintln!(
            "{}: {} coordinates differ in their last bits between ASCII and binary",
            e.model,
            differ / 8
        );
    }
}

#[test]
fn fixtures_written_in_each_encoding_read_back_identical() {
    smartmesh_test_support::require_public_fixtures!();
    for e in expected() {
        let src = fixture(e.model, "v41_ascii");
        for (v, bin) in all_options() {
            let what = format!("{} written as {v:?} binary={bin}", e.model);
            let (w, back) = common::roundtrip(Format::Gmsh, "msh", &src, &opts(v, bin));
            assert_same_mesh(&src, &back, &what);
            if v == GmshVersion::V41 {
                assert_eq!(back.entities, src.entities, "{what}: entities");
                assert!(w.report.dropped.is_empty(), "{what}: {:?}", w.report.dropped);
            } else {
                // 2.2 has no entity table: the point entities without nodes are lost.
                assert!(
                    w.report.dropped.iter().any(|d| d.contains("no entity table")),
                    "{what}: {:?}",
                    w.report.dropped
                );
            }
            // Same mesh, same bytes.
            let again = gmsh::write(&src, &opts(v, bin)).unwrap();
            assert_eq!(again.main, w.main, "{what}: deterministic");
        }
    }
}

#[test]
fn writing_what_was_read_gives_the_same_bytes() {
    smartmesh_test_support::require_public_fixtures!();
    // write → read → write is a fixed point for every encoding.
    for e in expected() {
        let src = fixture(e.model, "v22_binary");
        for (v, bin) in all_options() {
            let first = gmsh::write(&src, &opts(v, bin)).unwrap().main;
            let second = gmsh::write(&read_msh(&first).unwrap(), &opts(v, bin)).unwrap().main;
            assert!(first == second, "{} {v:?} binary={bin}", e.model);
        }
    }
}

fn small_mesh() -> TaggedMesh {
    let mut m = TaggedMesh::new();
    m.points = vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.5, 0.5, 0.0],
        [0.1, 0.1, 0.0],
    ];
    let mut t = CellBlock::new(CellKind::Triangle);
    t.push(&[0, 1, 4], 7, 1);
    t.push(&[1, 2, 4], 7, 1);
    t.push(&[2, 3, 4], 7, 1);
    t.push(&[3, 0, 4], 7, 1);
    let mut l = CellBlock::new(CellKind::Line);
    l.push(&[0, 1], 2, 3);
    l.push(&[1, 2], 2, 3);
    m.blocks = vec![t, l];
    m.tag_names.insert((2, 7), "Domain".into());
    m.tag_names.insert((1, 2), "Wall".into());
    let metric: Vec<f64> = (0..6)
        .flat_map(|i| smartmesh_formats::sym2_to_tensor9(1.0 + i as f64, 0.25, 2.0, 1.0))
        .collect();
    m.point_data.insert("metric".into(), DataArray::new(9, metric));
    m.cell_data.insert("quality".into(), DataArray::new(1, vec![0.1, 0.2, 0.3, 0.4, 0.5, 0.6]));
    m
}

#[test]
fn unused_nodes_and_data_survive_each_encoding() {
    // Point 5 is used by no cell (like a circle's centre).
    let m = small_mesh();
    for (v, bin) in all_options() {
        let (w, back) = common::roundtrip(Format::Gmsh, "msh", &m, &opts(v, bin));
        assert_same_mesh(&m, &back, &format!("{v:?} binary={bin}"));
        assert!(w.report.dropped.is_empty(), "{:?}", w.report.dropped);
    }
}

#[test]
fn z_coordinates_are_kept() {
    let mut m = small_mesh();
    m.points[2][2] = -0.125;
    m.coordinate_dim = 3;
    for (v, bin) in all_options() {
        let (_, back) = common::roundtrip(Format::Gmsh, "msh", &m, &opts(v, bin));
        assert_same_mesh(&m, &back, &format!("{v:?} binary={bin}"));
    }
}

#[test]
fn entity_with_two_groups_is_kept_in_both_versions() {
    let mut m = small_mesh();
    m.entities.insert((2, 1), vec![7, 8]);
    m.entities.insert((1, 3), vec![2]);
    m.tag_names.insert((2, 8), "Everything".into());
    for (v, bin) in all_options() {
        let (w, back) = common::roundtrip(Format::Gmsh, "msh", &m, &opts(v, bin));
        assert_same_mesh(&m, &back, &format!("{v:?} binary={bin}"));
        assert_eq!(back.entities[&(2, 1)], vec![7, 8], "{v:?} binary={bin}");
        assert!(w.report.dropped.is_empty(), "{:?}", w.report.dropped);
    }
    // 2.2 writes each triangle twice, as Gmsh does.
    let text = gmsh::write(&m, &opts(GmshVersion::V22, false)).unwrap().main;
    let text = String::from_utf8(text).unwrap();
    assert!(text.contains("$Elements\n10\n1 2 2 7 1 1 2 5\n2 2 2 8 1 1 2 5\n"), "{text}");
}

#[test]
fn cells_of_one_entity_in_two_groups_are_split_in_41_and_reported() {
    let mut m = small_mesh();
    m.blocks[0].physical[3] = 9;
    let w = gmsh::write(&m, &opts(GmshVersion::V41, false)).unwrap();
    assert!(
        w.report
            .dropped
            .iter()
            .any(|d| d.contains("2D entity 1 holds cells of several physical groups")),
        "{:?}",
        w.report.dropped
    );
    let back = read_msh(&w.main).unwrap();
    assert_points_bitwise(&m, &back, "split");
    let phys: Vec<i32> = back.cells().map(|c| c.2).collect();
    assert_eq!(phys, m.cells().map(|c| c.2).collect::<Vec<_>>());
    let geo: Vec<i32> = back.cells().map(|c| c.3).collect();
    // Entity tags count per dimension: the first free surface tag is 2.
    assert_eq!(geo, vec![1, 1, 1, 2, 3, 3]);
    // 2.2 holds it as it is.
    let (_, back) = common::roundtrip(Format::Gmsh, "msh", &m, &opts(GmshVersion::V22, true));
    assert_same_mesh(&m, &back, "2.2");
}

/// Cells moved to new entities are written, with another geometrical tag: the report
/// says "written as", not that something was left out.
#[test]
fn cells_moved_to_new_entities_are_reported_as_written() {
    let mut m = small_mesh();
    m.blocks[0].physical[3] = 9;
    m.blocks[1].geometrical[1] = 0;
    let w = gmsh::write(&m, &opts(GmshVersion::V41, false)).unwrap();
    let moved: Vec<_> = w.report.dropped.iter().filter(|d| d.contains("new entit")).collect();
    assert_eq!(moved.len(), 2, "{:?}", w.report.dropped);
    assert!(moved.iter().all(|d| d.contains("written as cells of")), "{moved:?}");
}

/// Lines in a physical group, triangles without one (Triangle's `A.1.ele`, a `.poly`
/// without regional attributes): Gmsh would drop the triangles when it saves the file,
/// and meshio refuses a 4.1 file whose blocks are not all in a group. The triangles go
/// to a group of their own, named `smartmesh:untagged`, one above the largest 2D tag,
/// and come back untagged.
#[test]
fn untagged_cells_beside_tagged_ones_get_a_group_of_their_own() {
    let mut m = TaggedMesh::new();
    m.points = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]];
    let mut t = CellBlock::new(CellKind::Triangle);
    t.push(&[0, 1, 2], 0, 1);
    t.push(&[0, 2, 3], 0, 1);
    let mut l = CellBlock::new(CellKind::Line);
    l.push(&[0, 1], 2, 3);
    l.push(&[1, 2], 0, 3);
    m.blocks = vec![t, l];
    m.tag_names.insert((2, 4), "Unused".into());
    for (version, binary) in all_options() {
        let w = gmsh::write(&m, &opts(version, binary)).unwrap();
        let text = String::from_utf8_lossy(&w.main);
        // 2D: above the named tag 4; 1D: above the lines' tag 2.
        assert!(text.contains("2 5 \"smartmesh:untagged\""), "{version:?} {binary}:\n{text}");
        assert!(text.contains("1 3 \"smartmesh:untagged\""), "{version:?} {binary}:\n{text}");
        let said: Vec<_> =
            w.report.dropped.iter().filter(|l| l.contains("without a physical tag")).collect();
        assert_eq!(said.len(), 2, "{:?}", w.report.dropped);
        assert!(said[0].contains("1 1D cell(s) without a physical tag written as physical group 3 `smartmesh:untagged`"), "{said:?}");
        assert!(said[1].contains("2 2D cell(s)"), "{said:?}");
        let back = read_msh(&w.main).unwrap();
        let untag = |m: &TaggedMesh| -> Vec<_> {
            cell_list(m).into_iter().map(|(k, n, p, _)| (k, n, p)).collect()
        };
        assert_eq!(untag(&back), untag(&m), "{version:?} {binary}");
        assert_eq!(back.tag_names, m.tag_names, "{version:?} {binary}");
        assert!(back.entities.values().all(|l| !l.contains(&5) && !l.contains(&3)));
    }
    // Without any physical tag, nothing is added: Gmsh keeps every element then.
    for b in &mut m.blocks {
        b.physical.fill(0);
    }
    m.tag_names.clear();
    for (version, binary) in all_options() {
        let w = gmsh::write(&m, &opts(version, binary)).unwrap();
        assert!(!String::from_utf8_lossy(&w.main).contains("$PhysicalNames"));
        assert!(w.report.dropped.iter().all(|l| !l.contains("physical tag")), "{:?}", w.report);
    }
}

#[test]
fn what_msh_cannot_hold_is_reported() {
    let mut m = small_mesh();
    m.point_sets.insert("corners".into(), vec![0, 1]);
    m.holes.push([0.5, 0.5]);
    m.tag_names.insert((1, 5), "say \"hi\"".into());
    m.point_data.insert("uv".into(), DataArray::new(2, vec![0.0; 12]));
    let mut q = DataArray::new(1, vec![1.0; 6]);
    q.values[2] = f64::NAN;
    m.cell_data.insert("quality".into(), q);
    let w = gmsh::write(&m, &opts(GmshVersion::V41, false)).unwrap();
    let all = w.report.dropped.join("\n");
    for needle in [
        "point set `corners`",
        "hole point",
        "double quotes",
        "`uv` has 2 components",
        "1 item(s) with NaN",
    ] {
        assert!(all.contains(needle), "missing `{needle}` in:\n{all}");
    }
    let back = read_msh(&w.main).unwrap();
    assert_eq!(back.tag_name(1, 5), Some("say 'hi'"));
    assert!(back.cell_data["quality"].values[2].is_nan());
    assert_eq!(back.point_data["uv"].components, 2);
}

#[test]
fn written_41_looks_like_gmsh() {
    let m = small_mesh();
    let w = gmsh::write(&m, &opts(GmshVersion::V41, false)).unwrap();
    let text = String::from_utf8(w.main).unwrap();
    let expected_head = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$PhysicalNames\n2\n1 2 \"Wall\"\n2 7 \"Domain\"\n$EndPhysicalNames\n\
$Entities\n0 1 1 0\n3 0.0 0.0 0.0 1.0 1.0 0.0 1 2 0\n1 0.0 0.0 0.0 1.0 1.0 0.0 1 7 0\n$EndEntities\n\
$Nodes\n2 6 1 6\n1 3 0 3\n1\n2\n3\n0.0 0.0 0.0\n1.0 0.0 0.0\n1.0 1.0 0.0\n2 1 0 3\n4\n5\n6\n0.0 1.0 0.0\n0.5 0.5 0.0\n0.1 0.1 0.0\n$EndNodes\n\
$Elements\n2 6 1 6\n1 3 1 2\n5 1 2\n6 2 3\n2 1 2 4\n1 1 2 5\n2 2 3 5\n3 3 4 5\n4 4 1 5\n$EndElements\n\
$NodeData\n1\n\"metric\"\n1\n0\n3\n0\n9\n6\n1 1.0 0.25 0.0 0.25 2.0 0.0 0.0 0.0 1.0\n";
    assert!(text.starts_with(expected_head), "{text}");
    assert!(text.ends_with("$ElementData\n1\n\"quality\"\n1\n0\n3\n0\n1\n6\n1 0.1\n2 0.2\n3 0.3\n4 0.4\n5 0.5\n6 0.6\n$EndElementData\n"), "{text}");
}

// ---------------------------------------------------------------------------------
// Features of the format read from hand-written files

const HEAD41: &str = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n";
const HEAD22: &str = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n";

const SQUARE41: &str = "$Entities\n0 0 1 0\n1 0 0 0 1 1 0 1 5 0\n$EndEntities\n\
$Nodes\n1 5 1 5\n2 1 0 5\n1\n2\n3\n4\n5\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0.5 0.5 0\n$EndNodes\n\
$Elements\n1 2 1 2\n2 1 2 2\n1 1 2 3\n2 1 3 4\n$EndElements\n";

#[test]
fn reads_a_minimal_41_file_with_an_unused_node() {
    let m = read_msh(format!("{HEAD41}{SQUARE41}").as_bytes()).unwrap();
    assert_eq!(m.points.len(), 5);
    assert_eq!(m.points[4], [0.5, 0.5, 0.0]);
    assert_eq!(
        cell_list(&m),
        vec![(CellKind::Triangle, vec![0, 1, 2], 5, 1), (CellKind::Triangle, vec![0, 2, 3], 5, 1)]
    );
}

#[test]
fn without_entities_a_41_file_has_no_groups() {
    let m = read_msh(format!("{HEAD41}$Nodes\n1 3 1 3\n2 4 0 3\n1\n2\n3\n0 0 0\n1 0 0\n0 1 0\n$EndNodes\n$Elements\n1 1 1 1\n2 4 2 1\n1 1 2 3\n$EndElements\n").as_bytes()).unwrap();
    assert_eq!(cell_list(&m), vec![(CellKind::Triangle, vec![0, 1, 2], 0, 4)]);
}

/// A square of two 6-node triangles and a 3-node line (as `gmsh -2 -order 2` writes
/// them: corners first), a node no cell uses, and a node view.
const SECOND_ORDER_NODES: &str = "1 0 0 0\n2 1 0 0\n3 1 1 0\n4 0 1 0\n5 0.5 0 0\n6 1 0.5 0\n7 0.5 1 0\n8 0 0.5 0\n9 0.5 0.5 0\n10 2 2 0\n";

/// Second-order cells are kept as the file has them, in both versions (as the VTK and
/// Medit readers keep them); `linearise` then makes them the linear cells of their
/// corners, dropping the mid-edge nodes with their point data and keeping the node no
/// cell uses.
#[test]
fn second_order_cells_are_kept_and_linearised_on_demand() {
    let view = "$NodeData\n1\n\"s\"\n1\n0\n3\n0\n1\n10\n1 1\n2 2\n3 3\n4 4\n5 5\n6 6\n7 7\n8 8\n9 9\n10 10\n$EndNodeData\n";
    let coords: String = SECOND_ORDER_NODES
        .lines()
        .map(|l| format!("{}\n", &l[l.find(' ').unwrap() + 1..]))
        .collect();
    let v41 = format!(
        "{HEAD41}$Entities\n0 1 1 0\n1 0 0 0 1 0 0 1 2 0\n1 0 0 0 1 1 0 1 5 0\n$EndEntities\n\
$Nodes\n1 10 1 10\n2 1 0 10\n1\n2\n3\n4\n5\n6\n7\n8\n9\n10\n{coords}$EndNodes\n\
$Elements\n2 3 1 3\n1 1 8 1\n1 1 2 5\n2 1 9 2\n2 1 2 3 5 6 9\n3 1 3 4 9 7 8\n$EndElements\n{view}"
    );
    let v22 = format!(
        "{HEAD22}$Nodes\n10\n{SECOND_ORDER_NODES}$EndNodes\n\
$Elements\n3\n1 8 2 2 1 1 2 5\n2 9 2 5 1 1 2 3 5 6 9\n3 9 2 5 1 1 3 4 9 7 8\n$EndElements\n{view}"
    );
    for file in [v41, v22] {
        let (mut m, report) =
            gmsh::read_reported(file.as_bytes(), &ReadContext::alone("msh")).unwrap();
        assert!(report.notes.is_empty(), "{:?}", report.notes);
        assert_eq!(m.points.len(), 10);
        assert_eq!(
            cell_list(&m),
            vec![
                (CellKind::Line3, vec![0, 1, 4], 2, 1),
                (CellKind::Triangle6, vec![0, 1, 2, 4, 5, 8], 5, 1),
                (CellKind::Triangle6, vec![0, 2, 3, 8, 6, 7], 5, 1),
            ]
        );
        assert_eq!(m.point_data["s"].values.len(), 10);

        let note = m.linearise().unwrap();
        assert!(
            note.contains("2 6-node triangles as 3-node")
                && note.contains("5 mid-edge nodes dropped"),
            "{note}"
        );
        assert_eq!(
            m.points,
            vec![
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [1.0, 1.0, 0.0],
                [0.0, 1.0, 0.0],
                [2.0, 2.0, 0.0]
            ]
        );
        assert_eq!(
            cell_list(&m),
            vec![
                (CellKind::Line, vec![0, 1], 2, 1),
                (CellKind::Triangle, vec![0, 1, 2], 5, 1),
                (CellKind::Triangle, vec![0, 2, 3], 5, 1),
            ]
        );
        assert_eq!(m.point_data["s"].values, vec![1.0, 2.0, 3.0, 4.0, 10.0]);
        assert_eq!(m.linearise(), None);
    }
}

/// Second-order cells of every kind go through MSH 2.2 and 4.1, ASCII and binary, as
/// they are: a 9-node quad written by smartmesh comes back with its 9 nodes.
#[test]
fn second_order_cells_round_trip_in_each_encoding() {
    let mut m = TaggedMesh::new();
    // A 2x1 block: nodes 0..15 on a 5x3 grid of step 0.5.
    for j in 0..3 {
        for i in 0..5 {
            m.points.push([0.5 * i as f64, 0.5 * j as f64, 0.0]);
        }
    }
    let g = |i: u32, j: u32| j * 5 + i;
    let mut q9 = CellBlock::new(CellKind::Quad9);
    q9.push(
        &[g(0, 0), g(2, 0), g(2, 2), g(0, 2), g(1, 0), g(2, 1), g(1, 2), g(0, 1), g(1, 1)],
        1,
        1,
    );
    let mut q8 = CellBlock::new(CellKind::Quad8);
    q8.push(&[g(2, 0), g(4, 0), g(4, 2), g(2, 2), g(3, 0), g(4, 1), g(3, 2), g(2, 1)], 2, 2);
    let mut t6 = CellBlock::new(CellKind::Triangle6);
    t6.push(&[g(0, 0), g(2, 0), g(0, 2), g(1, 0), g(1, 1), g(0, 1)], 3, 3);
    let mut l3 = CellBlock::new(CellKind::Line3);
    l3.push(&[g(0, 0), g(2, 0), g(1, 0)], 4, 4);
    m.blocks = vec![l3, t6, q9, q8];
    m.point_data.insert("f".into(), DataArray::new(1, (0..15).map(f64::from).collect()));
    for (version, binary) in all_options() {
        let what = format!("{version:?} binary={binary}");
        let (w, back) = common::roundtrip(Format::Gmsh, "msh", &m, &opts(version, binary));
        assert!(w.report.dropped.is_empty(), "{what}: {:?}", w.report.dropped);
        assert_points_bitwise(&m, &back, &what);
        assert_eq!(cell_list(&m), cell_list(&back), "{what}");
        assert_eq!(m.point_data, back.point_data, "{what}");
    }
}

#[test]
fn sparse_node_tags_are_mapped_without_a_table_of_the_largest_tag() {
    let file = format!(
        "{HEAD41}$Nodes\n1 3 7 1000000000000\n2 1 0 3\n1000000000000\n7\n500000000000\n0 0 0\n1 0 0\n0 1 0\n$EndNodes\n\
$Elements\n1 1 9 9\n2 1 2 1\n9 7 500000000000 1000000000000\n$EndElements\n"
    );
    let m = read_msh(file.as_bytes()).unwrap();
    // Points in node-tag order: 7, 5e11, 1e12.
    assert_eq!(m.points, vec![[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 0.0]]);
    assert_eq!(m.blocks[0].nodes, vec![0, 1, 2]);
}

#[test]
fn cells_are_ordered_by_element_tag() {
    let file = format!(
        "{HEAD22}$Nodes\n3\n1 0 0 0\n2 1 0 0\n3 0 1 0\n$EndNodes\n$Elements\n3\n30 2 2 1 1 1 2 3\n10 1 2 2 2 1 2\n20 15 2 3 3 3\n$EndElements\n"
    );
    let m = read_msh(file.as_bytes()).unwrap();
    let kinds: Vec<CellKind> = m.cells().map(|c| c.0).collect();
    assert_eq!(kinds, vec![CellKind::Line, CellKind::Vertex, CellKind::Triangle]);
}

#[test]
fn parametric_nodes_are_read_in_41_and_22() {
    let file = format!(
        "{HEAD41}$Nodes\n2 3 1 3\n1 1 1 2\n1\n2\n0 0 0 0.0\n1 0 0 1.0\n2 1 1 1\n3\n0 1 0 0.25 0.75\n$EndNodes\n$Elements\n1 1 1 1\n2 1 2 1\n1 1 2 3\n$EndElements\n"
    );
    let m = read_msh(file.as_bytes()).unwrap();
    assert_eq!(m.points, vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
    let file = format!("{HEAD22}$ParametricNodes\n3\n1 0 0 0 0 1\n2 1 0 0 1 1 0.5\n3 0 1 0 2 1 0.25 0.75\n$EndParametricNodes\n$Elements\n1\n1 2 2 1 1 1 2 3\n$EndElements\n");
    let m = read_msh(file.as_bytes()).unwrap();
    assert_eq!(m.points.len(), 3);
    assert_eq!(m.num_cells(), 1);
}

#[test]
fn gmsh_copies_of_an_element_in_two_groups_are_one_cell() {
    // As Gmsh 2.2 writes an entity of two physical groups: each element twice.
    let file = format!(
        "{HEAD22}$Nodes\n3\n1 0 0 0\n2 1 0 0\n3 0 1 0\n$EndNodes\n$Elements\n2\n1 2 2 5 1 1 2 3\n2 2 2 6 1 1 2 3\n$EndElements\n\
$ElementData\n1\n\"q\"\n1\n0\n3\n0\n1\n1\n2 4.5\n$EndElementData\n"
    );
    let m = read_msh(file.as_bytes()).unwrap();
    assert_eq!(cell_list(&m), vec![(CellKind::Triangle, vec![0, 1, 2], 5, 1)]);
    assert_eq!(m.entities[&(2, 1)], vec![5, 6]);
    assert_eq!(m.cell_data["q"].values, vec![4.5]);
}

/// Regression (found by `write_read_with_independent_geometrical_tags`): two equal
/// triangles of one entity in two groups, one after the other, are two cells, not a
/// cell and Gmsh's copy of it; the writer leaves a gap in the numbering between them.
#[test]
fn identical_cells_in_two_groups_are_not_taken_for_gmsh_copies() {
    let mut m = small_mesh();
    m.blocks[0].nodes[3..6].copy_from_slice(&[0, 1, 4]);
    m.blocks[0].physical[1] = 9;
    for bin in [false, true] {
        let (_, back) = common::roundtrip(Format::Gmsh, "msh", &m, &opts(GmshVersion::V22, bin));
        assert_same_mesh(&m, &back, "2.2");
    }
    let text =
        String::from_utf8(gmsh::write(&m, &opts(GmshVersion::V22, false)).unwrap().main).unwrap();
    assert!(text.contains("\n1 2 2 7 1 1 2 5\n3 2 2 9 1 1 2 5\n"), "{text}");
}

#[test]
fn extra_partition_tags_are_read_past() {
    let file = format!("{HEAD22}$Nodes\n3\n1 0 0 0\n2 1 0 0\n3 0 1 0\n$EndNodes\n$Elements\n1\n1 2 4 5 1 1 2 1 2 3\n$EndElements\n");
    let m = read_msh(file.as_bytes()).unwrap();
    assert_eq!(cell_list(&m), vec![(CellKind::Triangle, vec![0, 1, 2], 5, 1)]);
}

#[test]
fn the_last_time_step_of_a_view_is_kept() {
    let view = |step: i32, v: f64| {
        format!("$NodeData\n1\n\"T\"\n1\n{step}.0\n3\n{step}\n1\n5\n1 {v}\n2 {v}\n3 {v}\n4 {v}\n5 {v}\n$EndNodeData\n")
    };
    let file = format!("{HEAD41}{SQUARE41}{}{}", view(0, 1.0), view(1, 2.0));
    let m = read_msh(file.as_bytes()).unwrap();
    assert_eq!(m.point_data["T"].values, vec![2.0; 5]);
}

#[test]
fn partitions_of_one_step_are_merged_and_missing_items_are_nan() {
    let file = format!(
        "{HEAD41}{SQUARE41}$NodeData\n1\n\"T\"\n1\n0\n4\n0\n1\n2\n1\n1 1.5\n2 2.5\n$EndNodeData\n$NodeData\n1\n\"T\"\n1\n0\n4\n0\n1\n1\n2\n4 4.5\n$EndNodeData\n"
    );
    let m = read_msh(file.as_bytes()).unwrap();
    let v = &m.point_data["T"].values;
    assert_eq!((v[0], v[1], v[3]), (1.5, 2.5, 4.5));
    assert!(v[2].is_nan() && v[4].is_nan());
}

#[test]
fn element_node_data_becomes_cell_data_with_components_times_nodes() {
    let file = format!("{HEAD41}{SQUARE41}$ElementNodeData\n1\n\"u\"\n1\n0\n3\n0\n3\n1\n2 3 1 2 3 4 5 6 7 8 9\n$EndElementNodeData\n");
    let m = read_msh(file.as_bytes()).unwrap();
    let u = &m.cell_data["u"];
    assert_eq!(u.components, 9);
    assert!(u.values[..9].iter().all(|v| v.is_nan()));
    assert_eq!(&u.values[9..], &[1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0]);
}

#[test]
fn documented_optional_sections_are_skipped() {
    let file = format!(
        "{HEAD41}$Comments\nmade by hand $Nodes\n$EndComments\n{SQUARE41}$Periodic\n0\n$EndPeriodic\n$InterpolationScheme\n\"x\"\n1\n3\n2\n1 1 1\n1 1 1\n$EndInterpolationScheme\n$GhostElements\n0\n$EndGhostElements\n"
    );
    let m = read_msh(file.as_bytes()).unwrap();
    assert_eq!(m.num_cells(), 2);
}

#[test]
fn binary_41_with_a_4_byte_size_t() {
    // The 4.1 binary layout with size_t = 4, built by hand: one surface block.
    let mut b = b"$MeshFormat\n4.1 1 4\n".to_vec();
    b.extend_from_slice(&1i32.to_le_bytes());
    b.extend_from_slice(b"\n$EndMeshFormat\n$Nodes\n");
    for v in [1u32, 3, 1, 3] {
        b.extend_from_slice(&v.to_le_bytes());
    }
    for v in [2i32, 1, 0] {
        b.extend_from_slice(&v.to_le_bytes());
    }
    b.extend_from_slice(&3u32.to_le_bytes());
    for v in [1u32, 2, 3] {
        b.extend_from_slice(&v.to_le_bytes());
    }
    for v in [0.0f64, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0] {
        b.extend_from_slice(&v.to_le_bytes());
    }
    b.extend_from_slice(b"\n$EndNodes\n$Elements\n");
    for v in [1u32, 1, 1, 1] {
        b.extend_from_slice(&v.to_le_bytes());
    }
    for v in [2i32, 1, 2] {
        b.extend_from_slice(&v.to_le_bytes());
    }
    for v in [1u32, 1, 1, 2, 3] {
        b.extend_from_slice(&v.to_le_bytes());
    }
    b.extend_from_slice(b"\n$EndElements\n");
    let m = read_msh(&b).unwrap();
    assert_eq!(cell_list(&m), vec![(CellKind::Triangle, vec![0, 1, 2], 0, 1)]);
}

/// A binary 4.1 file (size_t = 8) with node blocks `(tags, points)` in the order given,
/// the header announcing `lo..=hi`, one triangle on nodes `tri` and a one-component
/// `$NodeData` `h` giving each tag in `data` the value 10 * tag; with the ASCII file of
/// the same content.
fn bin41_nodes(
    blocks: &[(&[u64], &[[f64; 3]])],
    lo: u64,
    hi: u64,
    tri: [u64; 3],
    data: &[u64],
) -> (Vec<u8>, String) {
    let n: usize = blocks.iter().map(|b| b.0.len()).sum();
    let mut b = b"$MeshFormat\n4.1 1 8\n".to_vec();
    b.extend_from_slice(&1i32.to_le_bytes());
    b.extend_from_slice(b"\n$EndMeshFormat\n$Nodes\n");
    let mut t =
        format!("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n{} {n} {lo} {hi}\n", blocks.len());
    for v in [blocks.len() as u64, n as u64, lo, hi] {
        b.extend_from_slice(&v.to_le_bytes());
    }
    for (tags, pts) in blocks {
        for v in [2i32, 1, 0] {
            b.extend_from_slice(&v.to_le_bytes());
        }
        b.extend_from_slice(&(tags.len() as u64).to_le_bytes());
        t += &format!("2 1 0 {}\n", tags.len());
        for &tag in tags.iter() {
            b.extend_from_slice(&tag.to_le_bytes());
            t += &format!("{tag}\n");
        }
        for p in pts.iter() {
            for c in p {
                b.extend_from_slice(&c.to_le_bytes());
            }
            t += &format!("{} {} {}\n", p[0], p[1], p[2]);
        }
    }
    b.extend_from_slice(b"\n$EndNodes\n$Elements\n");
    t += &format!(
        "$EndNodes\n$Elements\n1 1 1 1\n2 1 2 1\n1 {} {} {}\n$EndElements\n",
        tri[0], tri[1], tri[2]
    );
    for v in [1u64, 1, 1, 1] {
        b.extend_from_slice(&v.to_le_bytes());
    }
    for v in [2i32, 1, 2] {
        b.extend_from_slice(&v.to_le_bytes());
    }
    b.extend_from_slice(&1u64.to_le_bytes());
    b.extend_from_slice(&1u64.to_le_bytes());
    for v in tri {
        b.extend_from_slice(&v.to_le_bytes());
    }
    b.extend_from_slice(b"\n$EndElements\n");
    let head = format!("$NodeData\n1\n\"h\"\n1\n0.0\n3\n0\n1\n{}\n", data.len());
    b.extend_from_slice(head.as_bytes());
    t += &head;
    for &tag in data {
        b.extend_from_slice(&(tag as i32).to_le_bytes());
        b.extend_from_slice(&(10.0 * tag as f64).to_le_bytes());
        t += &format!("{tag} {}\n", 10.0 * tag as f64);
    }
    b.extend_from_slice(b"\n$EndNodeData\n");
    t += "$EndNodeData\n";
    (b, t)
}

/// Node blocks (tags, coordinates), the announced tag range, and the tags of a $NodeData.
type NodeLayout<'a> = (Vec<(&'a [u64], Vec<[f64; 3]>)>, u64, u64, Vec<u64>);

#[test]
fn binary_41_node_blocks_out_of_tag_order() {
    let p = |x: f64| [x, 2.0 * x, 0.0];
    // Tags 1..=4 over three blocks in another order (as Gmsh writes entities), then tags
    // that are not a full range, a tag outside the announced range, and data in another
    // order or with a node left out: each read as its ASCII twin reads.
    let cases: [NodeLayout; 4] = [
        (
            vec![(&[3, 4], vec![p(3.0), p(4.0)]), (&[1], vec![p(1.0)]), (&[2], vec![p(2.0)])],
            1,
            4,
            vec![1, 2, 3, 4],
        ),
        (
            vec![(&[30, 40], vec![p(3.0), p(4.0)]), (&[10, 20], vec![p(1.0), p(2.0)])],
            10,
            40,
            vec![40, 10, 30],
        ),
        (
            vec![(&[3, 9], vec![p(3.0), p(9.0)]), (&[1, 2], vec![p(1.0), p(2.0)])],
            1,
            4,
            vec![9, 1, 2, 3],
        ),
        (
            vec![(&[2, 1], vec![p(2.0), p(1.0)]), (&[4, 3], vec![p(4.0), p(3.0)])],
            1,
            4,
            vec![4, 3, 2],
        ),
    ];
    for (i, (blocks, lo, hi, data)) in cases.iter().enumerate() {
        let blocks: Vec<(&[u64], &[[f64; 3]])> =
            blocks.iter().map(|(t, q)| (*t, q.as_slice())).collect();
        let tri = [blocks[0].0[0], blocks[1].0[0], blocks[0].0[1]];
        let (bin, text) = bin41_nodes(&blocks, *lo, *hi, tri, data);
        let a = read_msh(&bin).unwrap_or_else(|e| panic!("case {i}: {e}"));
        let b = read_msh(text.as_bytes()).unwrap_or_else(|e| panic!("case {i} (ASCII): {e}"));
        assert_points_bitwise(&a, &b, &format!("case {i}"));
        assert_eq!(cell_list(&a), cell_list(&b), "case {i}");
        assert_data_bitwise(&a.point_data, &b.point_data, &format!("case {i}"));
        // Points in tag order.
        assert!(a.points.windows(2).all(|w| w[0][0] < w[1][0]), "case {i}: {:?}", a.points);
    }
}

#[test]
fn binary_41_duplicate_node_tag_across_blocks() {
    let p = [0.0, 0.0, 0.0];
    // Three tags announced as 1..=3, but tag 2 twice and 3 never.
    let (bin, _) = bin41_nodes(&[(&[1, 2], &[p, p]), (&[2], &[p])], 1, 3, [1, 2, 1], &[]);
    let e = read_msh(&bin).unwrap_err();
    assert!(e.to_string().contains("node tag 2 is defined twice"), "{e}");
    // Where the second block starts: after the header line, the 4 size_t of the
    // section header and the first block (a 20-byte header, 2 tags, 2 points).
    let nodes = bin.windows(7).position(|w| w == b"$Nodes\n").unwrap() + 7;
    assert_eq!(e.at, Some(Position::Byte((nodes + 32 + 20 + 16 + 48) as u64)));
}

// ---------------------------------------------------------------------------------
// Malformed inputs: each a clear error with its position, never a panic

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
fn malformed_truncated_ascii() {
    let full = format!("{HEAD41}{SQUARE41}");
    for cut in [10, 40, 120, 200, full.len() - 5] {
        let e = err(&full.as_bytes()[..cut]);
        assert!(matches!(e.at, Some(Position::Line(_))), "{e}");
    }
}

#[test]
fn malformed_truncated_binary() {
    smartmesh_test_support::require_public_fixtures!();
    let bytes = std::fs::read(common::public_fixture("gmsh/square_hole.v41_binary.msh")).unwrap();
    for cut in [100, 700, 5000, bytes.len() / 2, bytes.len() - 20] {
        let e = err(&bytes[..cut]);
        assert!(matches!(e.at, Some(Position::Byte(_))), "{e}");
    }
    let bytes = std::fs::read(common::public_fixture("gmsh/square_hole.v22_binary.msh")).unwrap();
    for cut in [200, 3000, bytes.len() / 2, bytes.len() - 20] {
        let e = err(&bytes[..cut]);
        assert!(matches!(e.at, Some(Position::Byte(_))), "{e}");
    }
}

#[test]
fn malformed_node_count_41() {
    let e = err_text(&format!("{HEAD41}{}", SQUARE41.replace("1 5 1 5\n", "1 6 1 6\n")));
    assert!(e.to_string().contains("announces 6 nodes, but its blocks hold 5"), "{e}");
}

#[test]
fn malformed_element_count_22() {
    let e = err_text(&format!("{HEAD22}$Nodes\n3\n1 0 0 0\n2 1 0 0\n3 0 1 0\n$EndNodes\n$Elements\n2\n1 2 2 1 1 1 2 3\n$EndElements\n"));
    assert_eq!(e.at, Some(Position::Line(13)), "{e}");
    let e = err_text(&format!("{HEAD22}$Nodes\n4\n1 0 0 0\n2 1 0 0\n3 0 1 0\n$EndNodes\n$Elements\n1\n1 2 2 1 1 1 2 3\n$EndElements\n"));
    assert_eq!(e.at, Some(Position::Line(9)), "{e}");
}

#[test]
fn malformed_unknown_node_tag() {
    let e = err_text(&format!("{HEAD41}{}", SQUARE41.replace("2 1 3 4\n", "2 1 3 44\n")));
    assert_eq!(e.at, Some(Position::Line(26)), "{e}");
    assert!(e.to_string().contains("element 2 refers to node 44"), "{e}");
}

#[test]
fn malformed_wrong_number_of_nodes_on_an_element_line() {
    let e = err_text(&format!("{HEAD41}{}", SQUARE41.replace("1 1 2 3\n", "1 1 2\n")));
    assert!(e.to_string().contains("3 node tags after element 1"), "{e}");
    let e = err_text(&format!("{HEAD22}$Nodes\n3\n1 0 0 0\n2 1 0 0\n3 0 1 0\n$EndNodes\n$Elements\n1\n1 2 2 1 1 1 2 3 3\n$EndElements\n"));
    assert_eq!(e.at, Some(Position::Line(12)), "{e}");
}

#[test]
fn malformed_nan_coordinate_ascii() {
    let e = err_text(&format!("{HEAD41}{}", SQUARE41.replace("1 1 0\n", "1 nan 0\n")));
    assert!(matches!(e.kind, ErrorKind::NonFinite { .. }), "{e}");
    assert_eq!(e.at, Some(Position::Line(18)));
}

#[test]
fn malformed_nan_coordinate_binary() {
    let mut bytes = gmsh::write(&small_mesh(), &opts(GmshVersion::V22, true)).unwrap().main;
    // The first node record follows `$Nodes\n6\n`; its x is 4 bytes in.
    let start = bytes.windows(9).position(|w| w == b"$Nodes\n6\n").unwrap() + 9;
    bytes[start + 4..start + 12].copy_from_slice(&f64::NAN.to_le_bytes());
    let e = err(&bytes);
    assert!(matches!(e.kind, ErrorKind::NonFinite { .. }), "{e}");
    assert_eq!(e.at, Some(Position::Byte(start as u64 + 4)));
}

#[test]
fn malformed_huge_node_count() {
    let e =
        err_text(&format!("{HEAD41}$Nodes\n1 1000000000000000 1 1000000000000000\n$EndNodes\n"));
    assert!(matches!(e.kind, ErrorKind::ImplausibleCount { .. }), "{e}");
    let e = err_text(&format!("{HEAD22}$Nodes\n1000000000000000\n1 0 0 0\n$EndNodes\n"));
    assert!(matches!(e.kind, ErrorKind::ImplausibleCount { .. }), "{e}");
    // Binary: a size_t count of 2^60 nodes in one block.
    let mut b = gmsh::write(&small_mesh(), &opts(GmshVersion::V41, true)).unwrap().main;
    let start = b.windows(7).position(|w| w == b"$Nodes\n").unwrap() + 7;
    b[start + 8..start + 16].copy_from_slice(&(1u64 << 60).to_le_bytes());
    let e = err(&b);
    assert!(matches!(e.kind, ErrorKind::ImplausibleCount { .. }), "{e}");
    assert_eq!(e.at, Some(Position::Byte(start as u64 + 8)));
}

#[test]
fn malformed_byte_swapped_endianness_marker() {
    let mut b = b"$MeshFormat\n4.1 1 8\n".to_vec();
    b.extend_from_slice(&1i32.to_be_bytes());
    b.extend_from_slice(b"\n$EndMeshFormat\n");
    let e = err(&b);
    assert_eq!(e.at, Some(Position::Byte(20)));
    assert!(e.to_string().contains("big-endian"), "{e}");
    let mut b = b"$MeshFormat\n2.2 1 8\n".to_vec();
    b.extend_from_slice(&7i32.to_le_bytes());
    b.extend_from_slice(b"\n$EndMeshFormat\n");
    let e = err(&b);
    assert!(e.to_string().contains("endianness marker"), "{e}");
}

#[test]
fn malformed_unknown_section() {
    // Skipped as Gmsh skips it, but only up to its `$End` line, which must be there.
    let e = err_text(&format!("{HEAD41}$Nodez\n0 0 0 0\n$EndNodes\n"));
    assert_eq!(e.at, Some(Position::Line(4)));
    assert!(e.to_string().contains("`$Nodez`"), "{e}");
}

#[test]
fn malformed_byte_order_mark_is_named() {
    let e = err_text(&format!("\u{feff}{HEAD41}"));
    assert_eq!(e.at, Some(Position::Line(1)));
    assert!(e.to_string().contains("a byte order mark (U+FEFF)"), "{e}");
}

#[test]
fn malformed_end_line_without_its_section() {
    let e = err_text(&format!("{HEAD41}{SQUARE41}$EndNodes\n"));
    assert_eq!(e.at, Some(Position::Line(28)));
    assert!(e.to_string().contains("`$EndNodes`, which closes no open section"), "{e}");
}

/// Gmsh's format documentation: "any section with an unrecognized header is simply
/// ignored" (so `$Comment`, or a tool's own section, in any version and encoding).
#[test]
fn unknown_sections_are_skipped_as_gmsh_does() {
    let extra = "$Comment\nwritten by hand\n$EndComment\n$Foo\n1 2 3 $Nodes\n$EndFoox\n$EndFoo\n";
    let m = read_msh(format!("{HEAD41}{extra}{SQUARE41}{extra}").as_bytes()).unwrap();
    assert_eq!(m, read_msh(format!("{HEAD41}{SQUARE41}").as_bytes()).unwrap());
    let v22 = "$Nodes\n3\n1 0 0 0\n2 1 0 0\n3 0 1 0\n$EndNodes\n$Elements\n1\n1 2 2 7 7 1 2 3\n$EndElements\n";
    let m = read_msh(format!("{HEAD22}{extra}{v22}{extra}").as_bytes()).unwrap();
    assert_eq!(m, read_msh(format!("{HEAD22}{v22}").as_bytes()).unwrap());
    // Binary files, with binary bytes inside the unknown section.
    for (version, binary) in all_options().into_iter().filter(|o| o.1) {
        let bytes = gmsh::write(&small_mesh(), &opts(version, binary)).unwrap().main;
        let end = b"$EndMeshFormat\n";
        let at = bytes.windows(end.len()).position(|w| w == end).unwrap() + end.len();
        let mut with = bytes[..at].to_vec();
        with.extend_from_slice(b"$Blob\n\x00\x01\xff$EndBlo\n\x07\n$EndBlob\n");
        with.extend_from_slice(&bytes[at..]);
        assert_eq!(read_msh(&with).unwrap(), read_msh(&bytes).unwrap(), "{version:?}");
    }
}

#[test]
fn malformed_optional_section_without_its_end() {
    let e = err_text(&format!("{HEAD41}$Comments\nsome text\n$EndComment\n"));
    assert_eq!(e.at, Some(Position::Line(4)));
    assert!(e.to_string().contains("no `$EndComments`"), "{e}");
}

#[test]
fn a_tetrahedron_is_read_as_one() {
    let m = read_msh(format!("{HEAD22}$Nodes\n4\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n$EndNodes\n$Elements\n1\n1 4 2 1 1 1 2 3 4\n$EndElements\n").as_bytes()).unwrap();
    assert_eq!(m.blocks.len(), 1);
    assert_eq!(m.blocks[0].kind, CellKind::Tetra);
    assert_eq!(m.blocks[0].nodes, vec![0, 1, 2, 3]);
}

#[test]
fn malformed_third_order_element() {
    let e = err_text(&format!("{HEAD41}$Nodes\n0 0 0 0\n$EndNodes\n$Elements\n1 1 1 1\n2 1 21 1\n1 1 2 3 4 5 6 7 8 9 10\n$EndElements\n"));
    assert!(e.to_string().contains("type 21 (10-node third-order triangle)"), "{e}");
}

#[test]
fn malformed_duplicate_node_tag() {
    let e = err_text(&format!("{HEAD22}$Nodes\n3\n1 0 0 0\n2 1 0 0\n2 0 1 0\n$EndNodes\n$Elements\n1\n1 1 2 1 1 1 2\n$EndElements\n"));
    assert!(e.to_string().contains("node tag 2 is defined twice"), "{e}");
}

#[test]
fn malformed_duplicate_element_tag() {
    let e = err_text(&format!("{HEAD22}$Nodes\n3\n1 0 0 0\n2 1 0 0\n3 0 1 0\n$EndNodes\n$Elements\n3\n2 1 2 1 1 1 2\n1 1 2 1 1 2 3\n2 1 2 1 1 3 1\n$EndElements\n"));
    assert!(e.to_string().contains("element tag 2 is used twice"), "{e}");
}

#[test]
fn malformed_zero_tags() {
    let e = err_text(&format!(
        "{HEAD41}{}",
        SQUARE41.replace("\n1\n2\n3\n4\n5\n", "\n1\n2\n0\n4\n5\n")
    ));
    assert!(e.to_string().contains("0 is reserved"), "{e}");
    let e = err_text(&format!("{HEAD41}{}", SQUARE41.replace("1 1 2 3\n", "0 1 2 3\n")));
    assert!(e.to_string().contains("0 is reserved"), "{e}");
}

#[test]
fn malformed_missing_mesh_format() {
    let e = err_text("$Nodes\n0\n$EndNodes\n");
    assert!(e.to_string().contains("`$MeshFormat`"), "{e}");
    let e = err_text("$NOD\n0\n$ENDNOD\n");
    assert!(e.to_string().contains("MSH version 1"), "{e}");
    let e = err(b"");
    assert!(matches!(e.kind, ErrorKind::UnexpectedEof { .. }), "{e}");
}

#[test]
fn malformed_unsupported_versions() {
    for v in ["4 0 8", "4.0 0 8", "3.0 0 8", "1.0 0 8", "five 0 8"] {
        let e = err_text(&format!("$MeshFormat\n{v}\n$EndMeshFormat\n"));
        assert_eq!(e.at, Some(Position::Line(2)), "{v}: {e}");
    }
    let e = err_text("$MeshFormat\n4.1 2 8\n$EndMeshFormat\n");
    assert!(e.to_string().contains("file type"), "{e}");
    let e = err_text("$MeshFormat\n4.1 1 3\n");
    assert!(e.to_string().contains("size_t of 3 bytes"), "{e}");
}

#[test]
fn malformed_physical_name_without_quotes() {
    let e = err_text(&format!("{HEAD41}$PhysicalNames\n1\n2 1 Domain\n$EndPhysicalNames\n"));
    assert_eq!(e.at, Some(Position::Line(6)));
    assert!(e.to_string().contains("double quotes"), "{e}");
}

#[test]
fn malformed_node_data_for_an_unknown_node() {
    let e = err_text(&format!(
        "{HEAD41}{SQUARE41}$NodeData\n1\n\"T\"\n1\n0\n3\n0\n1\n1\n9 1.0\n$EndNodeData\n"
    ));
    assert!(e.to_string().contains("node 9, which the mesh does not have"), "{e}");
    assert_eq!(e.at, Some(Position::Line(37)));
}

#[test]
fn malformed_node_data_without_its_integer_tags() {
    let e = err_text(&format!(
        "{HEAD41}{SQUARE41}$NodeData\n1\n\"T\"\n1\n0\n1\n0\n1 1.0\n$EndNodeData\n"
    ));
    assert!(e.to_string().contains("at least 3 integer tags"), "{e}");
}

#[test]
fn malformed_node_data_with_too_few_values() {
    let e = err_text(&format!(
        "{HEAD41}{SQUARE41}$NodeData\n1\n\"T\"\n1\n0\n3\n0\n3\n2\n1 1 2 3\n2 1 2\n$EndNodeData\n"
    ));
    assert!(e.to_string().contains("data value"), "{e}");
}

#[test]
fn malformed_view_with_a_huge_number_of_components() {
    let e = err_text(&format!(
        "{HEAD41}{SQUARE41}$ElementData\n1\n\"q\"\n1\n0\n3\n0\n1000000000000\n0\n$EndElementData\n"
    ));
    assert!(matches!(e.kind, ErrorKind::ImplausibleCount { .. }), "{e}");
    assert_eq!(e.at, Some(Position::Line(35)), "{e}");
}

#[test]
fn malformed_element_block_count_binary_22() {
    let mut b = gmsh::write(&small_mesh(), &opts(GmshVersion::V22, true)).unwrap().main;
    let start = b.windows(12).position(|w| w == b"$Elements\n6\n").unwrap() + 12;
    // The first block header says 99 elements follow.
    b[start + 4..start + 8].copy_from_slice(&99i32.to_le_bytes());
    let e = err(&b);
    assert_eq!(e.at, Some(Position::Byte(start as u64 + 4)), "{e}");
}

#[test]
fn malformed_entity_defined_twice() {
    let e = err_text(&format!("{HEAD41}$Entities\n2 0 0 0\n1 0 0 0 0\n1 1 0 0 0\n$EndEntities\n"));
    assert!(e.to_string().contains("point 1 is defined twice"), "{e}");
    assert_eq!(e.at, Some(Position::Line(7)));
}

#[test]
fn damaged_fixtures_give_errors_not_panics() {
    smartmesh_test_support::require_public_fixtures!();
    // The two smaller models in all encodings, damaged at 80 places each: a byte
    // replaced, or the file cut there.
    for model in ["square_hole", "two_domains_quads"] {
        for enc in ENCODINGS {
            let bytes =
                std::fs::read(common::public_fixture(&format!("gmsh/{model}.{enc}.msh"))).unwrap();
            let step = (bytes.len() / 80).max(1);
            for i in (0..bytes.len()).step_by(step) {
                for b in [b'9', 0xff, b'\n'] {
                    let mut d = bytes.clone();
                    d[i] = b;
                    if let Err(e) = read_msh(&d) {
                        assert!(e.at.is_some(), "{model}.{enc} byte {i}: {e}");
                    }
                }
                let _ = read_msh(&bytes[..i]);
            }
        }
    }
}

#[test]
fn a_data_only_file_is_its_node_views_indexed_by_tag() {
    // Gmsh's data-only file: views, no mesh; node tags out of order and one missing.
    let text = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$InterpolationScheme\n\"I\"\n1\n1 1\n0\n$EndInterpolationScheme\n$NodeData\n1\n\"h\"\n1\n0.0\n3\n0\n1\n3\n3 0.3\n1 0.1\n4 0.4\n$EndNodeData\n";
    let ctx = ReadContext::alone("msh");
    let gmsh::MshContent::NodeData(data) = gmsh::read_mesh_or_data(text.as_bytes(), &ctx).unwrap()
    else {
        panic!("read as a mesh")
    };
    let h = &data.arrays["h"];
    assert_eq!(h.len(), 4);
    assert_eq!(h.values[0], 0.1);
    assert!(h.values[1].is_nan());
    assert_eq!((h.values[2], h.values[3]), (0.3, 0.4));
    assert_eq!(data.entries["h"], 3);
    // As a mesh it is refused, saying what it is.
    let e = read_msh(text.as_bytes()).unwrap_err().to_string();
    assert!(e.contains("data-only"), "{e}");
    // A mesh section after the views: neither a mesh nor a data-only file.
    let both = format!("{text}$Nodes\n0 0 0 0\n$EndNodes\n");
    let e = gmsh::read_mesh_or_data(both.as_bytes(), &ctx).unwrap_err().to_string();
    assert!(e.contains("$Nodes section after $NodeData"), "{e}");
    // A tag far beyond the entries does not make a huge array.
    let far = text.replace("4 0.4", "4000000000 0.4");
    let e = gmsh::read_mesh_or_data(far.as_bytes(), &ctx).unwrap_err().to_string();
    assert!(e.contains("view `h`"), "{e}");
    // A file with a mesh reads as the mesh, as `read` does.
    let mut m = TaggedMesh::new();
    m.points = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
    m.block_mut(CellKind::Triangle).push(&[0, 1, 2], 1, 1);
    let bytes = smartmesh_formats::write_bytes(Format::Gmsh, &m, &WriteOptions::default()).unwrap();
    let gmsh::MshContent::Mesh(back) = gmsh::read_mesh_or_data(&bytes.main, &ctx).unwrap() else {
        panic!("read as data")
    };
    assert_eq!(back, read_msh(&bytes.main).unwrap());
}

// ---------------------------------------------------------------------------------
// Properties

#[cfg(feature = "proptest")]
mod properties {
    use super::*;
    use proptest::prelude::*;
    use smartmesh_formats::arbitrary::{arb_tagged_mesh, MeshFeatures};

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(64))]

        /// Geometrical tags equal to physical ones: every encoding is an identity.
        #[test]
        fn write_read_identity(m in arb_tagged_mesh(MeshFeatures { geometrical: false, ..MeshFeatures::ALL })) {
            for (v, bin) in all_options() {
                let (w, back) = common::roundtrip(Format::Gmsh, "msh", &m, &opts(v, bin));
                assert_same_mesh(&m, &back, &format!("{v:?} binary={bin}"));
                prop_assert!(w.report.dropped.is_empty(), "{:?}", w.report.dropped);
                let again = gmsh::write(&back, &opts(v, bin)).unwrap();
                prop_assert!(again.main == w.main, "{v:?} binary={bin}: write(read(write(m))) differs");
            }
        }

        /// Independent geometrical tags: 2.2 holds them; 4.1 keeps physical tags and
        /// moves cells to new entities only where one entity holds several groups.
        #[test]
        fn write_read_with_independent_geometrical_tags(m in arb_tagged_mesh(MeshFeatures::ALL)) {
            for bin in [false, true] {
                let (_, back) = common::roundtrip(Format::Gmsh, "msh", &m, &opts(GmshVersion::V22, bin));
                assert_same_mesh(&m, &back, "2.2");
                let (w, back) = common::roundtrip(Format::Gmsh, "msh", &m, &opts(GmshVersion::V41, bin));
                assert_points_bitwise(&m, &back, "4.1");
                assert_eq!(back.tag_names, m.tag_names);
                let (a, b) = (cell_list(&m), cell_list(&back));
                prop_assert_eq!(a.len(), b.len());
                let mut origin: BTreeMap<(u8, i32), (i32, i32)> = BTreeMap::new();
                for (x, y) in a.iter().zip(&b) {
                    prop_assert_eq!((x.0, &x.1, x.2), (y.0, &y.1, y.2));
                    // The new entity comes from one (geometrical, physical) pair.
                    let o = origin.entry((x.0.dim(), y.3)).or_insert((x.3, x.2));
                    prop_assert_eq!(*o, (x.3, x.2));
                    prop_assert_eq!(back.entities[&(x.0.dim(), y.3)].first().copied().unwrap_or(0), y.2);
                }
                let moved = a.iter().zip(&b).any(|(x, y)| x.3 != y.3);
                prop_assert_eq!(moved, !w.report.dropped.is_empty(), "{:?}", w.report.dropped);
                assert_data_bitwise(&m.point_data, &back.point_data, "4.1");
            }
        }
    }
}

// ---------------------------------------------------------------------------------
// Speed (release, one-off): `cargo test --release -p smartmesh-formats --test gmsh -- --ignored --nocapture`

/// A structured triangulation of the unit square: `n * n` quads split in two, with its
/// boundary lines, tagged like a Gmsh model.
fn big_mesh(n: usize) -> TaggedMesh {
    let mut m = TaggedMesh::new();
    let h = 1.0 / n as f64;
    for j in 0..=n {
        for i in 0..=n {
            m.points.push([i as f64 * h + 0.1 * h * ((i * j) % 7) as f64 / 7.0, j as f64 * h, 0.0]);
        }
    }
    let id = |i: usize, j: usize| j * (n + 1) + i;
    let mut l = CellBlock::new(CellKind::Line);
    for i in 0..n {
        l.push(&[id(i, 0), id(i + 1, 0)], 1, 1);
        l.push(&[id(i, n), id(i + 1, n)], 1, 3);
    }
    let mut t = CellBlock::new(CellKind::Triangle);
    for j in 0..n {
        for i in 0..n {
            t.push(&[id(i, j), id(i + 1, j), id(i + 1, j + 1)], 2, 1);
            t.push(&[id(i, j), id(i + 1, j + 1), id(i, j + 1)], 2, 1);
        }
    }
    m.blocks = vec![l, t];
    m.tag_names.insert((1, 1), "Walls".into());
    m.tag_names.insert((2, 2), "Domain".into());
    m
}

#[test]
#[ignore = "speed check, release build only"]
fn bench_against_mshio() {
    use std::time::Instant;
    let m = big_mesh(866); // 751,689 nodes, 1,499,912 triangles
    println!("mesh: {} nodes, {} triangles", m.points.len(), m.num_cells_of(CellKind::Triangle));
    let dir = std::env::var("GMSH_BENCH_DIR").ok();
    let best = |f: &mut dyn FnMut()| {
        let mut t = f64::MAX;
        for _ in 0..3 {
            let s = Instant::now();
            f();
            t = t.min(s.elapsed().as_secs_f64());
        }
        t
    };
    for (v, bin) in all_options() {
        let o = opts(v, bin);
        let mut bytes = Vec::new();
        let tw = best(&mut || bytes = gmsh::write(&m, &o).unwrap().main);
        let mut back = TaggedMesh::new();
        let tr = best(&mut || back = read_msh(&bytes).unwrap());
        assert_same_mesh(&m, &back, "bench");
        let tc = best(&mut || {
            let c = bytes.clone();
            std::hint::black_box(c);
        });
        println!(
            "{v:?} binary={bin}: {:.1} MB, write {tw:.3} s, read {tr:.3} s, memory copy {tc:.3} s",
            bytes.len() as f64 / 1e6
        );
        if v == GmshVersion::V41 {
            let tm = best(&mut || {
                let f = mshio::parse_msh_bytes(&bytes).map_err(|e| format!("{e}")).unwrap();
                std::hint::black_box(f);
            });
            println!("    mshio 0.4 parse of the same bytes: {tm:.3} s");
        }
        if let Some(d) = &dir {
            let name = format!(
                "{d}/bench_{}_{}.msh",
                if v == GmshVersion::V41 { "41" } else { "22" },
                if bin { "bin" } else { "ascii" }
            );
            std::fs::write(name, &bytes).unwrap();
        }
    }
    // How mshio reports an error, for comparison: a node tag cut in the middle.
    let bytes = gmsh::write(&small_mesh(), &opts(GmshVersion::V41, false)).unwrap().main;
    let mut bad = bytes.clone();
    let at = bad.windows(4).position(|w| w == b"\n5\n6").unwrap() + 1;
    bad[at] = b'x';
    println!(
        "mshio error:     {}",
        mshio::parse_msh_bytes(&bad).map(|_| ()).map_err(|e| format!("{e}")).unwrap_err()
    );
    println!("smartmesh error: {}", read_msh(&bad).unwrap_err());
    // And on headers with an odd data size.
    for head in [
        "$MeshFormat\n4.1 0 300\n$EndMeshFormat\n",
        "$MeshFormat\n4.1 1 3\n\x01\x00\x00\x00\n$EndMeshFormat\n",
    ] {
        let r = std::panic::catch_unwind(|| mshio::parse_msh_bytes(head.as_bytes()).is_ok());
        println!("mshio on {head:?}: {}", if r.is_err() { "panicked" } else { "returned" });
        println!("smartmesh: {:?}", read_msh(head.as_bytes()).err().map(|e| e.to_string()));
    }
}

/// Binary `$NodeData` tables are taken whole and converted in one pass, and a view in
/// node order becomes the point array as read: a NaN is kept (a data array may hold
/// NaN), an unknown node tag is still refused at its byte, in both versions, and a view
/// in another order is still put in node order.
#[test]
fn binary_node_data_is_checked_value_by_value() {
    let mut m = small_mesh();
    m.cell_data.clear();
    let marker = 1234.5678f64;
    m.point_data.get_mut("metric").unwrap().values[9 * 3 + 4] = marker;
    for version in [GmshVersion::V22, GmshVersion::V41] {
        let bytes = gmsh::write(&m, &opts(version, true)).unwrap().main;
        let back = read_msh(&bytes).unwrap();
        assert_data_bitwise(&back.point_data, &m.point_data, &format!("{version:?}"));
        let at = memchr::memmem::find(&bytes, &marker.to_le_bytes()).unwrap();
        let mut bad = bytes.clone();
        bad[at..at + 8].copy_from_slice(&f64::NAN.to_le_bytes());
        let nan = read_msh(&bad).unwrap_or_else(|e| panic!("{version:?}: {e}"));
        let values = &nan.point_data["metric"].values;
        assert!(values[9 * 3 + 4].is_nan(), "{version:?}");
        assert_eq!(values.iter().filter(|v| v.is_nan()).count(), 1, "{version:?}");
        // The entry's node tag (4 + 8 * 4 bytes before the value): 4 -> 99.
        let tag_at = at - 8 * 4 - 4;
        assert_eq!(bytes[tag_at..tag_at + 4], 4i32.to_le_bytes(), "{version:?}");
        let mut bad = bytes.clone();
        bad[tag_at..tag_at + 4].copy_from_slice(&99i32.to_le_bytes());
        let e = read_msh(&bad).unwrap_err();
        assert!(
            e.to_string().contains("node 99, which the mesh does not have"),
            "{version:?}: {e}"
        );
        assert_eq!(e.at, Some(Position::Byte(tag_at as u64)), "{version:?}: {e}");
        // Entries 3 and 4 swapped (tags and values): the array is still in node order.
        let rec = 4 + 8 * 9;
        let (a, b) = (tag_at, tag_at + rec);
        let mut swapped = bytes.clone();
        swapped[a..a + rec].copy_from_slice(&bytes[b..b + rec]);
        swapped[b..b + rec].copy_from_slice(&bytes[a..a + rec]);
        let back = read_msh(&swapped).unwrap();
        assert_data_bitwise(&back.point_data, &m.point_data, &format!("{version:?} swapped"));
    }
}

/// Cells as (kind, tags, coordinates of their nodes to 1e-12), sorted: a mesh's cells
/// whatever the numbering of its nodes and cells (and the last digit of ASCII numbers).
fn placed_cells(m: &TaggedMesh) -> Vec<(CellKind, i32, i32, Vec<[i64; 3]>)> {
    let mut v: Vec<_> = m
        .cells()
        .map(|(k, nodes, p, g)| {
            let at = nodes
                .iter()
                .map(|&n| m.points[n as usize].map(|c| (c * 1e12).round() as i64))
                .collect();
            (k, p, g, at)
        })
        .collect();
    v.sort();
    v
}

/// A partitioned MSH 4.1 file (after Gmsh's tutorial t21, `fixtures/make_partitioned.py`):
/// its cells lie on the partitioned entities of `$PartitionedEntities`, whose physical
/// tags and parents are read, so that it reads as the MSH 2.2 file of the same mesh does
/// (physical groups Left, Right, Bottom; the parent entity as geometrical tag), ASCII and
/// binary; the report says the partitions were merged.
#[test]
fn a_partitioned_41_file_keeps_its_physical_groups() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../fixtures");
    let read = |name: &str| {
        smartmesh_formats::read_path_reported(&dir.join(name), None)
            .unwrap_or_else(|e| panic!("{e}"))
    };
    let note = "3 partitions read as one mesh (which partition each cell was in is not kept)";
    let (v22, report) = read("partitioned_t21.v22.msh");
    assert_eq!(report.notes, vec![note]);
    let per_tag = common::counts_per_tag(&v22);
    assert_eq!(
        per_tag,
        counts(&[("line", 10, 5), ("triangle", 100, 66), ("triangle", 200, 66)]),
        "{per_tag:?}"
    );
    for name in
        ["partitioned_t21.msh", "partitioned_t21_binary.msh", "partitioned_t21_binary.v22.msh"]
    {
        let (m, report) = read(name);
        // Gmsh numbers nodes otherwise in 2.2: cells compared by their corners' places.
        assert_eq!(placed_cells(&m), placed_cells(&v22), "{name}");
        assert_eq!(m.tag_names, v22.tag_names, "{name}");
        if !name.ends_with("v22.msh") {
            assert_eq!(m.entities.get(&(2, 1)), Some(&vec![100]), "{name}");
        }
        assert_eq!(report.notes, vec![note], "{name}");
    }
}

/// A view with `nan` and `inf` values (as Gmsh prints them) is read with them, ASCII and
/// binary: a data array may hold NaN, refused only where it is used.
#[test]
fn views_keep_nan_and_infinities() {
    let file = format!(
        "{HEAD22}$Nodes\n3\n1 0 0 0\n2 1 0 0\n3 0 1 0\n$EndNodes\n$Elements\n1\n1 2 2 1 1 1 2 3\n$EndElements\n\
$NodeData\n1\n\"u\"\n1\n0\n3\n0\n1\n3\n1 nan\n2 -inf\n3 2.5\n$EndNodeData\n"
    );
    let m = read_msh(file.as_bytes()).unwrap();
    let u = &m.point_data["u"].values;
    assert!(u[0].is_nan() && u[1] == f64::NEG_INFINITY && u[2] == 2.5, "{u:?}");
    for version in [GmshVersion::V22, GmshVersion::V41] {
        let w = gmsh::write(&m, &opts(version, true)).unwrap();
        let back = read_msh(&w.main).unwrap();
        assert_eq!(back.point_data["u"].values[2], 2.5, "{version:?}");
    }
}
