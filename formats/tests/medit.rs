//! Medit .mesh/.meshb with .sol/.solb: MMG's files, round trips, every binary version
//! and byte order, property tests and malformed input.

use smartmesh_formats::{GmshWrite, MeditWrite, VtkWrite};
use smartmesh_test_support::formats as common;

use std::collections::BTreeMap;

use common::{counts_per_tag, read_file, roundtrip};
use proptest::prelude::*;
use smartmesh_formats::arbitrary::{arb_tagged_mesh, MeshFeatures};
use smartmesh_formats::medit::{read_sol, write_sol};
use smartmesh_formats::{
    read_bytes, sym2_to_tensor9, write_bytes, CellBlock, CellKind, DataArray, ErrorKind, Format,
    Layout, MemorySiblings, Position, ReadContext, TaggedMesh, WriteOptions,
};

fn opts(main: &str) -> WriteOptions {
    WriteOptions { main_name: Some(main.to_string()), ..Default::default() }
}

fn counts(entries: &[(&str, i32, usize)]) -> BTreeMap<(String, i32), usize> {
    entries.iter().map(|&(k, t, n)| ((k.to_string(), t), n)).collect()
}

fn read_alone(bytes: &[u8], ext: &str) -> smartmesh_formats::Result<TaggedMesh> {
    read_bytes(Format::Medit, bytes, &ReadContext::alone(ext))
}

fn read_with_sol(
    mesh: &[u8],
    ext: &str,
    sol_ext: &str,
    sol: &[u8],
) -> smartmesh_formats::Result<TaggedMesh> {
    let sib = MemorySiblings { files: BTreeMap::from([(sol_ext.to_string(), sol.to_vec())]) };
    read_bytes(Format::Medit, mesh, &ReadContext { siblings: &sib, extension: ext.into() })
}

// -----------------------------------------------------------------------------------------
// Public fixtures. The expected numbers were counted with a short Python script that splits
// the ASCII files into tokens and tallies the last field of each Vertices/Edges/Triangles
// record, and reads the .meshb with `struct` (keyword code, next offset, count, then
// `<ddi` vertices); nothing of smartmesh is involved.
// -----------------------------------------------------------------------------------------

#[test]
#[allow(clippy::excessive_precision)] // the values as the file prints them
fn square_hole_input_with_metric() {
    smartmesh_test_support::require_public_fixtures!();
    let m = read_file("medit/square_hole_input.mesh");
    assert_eq!(m.coordinate_dim, 2);
    assert_eq!(m.points.len(), 435);
    assert_eq!(
        counts_per_tag(&m),
        counts(&[("line", 1, 52), ("line", 2, 44), ("triangle", 3, 774)])
    );
    // Every vertex reference is 0: no `medit:ref` array.
    assert!(!m.point_data.contains_key("medit:ref"));
    assert!(m.point_sets.is_empty());
    let metric = &m.point_data["metric"];
    // Kept packed as the file has it: m11 m12 m22.
    assert_eq!((metric.components, metric.layout), (3, Layout::Symmetric2));
    assert!(metric.is_tensor());
    assert_eq!(metric.len(), 435);
    // "69.807785718567544 -28.785867635430975 69.80778571856753" is m11 m12 m22.
    assert_eq!(metric.item(0), &[69.807785718567544, -28.785867635430975, 69.80778571856753]);
    assert_eq!(
        metric.tensor9(0),
        sym2_to_tensor9(69.807785718567544, -28.785867635430975, 69.80778571856753, 1.0)
    );
    // ... and stands for the 9-component tensor with zz = 1.
    let full = metric.expanded();
    assert_eq!((full.components, full.layout, full.len()), (9, Layout::Plain, 435));
    assert_eq!(
        full.item(0),
        &sym2_to_tensor9(69.807785718567544, -28.785867635430975, 69.80778571856753, 1.0)
    );
    assert_eq!(*metric, *full);
    assert_eq!(m.point_data.len(), 1);
}

#[test]
fn square_hole_adapted_by_mmg() {
    smartmesh_test_support::require_public_fixtures!();
    let m = read_file("medit/square_hole_mmg.mesh");
    assert_eq!(m.points.len(), 466);
    assert_eq!(
        counts_per_tag(&m),
        counts(&[("line", 1, 48), ("line", 2, 40), ("triangle", 3, 844)])
    );
    assert_eq!(m.point_sets["Corners"], vec![0, 1, 2, 3]);
    // One vertex (the last) has reference 2.
    let refs = &m.point_data["medit:ref"].values;
    assert_eq!(refs.iter().filter(|&&r| r != 0.0).count(), 1);
    assert_eq!(refs[465], 2.0);
    assert_eq!(
        m.point_data["metric"].tensor9(0),
        sym2_to_tensor9(73.9024724165296, -24.3655176449654, 74.5873813652242, 1.0)
    );
}

#[test]
fn square_hole_mesh_and_meshb_agree() {
    smartmesh_test_support::require_public_fixtures!();
    let a = read_file("medit/square_hole_mmg.mesh");
    let b = read_file("medit/square_hole_mmg.meshb");
    // MMG prints 15 significant digits in ASCII and writes doubles in binary: the
    // coordinates agree to the last printed digit, everything else exactly.
    assert_eq!(a.points.len(), b.points.len());
    for (p, q) in a.points.iter().zip(&b.points) {
        for k in 0..3 {
            assert!((p[k] - q[k]).abs() <= 1e-15 * p[k].abs().max(1.0), "{p:?} {q:?}");
        }
    }
    let (mut a, mut b) = (a, b);
    a.points.clear();
    b.points.clear();
    assert_eq!(a, b);
}

// -----------------------------------------------------------------------------------------
// Round trips
// -----------------------------------------------------------------------------------------

fn full_mesh() -> TaggedMesh {
    let mut m = TaggedMesh::new();
    m.points = vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.5, 0.5, 0.0],
        [0.1, 1e-300, 0.0],
    ];
    m.blocks.push(CellBlock {
        kind: CellKind::Line,
        nodes: vec![0, 1, 1, 2, 2, 3, 3, 0],
        physical: vec![1, 2, -3, 4],
        geometrical: vec![1, 2, -3, 4],
    });
    m.blocks.push(CellBlock {
        kind: CellKind::Triangle,
        nodes: vec![0, 1, 4, 1, 2, 4],
        physical: vec![7, 8],
        geometrical: vec![7, 8],
    });
    m.blocks.push(CellBlock {
        kind: CellKind::Quad,
        nodes: vec![2, 3, 0, 4],
        physical: vec![9],
        geometrical: vec![9],
    });
    m.point_data.insert("medit:ref".into(), DataArray::new(1, vec![1.0, 2.0, 3.0, 4.0, 0.0, -5.0]));
    let metric: Vec<f64> =
        (0..6).flat_map(|i| sym2_to_tensor9(1.0 + i as f64, 0.1 / 3.0, 2.0, 1.0)).collect();
    m.point_data.insert("metric".into(), DataArray::new(9, metric));
    m.point_sets.insert("Corners".into(), vec![0, 1, 2, 3]);
    m.point_sets.insert("RequiredVertices".into(), vec![5]);
    m.cell_sets.insert("RequiredEdges".into(), vec![0, 3]);
    m.cell_sets.insert("Ridges".into(), vec![2]);
    m.cell_sets.insert("RequiredTriangles".into(), vec![5]);
    m.cell_sets.insert("RequiredQuadrilaterals".into(), vec![6]);
    m
}

#[test]
fn write_read_identity_ascii_and_binary() {
    let m = full_mesh();
    for (main, ext, sol) in [("out.mesh", "mesh", "sol"), ("out.meshb", "meshb", "solb")] {
        let (w, back) = roundtrip(Format::Medit, ext, &m, &opts(main));
        assert!(w.report.dropped.is_empty(), "{main}: {:?}", w.report.dropped);
        assert_eq!(w.siblings.len(), 1);
        assert_eq!(w.siblings[0].0, sol);
        assert_eq!(back, m, "{main}");
        for (a, b) in back.points.iter().zip(&m.points) {
            assert_eq!(a.map(f64::to_bits), b.map(f64::to_bits));
        }
    }
}

#[test]
fn binary_option_without_a_name() {
    let o = WriteOptions { medit: MeditWrite { binary: true }, ..Default::default() };
    let w = write_bytes(Format::Medit, &full_mesh(), &o).unwrap();
    assert_eq!(&w.main[..8], &[1, 0, 0, 0, 2, 0, 0, 0]);
    assert_eq!(w.siblings[0].0, "solb");
    // The extension wins over the option: MMG reads `.mesh` as text.
    let o = WriteOptions {
        medit: MeditWrite { binary: true },
        main_name: Some("x.mesh".into()),
        ..Default::default()
    };
    let w = write_bytes(Format::Medit, &full_mesh(), &o).unwrap();
    assert!(w.main.starts_with(b"MeshVersionFormatted 2\n"));
}

#[test]
fn ascii_layout() {
    let mut m = full_mesh();
    m.point_data.remove("metric");
    let w = write_bytes(Format::Medit, &m, &opts("x.mesh")).unwrap();
    let text = String::from_utf8(w.main).unwrap();
    assert!(
        text.starts_with("MeshVersionFormatted 2\n\nDimension 2\n\nVertices\n6\n0.0 0.0 1\n"),
        "{text}"
    );
    assert!(text.contains("\nEdges\n4\n1 2 1\n"), "{text}");
    assert!(text.contains("\nRequiredEdges\n2\n1\n4\n"), "{text}");
    assert!(text.ends_with("\nEnd\n"));
    assert!(w.siblings.is_empty());
}

#[test]
fn three_dimensional_points_keep_z() {
    let mut m = full_mesh();
    m.points[4][2] = 0.25;
    m.coordinate_dim = 3;
    for main in ["z.mesh", "z.meshb"] {
        let ext = main.rsplit_once('.').unwrap().1;
        let (w, back) = roundtrip(Format::Medit, ext, &m, &opts(main));
        assert!(w.report.dropped.is_empty());
        assert_eq!(back, m, "{main}");
    }
}

#[test]
fn size_when_there_is_no_metric() {
    let mut m = full_mesh();
    m.point_data.remove("metric");
    m.point_data.insert("size".into(), DataArray::new(1, vec![0.1, 0.2, 0.3, 0.4, 0.5, 0.6]));
    let (w, back) = roundtrip(Format::Medit, "mesh", &m, &opts("s.mesh"));
    assert!(String::from_utf8_lossy(&w.siblings[0].1).contains("SolAtVertices\n6\n1 1\n0.1\n"));
    assert_eq!(back, m);
}

#[test]
fn second_order_elements_round_trip() {
    let mut m = TaggedMesh::new();
    m.points = (0..9).map(|i| [i as f64, (i % 3) as f64, 0.0]).collect();
    m.blocks.push(CellBlock {
        kind: CellKind::Line3,
        nodes: vec![0, 1, 2],
        physical: vec![1],
        geometrical: vec![1],
    });
    m.blocks.push(CellBlock {
        kind: CellKind::Triangle6,
        nodes: vec![0, 1, 2, 3, 4, 5],
        physical: vec![2],
        geometrical: vec![2],
    });
    m.blocks.push(CellBlock {
        kind: CellKind::Quad9,
        nodes: (0..9).collect(),
        physical: vec![3],
        geometrical: vec![3],
    });
    for main in ["p2.mesh", "p2.meshb"] {
        let ext = main.rsplit_once('.').unwrap().1;
        let (w, back) = roundtrip(Format::Medit, ext, &m, &opts(main));
        assert!(w.report.dropped.is_empty());
        assert_eq!(back, m);
    }
}

#[test]
fn what_medit_cannot_hold_is_reported() {
    let mut m = full_mesh();
    m.blocks.push(CellBlock {
        kind: CellKind::Vertex,
        nodes: vec![4],
        physical: vec![1],
        geometrical: vec![1],
    });
    m.blocks[1].geometrical[0] = 70;
    m.point_data.insert("size".into(), DataArray::new(1, vec![1.0; 6]));
    m.point_data.insert("size_tensor".into(), DataArray::new(9, vec![1.0; 54]));
    m.cell_data.insert("gmsh:physical".into(), DataArray::new(1, vec![0.0; 8]));
    m.tag_names.insert((1, 1), "Walls".into());
    m.holes.push([0.5, 0.5]);
    m.point_sets.insert("Mine".into(), vec![1]);
    m.cell_sets.insert("RequiredTriangles".into(), vec![0, 5]);
    let w = write_bytes(Format::Medit, &m, &opts("x.mesh")).unwrap();
    let d = w.report.dropped.join("\n");
    for needle in [
        "the tags of 1 point cells",
        "geometrical tags of 1 cells",
        "point data `size` (1 component): MMG reads one solution, `metric` was written",
        "point data `size_tensor`",
        "cell data `gmsh:physical`",
        "1 tag names",
        "1 holes",
        "point set `Mine`",
        "1 entries of cell set `RequiredTriangles`",
    ] {
        assert!(d.contains(needle), "missing `{needle}` in:\n{d}");
    }
}

#[test]
fn same_mesh_same_bytes() {
    for main in ["a.mesh", "a.meshb"] {
        let a = write_bytes(Format::Medit, &full_mesh(), &opts(main)).unwrap();
        let b = write_bytes(Format::Medit, &full_mesh(), &opts(main)).unwrap();
        assert_eq!((a.main, a.siblings), (b.main, b.siblings));
    }
}

#[test]
fn fixture_rewritten_reads_back_identically() {
    smartmesh_test_support::require_public_fixtures!();
    for file in ["medit/square_hole_input.mesh", "medit/square_hole_mmg.meshb"] {
        let m = read_file(file);
        for (main, ext) in [("r.mesh", "mesh"), ("r.meshb", "meshb")] {
            let (w, back) = roundtrip(Format::Medit, ext, &m, &opts(main));
            assert!(w.report.dropped.is_empty(), "{:?}", w.report.dropped);
            assert_eq!(back, m, "{file} as {main}");
        }
    }
}

// -----------------------------------------------------------------------------------------
// Binary versions and byte orders, built by hand after libMeshb's layout
// -----------------------------------------------------------------------------------------

/// A binary file: one triangle with reference 7 on three vertices (refs 0, 1, 2), and
/// Corners 1 3, in `version` and byte order `le`.
fn handmade(version: u32, le: bool) -> Vec<u8> {
    let int = |v: i64, out: &mut Vec<u8>| {
        if version >= 4 {
            out.extend_from_slice(&if le { v.to_le_bytes() } else { v.to_be_bytes() });
        } else {
            out.extend_from_slice(&if le {
                (v as i32).to_le_bytes()
            } else {
                (v as i32).to_be_bytes()
            });
        }
    };
    let word = |v: i32, out: &mut Vec<u8>| {
        out.extend_from_slice(&if le { v.to_le_bytes() } else { v.to_be_bytes() })
    };
    let real = |v: f64, out: &mut Vec<u8>| {
        if version == 1 {
            out.extend_from_slice(&if le {
                (v as f32).to_le_bytes()
            } else {
                (v as f32).to_be_bytes()
            });
        } else {
            out.extend_from_slice(&if le { v.to_le_bytes() } else { v.to_be_bytes() });
        }
    };
    let psz = if version >= 3 { 8 } else { 4 };
    let mut out = Vec::new();
    word(1, &mut out);
    word(version as i32, &mut out);
    // Each keyword: code, placeholder offset, data; the offset is patched afterwards.
    let keyword = |code: i32, out: &mut Vec<u8>, body: &dyn Fn(&mut Vec<u8>)| {
        word(code, out);
        let at = out.len();
        out.resize(at + psz, 0);
        body(out);
        let next = out.len() as i64;
        let bytes: Vec<u8> = if psz == 8 {
            (if le { next.to_le_bytes() } else { next.to_be_bytes() }).to_vec()
        } else {
            (if le { (next as i32).to_le_bytes() } else { (next as i32).to_be_bytes() }).to_vec()
        };
        out[at..at + psz].copy_from_slice(&bytes);
    };
    keyword(3, &mut out, &|o| word(2, o));
    keyword(4, &mut out, &|o| {
        int(3, o);
        for (i, (x, y)) in [(0.0, 0.0), (1.0, 0.0), (0.0, 0.5)].into_iter().enumerate() {
            real(x, o);
            real(y, o);
            int(i as i64, o);
        }
    });
    // An unused keyword (Normals, code 60: count, then dim reals) is skipped by offset.
    keyword(60, &mut out, &|o| {
        int(1, o);
        real(1.0, o);
        real(0.0, o);
    });
    keyword(6, &mut out, &|o| {
        int(1, o);
        for v in [1, 2, 3, 7] {
            int(v, o);
        }
    });
    keyword(13, &mut out, &|o| {
        int(2, o);
        int(1, o);
        int(3, o);
    });
    keyword(54, &mut out, &|_| {});
    out
}

#[test]
fn binary_versions_and_byte_orders() {
    for version in 1..=4 {
        for le in [true, false] {
            let bytes = handmade(version, le);
            let m =
                read_alone(&bytes, "meshb").unwrap_or_else(|e| panic!("v{version} le={le}: {e}"));
            assert_eq!(
                m.points,
                vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.5, 0.0]],
                "v{version} le={le}"
            );
            assert_eq!(
                m.blocks,
                vec![CellBlock {
                    kind: CellKind::Triangle,
                    nodes: vec![0, 1, 2],
                    physical: vec![7],
                    geometrical: vec![7]
                }]
            );
            assert_eq!(m.point_data["medit:ref"].values, vec![0.0, 1.0, 2.0]);
            assert_eq!(m.point_sets["Corners"], vec![0, 2]);
        }
    }
}

// -----------------------------------------------------------------------------------------
// Solution files
// -----------------------------------------------------------------------------------------

#[test]
fn sol_api_several_solutions() {
    let size = DataArray::new(1, vec![0.5, 0.25]);
    let vector = DataArray::new(3, vec![1.0, 2.0, 0.0, 3.0, 4.0, 0.0]);
    let metric = DataArray::new(
        9,
        [sym2_to_tensor9(4.0, 0.5, 9.0, 1.0), sym2_to_tensor9(1.0, 0.0, 1.0, 1.0)].concat(),
    );
    for binary in [false, true] {
        let bytes = write_sol(
            &[("size", &size), ("metric", &metric), ("vector", &vector), ("size", &size)],
            2,
            binary,
        )
        .unwrap();
        if !binary {
            let text = String::from_utf8(bytes.clone()).unwrap();
            assert!(
                text.contains("SolAtVertices\n2\n4 1 3 2 1\n0.5 4.0 0.5 9.0 1.0 2.0 0.5\n"),
                "{text}"
            );
        }
        let back = read_sol(&bytes, 2, binary).unwrap();
        assert_eq!(back.keys().collect::<Vec<_>>(), ["metric", "size", "size_2", "vector"]);
        assert_eq!(back["size"], size);
        assert_eq!(back["size_2"], size);
        assert_eq!(back["metric"], metric);
        assert_eq!(back["vector"], vector);
    }
}

#[test]
fn sol_api_three_dimensional_tensor_order() {
    // libMeshb and MMG 3D: m11 m12 m22 m13 m23 m33.
    let text = b"MeshVersionFormatted 2\nDimension 3\nSolAtVertices\n1\n1 3\n1 2 3 4 5 6\nEnd\n";
    let back = read_sol(text, 1, false).unwrap();
    assert_eq!(back["metric"].values, vec![1.0, 2.0, 4.0, 2.0, 3.0, 5.0, 4.0, 5.0, 6.0]);
    let again = write_sol(&[("metric", &back["metric"])], 3, false).unwrap();
    assert!(String::from_utf8_lossy(&again).contains("\n1.0 2.0 3.0 4.0 5.0 6.0\n"));
}

#[test]
fn sol_api_refusals() {
    let a = DataArray::new(1, vec![1.0]);
    let b = DataArray::new(1, vec![1.0, 2.0]);
    let c = DataArray::new(4, vec![1.0; 4]);
    assert!(write_sol(&[], 2, false).is_err());
    assert!(write_sol(&[("a", &a), ("b", &b)], 2, false).is_err());
    assert!(write_sol(&[("c", &c)], 2, false).is_err());
    assert!(write_sol(&[("a", &a)], 4, false).is_err());
    let e = read_sol(
        b"MeshVersionFormatted 2\nDimension 2\nSolAtVertices\n2\n1 1\n1\n2\nEnd\n",
        3,
        false,
    )
    .unwrap_err();
    assert!(e.to_string().contains("gives 2 vertices, the mesh has 3"), "{e}");
}

/// A binary solution's non-finite value is refused at its byte, whether the solution is
/// one field decoded straight into its array or several left in the file.
#[test]
fn solb_non_finite_value_names_its_byte() {
    let metric = DataArray::symmetric2((0..30).map(|i| 1.0 + i as f64 / 64.0).collect());
    let size = DataArray::new(1, (0..10).map(|i| 0.5 + i as f64 / 128.0).collect());
    for arrays in [
        vec![("metric", &metric)],
        vec![("size", &size)],
        vec![("size", &size), ("metric", &metric)],
    ] {
        let good = write_sol(&arrays, 2, true).unwrap();
        let back = read_sol(&good, 10, true).unwrap();
        for (name, a) in &arrays {
            assert_eq!(&back[*name], *a, "{name}");
        }
        // The last value of the last field (vertex 9's m22, or its size).
        let last = arrays.last().unwrap().1.values.last().copied().unwrap();
        let at = memchr::memmem::rfind(&good, &last.to_le_bytes()).unwrap();
        for bad_value in [f64::NAN, f64::NEG_INFINITY] {
            let mut bad = good.clone();
            bad[at..at + 8].copy_from_slice(&bad_value.to_le_bytes());
            let e = read_sol(&bad, 10, true).unwrap_err();
            assert!(matches!(e.kind, ErrorKind::NonFinite { .. }), "{e}");
            assert_eq!(byte_of(&e), at as u64, "{e}");
        }
    }
}

/// A big-endian `.solb` (version 2, one scalar field): read, and a non-finite value
/// refused at its byte.
#[test]
fn big_endian_solb_values_and_non_finite_byte() {
    let sizes = [0.5, 0.25, 2.0, 4.0];
    let solb = |values: &[f64]| {
        let mut b = Vec::new();
        let word = |b: &mut Vec<u8>, v: i32| b.extend_from_slice(&v.to_be_bytes());
        word(&mut b, 1);
        word(&mut b, 2);
        // Dimension 2: code, offset of the next keyword, value.
        word(&mut b, 3);
        word(&mut b, 20);
        word(&mut b, 2);
        // SolAtVertices: code, next offset, vertices, one type (1: scalar), values.
        word(&mut b, 62);
        word(&mut b, 40 + 8 * values.len() as i32);
        word(&mut b, values.len() as i32);
        word(&mut b, 1);
        word(&mut b, 1);
        for v in values {
            b.extend_from_slice(&v.to_be_bytes());
        }
        word(&mut b, 54);
        word(&mut b, 0);
        b
    };
    let back = read_sol(&solb(&sizes), 4, true).unwrap();
    assert_eq!(back["size"], DataArray::new(1, sizes.to_vec()));
    let e = read_sol(&solb(&[0.5, 0.25, f64::INFINITY, f64::NAN]), 4, true).unwrap_err();
    assert!(matches!(e.kind, ErrorKind::NonFinite { .. }), "{e}");
    assert_eq!(byte_of(&e), 40 + 16, "{e}");
}

#[test]
fn solb_beside_mesh_and_fallback() {
    let m = full_mesh();
    let w = write_bytes(Format::Medit, &m, &opts("x.meshb")).unwrap();
    // A .meshb with a .sol (not .solb) beside it: MMG falls back to it, so do we.
    let metric = &m.point_data["metric"];
    let sol = write_sol(&[("metric", metric)], 2, false).unwrap();
    let back = read_with_sol(&w.main, "meshb", "sol", &sol).unwrap();
    assert_eq!(&back.point_data["metric"], metric);
}

// -----------------------------------------------------------------------------------------
// Property tests
// -----------------------------------------------------------------------------------------

/// Medit holds one reference per element and no names; point cells are not elements.
const MEDIT_FEATURES: MeshFeatures = MeshFeatures {
    quads: true,
    lines: true,
    vertices: false,
    geometrical: false,
    names: false,
    point_scalar: false,
    point_tensor: true,
    negative_tags: true,
};

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]
    #[test]
    fn prop_write_read_identity(m in arb_tagged_mesh(MEDIT_FEATURES), binary in any::<bool>(), scalar in any::<bool>()) {
        let mut m = m;
        if scalar {
            // MMG reads one solution: a size instead of the metric.
            m.point_data.clear();
            m.point_data.insert("size".into(), DataArray::new(1, (0..m.points.len()).map(|i| 0.5 + i as f64).collect()));
        }
        let (main, ext) = if binary { ("p.meshb", "meshb") } else { ("p.mesh", "mesh") };
        let (w, back) = roundtrip(Format::Medit, ext, &m, &opts(main));
        prop_assert!(w.report.dropped.is_empty(), "{:?}", w.report.dropped);
        prop_assert_eq!(&back, &m);
        for (a, b) in back.points.iter().zip(&m.points) {
            prop_assert_eq!(a.map(f64::to_bits), b.map(f64::to_bits));
        }
    }
}

// -----------------------------------------------------------------------------------------
// Malformed input: every error names its line (ASCII) or byte offset (binary).
// -----------------------------------------------------------------------------------------

const HEAD: &str = "MeshVersionFormatted 2\nDimension 2\n";

fn ascii_err(body: &str) -> smartmesh_formats::Error {
    read_alone(format!("{HEAD}{body}").as_bytes(), "mesh").expect_err("should fail")
}

fn line_of(e: &smartmesh_formats::Error) -> u64 {
    match e.at {
        Some(Position::Line(l)) => l,
        other => panic!("no line in {e} ({other:?})"),
    }
}

fn byte_of(e: &smartmesh_formats::Error) -> u64 {
    match e.at {
        Some(Position::Byte(b)) => b,
        other => panic!("no byte offset in {e} ({other:?})"),
    }
}

const SQUARE: &str = "Vertices\n4\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n";

#[test]
fn malformed_truncated_ascii() {
    let e = ascii_err("Vertices\n4\n0.0 0.0 0\n1.0 0.0 0\n1.0 1.0 0\n0.0 1.0\n");
    assert!(matches!(e.kind, ErrorKind::UnexpectedEof { .. }), "{e}");
    let e = ascii_err(&format!("{SQUARE}Triangles\n2\n1  2  3  0\n1  3  4\n"));
    assert!(matches!(e.kind, ErrorKind::UnexpectedEof { .. }), "{e}");
}

#[test]
fn malformed_wrong_counts_ascii() {
    // Two triangles announced, one given, then End: `End` is not a vertex number.
    let e =
        ascii_err(&format!("{SQUARE}Triangles\n2\n1 2 3 0\nEnd\n# comments count as bytes left\n"));
    assert_eq!(line_of(&e), 12, "{e}");
    assert!(e.to_string().contains("found `End`"), "{e}");
}

#[test]
fn malformed_index_out_of_range_ascii() {
    let e = ascii_err(&format!("{SQUARE}Triangles\n1\n1 2 5 0\nEnd\n"));
    assert!(matches!(e.kind, ErrorKind::IndexOutOfRange { index: 5, available: 4, .. }), "{e}");
    assert_eq!(line_of(&e), 11);
    let e = ascii_err(&format!("{SQUARE}Edges\n1\n0 1 0\nEnd\n"));
    assert!(matches!(e.kind, ErrorKind::IndexOutOfRange { index: 0, .. }), "{e}");
    let e = ascii_err(&format!("{SQUARE}Edges\n1\n1 2 0\nRequiredEdges\n1\n2\nEnd\n"));
    assert!(matches!(e.kind, ErrorKind::IndexOutOfRange { index: 2, available: 1, .. }), "{e}");
    let e = ascii_err(&format!("{SQUARE}Corners\n1\n9\nEnd\n"));
    assert!(e.to_string().contains("Corners entry 1 refers to 9, but only 4 exist"), "{e}");
}

#[test]
fn malformed_elements_before_vertices_are_checked_at_the_end() {
    let e = ascii_err(&format!("Triangles\n1\n1 2 9 0\n{SQUARE}End\n"));
    assert!(matches!(e.kind, ErrorKind::IndexOutOfRange { index: 9, available: 4, .. }), "{e}");
    assert_eq!(line_of(&e), 3);
}

#[test]
fn malformed_nan_ascii() {
    let e = ascii_err("Vertices\n1\nnan 0 0\nEnd\n");
    assert!(matches!(e.kind, ErrorKind::NonFinite { .. }), "{e}");
    assert_eq!(line_of(&e), 5);
}

#[test]
fn malformed_huge_count_ascii() {
    let e = ascii_err("Vertices\n100000000000000\n0 0 0\n");
    assert!(matches!(e.kind, ErrorKind::ImplausibleCount { .. }), "{e}");
    let e = ascii_err("Normals\n100000000000000\n0 0 0\n");
    assert!(matches!(e.kind, ErrorKind::ImplausibleCount { .. }), "{e}");
}

#[test]
fn malformed_unknown_keyword() {
    let e = ascii_err("Vertexes\n1\n0 0 0\n");
    assert!(
        e.to_string().contains("expected a keyword of libMeshb's table, found `Vertexes`"),
        "{e}"
    );
    assert_eq!(line_of(&e), 3);
}

#[test]
fn malformed_unskippable_layout() {
    // ExtraVerticesAtEdges has a variable layout (`in`): it cannot be skipped in ASCII.
    let e = ascii_err("ExtraVerticesAtEdges\n1\n1 2\n");
    assert!(matches!(e.kind, ErrorKind::Unsupported(_)), "{e}");
}

#[test]
fn known_keywords_are_skipped() {
    let m = read_alone(
        format!("# comment\n{HEAD}{SQUARE}Normals\n1\n1.0 0.0\nNormalAtVertices\n1\n1 1\nAngleOfCornerBound\n45\nSolAtTriangles\n2\n2 1 3\n1.5 1 2 3\n2.5 4 5 6\nComments\n1\nany text, even 12 numbers\nTriangles\n1\n1 2 3 5\nEnd\n").as_bytes(),
        "mesh",
    )
    .unwrap();
    assert_eq!(counts_per_tag(&m), counts(&[("triangle", 5, 1)]));
}

#[test]
fn malformed_third_order_elements() {
    let tet20: String = (1..=20).map(|v| format!("{} ", v.min(4))).collect();
    let e = ascii_err(&format!("{SQUARE}TetrahedraP3\n1\n{tet20}0\nEnd\n"));
    assert!(matches!(e.kind, ErrorKind::Unsupported(_)), "{e}");
    assert!(e.to_string().contains("1 TetrahedraP3"), "{e}");
}

#[test]
fn malformed_bad_version_and_dimension() {
    let e = read_alone(b"MeshVersionFormatted 7\nDimension 2\n", "mesh").unwrap_err();
    assert!(e.to_string().contains("MeshVersionFormatted 1, 2, 3 or 4"), "{e}");
    let e = read_alone(b"MeshVersionFormatted 2\nDimension 4\n", "mesh").unwrap_err();
    assert!(e.to_string().contains("Dimension 2 or 3"), "{e}");
    let e = read_alone(b"MeshVersionFormatted 2\nVertices\n1\n0 0 0\n", "mesh").unwrap_err();
    assert!(e.to_string().contains("Dimension before Vertices"), "{e}");
}

#[test]
fn malformed_bad_reference() {
    let e = ascii_err("Vertices\n1\n0 0 99999999999\n");
    assert!(e.to_string().contains("32-bit"), "{e}");
}

#[test]
fn malformed_bad_binary_code() {
    let mut b = handmade(2, true);
    b[0] = 2;
    let e = read_alone(&b, "meshb").unwrap_err();
    assert_eq!(byte_of(&e), 0);
    assert!(e.to_string().contains("endianness code"), "{e}");
    let e = read_alone(b"Meshversion", "meshb").unwrap_err();
    assert_eq!(byte_of(&e), 0, "{e}");
}

#[test]
fn malformed_bad_binary_version() {
    let mut b = handmade(2, true);
    b[4] = 9;
    let e = read_alone(&b, "meshb").unwrap_err();
    assert_eq!(byte_of(&e), 4);
}

#[test]
fn malformed_truncated_binary() {
    let b = handmade(2, true);
    // Cut inside the vertices: the count no longer fits in what is left.
    let cut = &b[..40];
    let e = read_alone(cut, "meshb").unwrap_err();
    assert!(
        matches!(e.kind, ErrorKind::ImplausibleCount { .. } | ErrorKind::Inconsistent(_)),
        "{e}"
    );
    byte_of(&e);
    // Cut inside a keyword header.
    let e = read_alone(&b[..10], "meshb").unwrap_err();
    assert!(matches!(e.kind, ErrorKind::UnexpectedEof { .. }), "{e}");
    assert_eq!(byte_of(&e), 8);
}

#[test]
fn malformed_binary_next_offset() {
    let mut b = handmade(2, true);
    // Dimension at byte 8: its next offset (byte 12) pointing backwards.
    b[12..16].copy_from_slice(&4i32.to_le_bytes());
    let e = read_alone(&b, "meshb").unwrap_err();
    assert_eq!(byte_of(&e), 12, "{e}");
    b[12..16].copy_from_slice(&1_000_000i32.to_le_bytes());
    let e = read_alone(&b, "meshb").unwrap_err();
    assert!(e.to_string().contains("outside bytes"), "{e}");
}

#[test]
fn malformed_binary_wrong_count() {
    let mut b = handmade(2, true);
    // The vertex count (byte 28) raised past what the keyword holds.
    b[28..32].copy_from_slice(&4i32.to_le_bytes());
    let e = read_alone(&b, "meshb").unwrap_err();
    assert!(matches!(e.kind, ErrorKind::ImplausibleCount { .. }), "{e}");
    assert_eq!(byte_of(&e), 28);
    b[28..32].copy_from_slice(&(-1i32).to_le_bytes());
    let e = read_alone(&b, "meshb").unwrap_err();
    assert_eq!(byte_of(&e), 28, "{e}");
}

#[test]
fn malformed_binary_index_out_of_range() {
    let b = handmade(2, true);
    // The triangle's third vertex number: find the Triangles keyword (code 6).
    let at = (8..b.len() - 4)
        .step_by(4)
        .find(|&i| b[i..i + 4] == 6i32.to_le_bytes() && b[i + 8..i + 12] == 1i32.to_le_bytes())
        .unwrap();
    let mut bad = b.clone();
    bad[at + 20..at + 24].copy_from_slice(&9i32.to_le_bytes());
    let e = read_alone(&bad, "meshb").unwrap_err();
    assert!(matches!(e.kind, ErrorKind::IndexOutOfRange { index: 9, available: 3, .. }), "{e}");
    assert_eq!(byte_of(&e), at as u64 + 12);
    let mut bad = b.clone();
    bad[at + 12..at + 16].copy_from_slice(&0i32.to_le_bytes());
    let e = read_alone(&bad, "meshb").unwrap_err();
    assert!(matches!(e.kind, ErrorKind::IndexOutOfRange { index: 0, .. }), "{e}");
}

#[test]
fn malformed_binary_nan() {
    let mut b = handmade(2, true);
    // First vertex x at byte 32.
    b[32..40].copy_from_slice(&f64::NAN.to_le_bytes());
    let e = read_alone(&b, "meshb").unwrap_err();
    assert!(matches!(e.kind, ErrorKind::NonFinite { .. }), "{e}");
    assert_eq!(byte_of(&e), 32);
}

/// A version-2 `.meshb` (4-byte integers and offsets) of a strip of `n` triangles on
/// `n + 2` vertices, all references 0, and where its Vertices and Triangles records start.
fn strip_meshb(n: usize) -> (Vec<u8>, usize, usize) {
    let mut m = TaggedMesh::new();
    m.points = (0..n + 2).map(|i| [(i / 2) as f64, (i % 2) as f64, 0.0]).collect();
    let mut tris = CellBlock::new(CellKind::Triangle);
    for i in 0..n {
        tris.push(&[i, i + 1, i + 2], 0, 0);
    }
    m.blocks.push(tris);
    let b = write_bytes(Format::Medit, &m, &opts("s.meshb")).unwrap().main;
    // Walk the keywords: code, offset of the next one, then the count.
    let (mut pos, mut vertices, mut triangles) = (8, 0, 0);
    while pos + 8 <= b.len() {
        let code = i32::from_le_bytes(b[pos..pos + 4].try_into().unwrap());
        let next = i32::from_le_bytes(b[pos + 4..pos + 8].try_into().unwrap()) as usize;
        match code {
            4 => vertices = pos + 12,
            6 => triangles = pos + 12,
            _ => {}
        }
        if next == 0 {
            break;
        }
        pos = next;
    }
    assert!(vertices > 0 && triangles > 0, "both keywords written");
    (b, vertices, triangles)
}

#[test]
fn malformed_binary_fault_after_many_good_records() {
    let (b, vertices, triangles) = strip_meshb(100);
    let m = read_alone(&b, "meshb").unwrap();
    assert_eq!(m.num_cells(), 100);
    assert!(!m.point_data.contains_key("medit:ref"), "all references 0: no array");
    // Triangle 71's second vertex past the vertices (checked once the elements are read).
    let mut bad = b.clone();
    let tri = |i: usize| triangles + 16 * (i - 1);
    bad[tri(71) + 4..tri(71) + 8].copy_from_slice(&500i32.to_le_bytes());
    let e = read_alone(&bad, "meshb").unwrap_err();
    assert!(matches!(e.kind, ErrorKind::IndexOutOfRange { index: 500, available: 102, .. }), "{e}");
    assert_eq!(byte_of(&e), tri(71) as u64);
    // A negative number in triangle 90 and a 0 in triangle 95, both refused as they are
    // decoded: the first is named.
    let mut bad = b.clone();
    bad[tri(90)..tri(90) + 4].copy_from_slice(&(-3i32).to_le_bytes());
    bad[tri(95) + 8..tri(95) + 12].copy_from_slice(&0i32.to_le_bytes());
    let e = read_alone(&bad, "meshb").unwrap_err();
    assert!(matches!(e.kind, ErrorKind::IndexOutOfRange { index: -3, .. }), "{e}");
    assert_eq!(byte_of(&e), tri(90) as u64);
    // Vertex 60's y is infinite: the error is at its record.
    let mut bad = b.clone();
    let vtx = |i: usize| vertices + 20 * (i - 1);
    bad[vtx(60) + 8..vtx(60) + 16].copy_from_slice(&f64::INFINITY.to_le_bytes());
    let e = read_alone(&bad, "meshb").unwrap_err();
    assert!(matches!(e.kind, ErrorKind::NonFinite { .. }), "{e}");
    assert_eq!(byte_of(&e), vtx(60) as u64);
    // One reference that is not 0 (vertex 77): every vertex gets its reference.
    let mut refd = b.clone();
    refd[vtx(77) + 16..vtx(77) + 20].copy_from_slice(&(-4i32).to_le_bytes());
    let m = read_alone(&refd, "meshb").unwrap();
    let refs = &m.point_data["medit:ref"].values;
    assert_eq!(refs.len(), 102);
    assert_eq!(
        refs.iter().enumerate().filter(|(_, &r)| r != 0.0).collect::<Vec<_>>(),
        vec![(76, &-4.0)]
    );
}

#[test]
fn malformed_binary_references_past_32_bits() {
    // Version 4: 8-byte integers, so a reference can exceed what a 32-bit tag holds.
    let b = handmade(4, true);
    // Vertices at byte 24 + 12 (code, offset) + 8 (count); 24 bytes per vertex.
    let second_ref = 44 + 24 + 16;
    let mut bad = b.clone();
    bad[second_ref..second_ref + 8].copy_from_slice(&(1i64 << 40).to_le_bytes());
    let e = read_alone(&bad, "meshb").unwrap_err();
    assert!(e.to_string().contains("the reference of vertex 2 (a 32-bit integer)"), "{e}");
    assert_eq!(byte_of(&e), second_ref as u64);
    // The triangle's reference: the last 8 bytes of its record.
    let at = (8..b.len() - 12)
        .step_by(4)
        .find(|&i| b[i..i + 4] == 6i32.to_le_bytes() && b[i + 12..i + 20] == 1i64.to_le_bytes())
        .unwrap();
    let tri_ref = at + 20 + 24;
    assert_eq!(b[tri_ref..tri_ref + 8], 7i64.to_le_bytes());
    let mut bad = b.clone();
    bad[tri_ref..tri_ref + 8].copy_from_slice(&(-(1i64 << 33)).to_le_bytes());
    let e = read_alone(&bad, "meshb").unwrap_err();
    assert!(e.to_string().contains("the reference of triangle 1"), "{e}");
    assert_eq!(byte_of(&e), tri_ref as u64);
}

#[test]
fn malformed_binary_huge_count() {
    let mut b = handmade(4, true);
    // Version 4: the vertex count is 8 bytes at byte 36 (after code, 8-byte offset).
    b[36..44].copy_from_slice(&(1i64 << 60).to_le_bytes());
    let e = read_alone(&b, "meshb").unwrap_err();
    assert!(matches!(e.kind, ErrorKind::ImplausibleCount { .. }), "{e}");
    assert_eq!(byte_of(&e), 36);
}

#[test]
fn malformed_sol_beside_mesh() {
    let mesh = format!("{HEAD}{SQUARE}End\n");
    let e = read_with_sol(
        mesh.as_bytes(),
        "mesh",
        "sol",
        b"MeshVersionFormatted 2\nDimension 2\nSolAtVertices\n3\n1 1\n1\n2\n3\nEnd\n",
    )
    .unwrap_err();
    assert!(e.to_string().starts_with("<memory>.sol:3:"), "{e}");
    let e = read_with_sol(
        mesh.as_bytes(),
        "mesh",
        "sol",
        b"MeshVersionFormatted 2\nDimension 3\nSolAtVertices\n4\n1 1\n1\n2\n3\n4\nEnd\n",
    )
    .unwrap_err();
    assert!(e.to_string().contains("the solution is 3D but the mesh is 2D"), "{e}");
    let e = read_with_sol(
        mesh.as_bytes(),
        "mesh",
        "sol",
        b"MeshVersionFormatted 2\nDimension 2\nSolAtVertices\n4\n1 7\n1\n2\n3\n4\nEnd\n",
    )
    .unwrap_err();
    assert!(e.to_string().contains("solution type 1 (scalar)"), "{e}");
    assert_eq!(line_of(&e), 5);
}

#[test]
fn malformed_error_after_fast_records() {
    // The first records go through the fast path; the error still names its own line.
    let e = ascii_err(&format!("{SQUARE}Triangles\n3\n1 2 3 0\n1 3 4 0\n1 4 7 0\nEnd\n"));
    assert!(matches!(e.kind, ErrorKind::IndexOutOfRange { index: 7, .. }), "{e}");
    assert_eq!(line_of(&e), 13);
    let e = ascii_err("Vertices\n3\n0 0 0\n1 0 0\n1 inf 0\nEnd\n");
    assert!(matches!(e.kind, ErrorKind::NonFinite { .. }), "{e}");
    assert_eq!(line_of(&e), 7);
}

#[test]
fn records_mixing_fast_and_general_paths() {
    let m = read_alone(
        format!("{HEAD}Vertices 4 0 0 0 1 0 # c\n 0\n1 1.0D0 0\n0 1 0\nTriangles\n2\n1 2 3 +1 # comment\n1 3 4 -2\nEnd\n").as_bytes(),
        "mesh",
    )
    .unwrap();
    assert_eq!(m.points[2], [1.0, 1.0, 0.0]);
    assert_eq!(m.blocks[0].physical, vec![1, -2]);
}

#[test]
fn malformed_dimension_changes() {
    let e = read_alone(
        b"MeshVersionFormatted 2\nDimension 2\nSolAtVertices\n1\n1 3\n1 2 3\nDimension 3\n",
        "mesh",
    )
    .unwrap_err();
    assert!(e.to_string().contains("Dimension 3 after Dimension 2"), "{e}");
    assert_eq!(line_of(&e), 7);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]
    /// Whatever the bytes, the readers return a value or an error: no panic, no abort.
    #[test]
    fn prop_no_panic_on_damaged_files(edits in prop::collection::vec((any::<prop::sample::Index>(), any::<u8>()), 1..8), cut in any::<prop::sample::Index>(), binary in any::<bool>()) {
        let mut bytes = if binary { handmade(2, true) } else { format!("{HEAD}{SQUARE}Edges\n1\n1 2 3\nTriangles\n2\n1 2 3 4\n1 3 4 4\nCorners\n1\n2\nRequiredEdges\n1\n1\nEnd\n").into_bytes() };
        for (at, byte) in edits {
            let i = at.index(bytes.len());
            bytes[i] = byte;
        }
        bytes.truncate(cut.index(bytes.len() + 1).max(1));
        let _ = read_alone(&bytes, if binary { "meshb" } else { "mesh" });
        let _ = read_sol(&bytes, 4, binary);
    }
}

#[test]
fn malformed_solb_value_names_its_byte() {
    let m = full_mesh();
    let w = write_bytes(Format::Medit, &m, &opts("x.meshb")).unwrap();
    let mut solb = w.siblings.iter().find(|s| s.0 == "solb").unwrap().1.clone();
    // Version 2: the header (8 bytes), Dimension (12), SolAtVertices' code, offset,
    // count, number of types and type (20): the values start at byte 40.
    assert_eq!(i32::from_le_bytes(solb[40 - 4..40].try_into().unwrap()), 3, "one type-3 solution");
    let back = read_with_sol(&w.main, "meshb", "solb", &solb).unwrap();
    assert_eq!(&back.point_data["metric"], &m.point_data["metric"]);
    // The last value (m22 of the last vertex) ends just before End (code and offset).
    let last = solb.len() - 8 - 8;
    assert_eq!(f64::from_le_bytes(solb[last..last + 8].try_into().unwrap()), 2.0);
    for (at, v) in [(40 + 8 * 4, f64::NAN), (last, f64::INFINITY)] {
        let keep = solb[at..at + 8].to_vec();
        solb[at..at + 8].copy_from_slice(&v.to_le_bytes());
        let e = read_with_sol(&w.main, "meshb", "solb", &solb).unwrap_err();
        assert!(matches!(e.kind, ErrorKind::NonFinite { .. }), "{e}");
        assert_eq!(byte_of(&e), at as u64, "{e}");
        assert!(e.to_string().contains(".solb"), "{e}");
        solb[at..at + 8].copy_from_slice(&keep);
    }
}

/// A packed 2D solution tensor goes out to the 9-component formats in full (zz = 1) and
/// comes back from them equal to what was read (the VTK readers pack it again, the Gmsh
/// ones keep the 9 components); back into Medit it is packed again, with the file's bits.
#[test]
fn packed_metric_through_the_nine_component_formats() {
    smartmesh_test_support::require_public_fixtures!();
    let m = read_file("medit/square_hole_input.mesh");
    let packed = &m.point_data["metric"];
    assert_eq!(packed.layout, Layout::Symmetric2);
    let targets: [(Format, &str, WriteOptions, Layout); 5] = [
        (
            Format::Gmsh,
            "msh",
            WriteOptions {
                gmsh: GmshWrite { binary: true, ..Default::default() },
                ..WriteOptions::default()
            },
            Layout::Plain,
        ),
        (
            Format::Gmsh,
            "msh",
            WriteOptions {
                gmsh: GmshWrite {
                    version: smartmesh_formats::GmshVersion::V22,
                    ..Default::default()
                },
                ..WriteOptions::default()
            },
            Layout::Plain,
        ),
        (Format::Vtu, "vtu", WriteOptions::default(), Layout::Symmetric2),
        (
            Format::Vtu,
            "vtu",
            WriteOptions {
                vtk: VtkWrite {
                    vtu_encoding: smartmesh_formats::VtuEncoding::Ascii,
                    ..Default::default()
                },
                ..WriteOptions::default()
            },
            Layout::Symmetric2,
        ),
        (
            Format::VtkLegacy,
            "vtk",
            WriteOptions {
                vtk: VtkWrite { legacy_binary: true, ..Default::default() },
                ..WriteOptions::default()
            },
            Layout::Symmetric2,
        ),
    ];
    for (format, ext, opts, layout) in targets {
        let (written, back) = roundtrip(format, ext, &m, &opts);
        assert!(written.report.dropped.is_empty(), "{ext}: {:?}", written.report.dropped);
        let read = &back.point_data["metric"];
        assert_eq!((read.layout, read.len()), (layout, packed.len()), "{ext}");
        let full = read.expanded();
        assert_eq!(full.components, 9, "{ext}");
        for i in 0..packed.len() {
            let (p, f) = (packed.item(i), full.item(i));
            assert_eq!(f, &sym2_to_tensor9(p[0], p[1], p[2], 1.0), "{ext}, vertex {i}");
        }
        let full = read;
        assert_eq!(full, packed, "{ext}");
        // And back to Medit: packed again, bit for bit.
        let medit = WriteOptions {
            medit: MeditWrite { binary: true },
            main_name: Some("x.meshb".into()),
            ..WriteOptions::default()
        };
        let (_, again) = roundtrip(Format::Medit, "meshb", &back, &medit);
        let again = &again.point_data["metric"];
        assert_eq!(again.layout, Layout::Symmetric2, "{ext}");
        assert!(
            again.values.iter().zip(&packed.values).all(|(a, b)| a.to_bits() == b.to_bits()),
            "{ext}"
        );
    }
}

/// Equality looks through the packing: a packed tensor equals the full one it stands
/// for, not one that differs in a single implied entry.
#[test]
fn packed_and_full_tensors_compare_by_what_they_stand_for() {
    let packed = DataArray::symmetric2(vec![4.0, -1.0, 9.0, 1.0, 0.0, 1.0]);
    let mut full = DataArray::new(
        9,
        [sym2_to_tensor9(4.0, -1.0, 9.0, 1.0), sym2_to_tensor9(1.0, 0.0, 1.0, 1.0)].concat(),
    );
    assert_eq!(packed, full);
    assert_eq!(full, packed);
    full.values[8] = 2.0; // zz of vertex 0 is no longer the implied 1
    assert_ne!(packed, full);
    // Three plain components are a vector, not a packed tensor.
    assert_ne!(packed, DataArray::new(3, packed.values.clone()));
    assert!(!DataArray::new(3, packed.values.clone()).is_tensor());
}

/// Cells index points with 32 bits: a 64-bit vertex number past that range is refused
/// with its value, not wrapped onto a vertex that exists (2^32 + 1 would be vertex 1).
#[test]
fn malformed_binary_vertex_number_past_32_bits() {
    let b = handmade(4, true);
    // Triangles (code 6): code, 8-byte offset, count 1, then the vertex numbers.
    let at = (8..b.len() - 20)
        .find(|&i| b[i..i + 4] == 6i32.to_le_bytes() && b[i + 12..i + 20] == 1i64.to_le_bytes())
        .unwrap();
    let mut bad = b.clone();
    bad[at + 20..at + 28].copy_from_slice(&((1i64 << 32) + 1).to_le_bytes());
    let e = read_alone(&bad, "meshb").unwrap_err();
    assert!(matches!(e.kind, ErrorKind::IndexOutOfRange { index: 4_294_967_297, .. }), "{e}");
    assert_eq!(byte_of(&e), at as u64 + 20);
    // The well-formed file reads.
    assert_eq!(read_alone(&b, "meshb").unwrap().blocks.iter().map(|b| b.len()).sum::<usize>(), 1);
}

#[test]
fn an_empty_file_is_not_a_mesh() {
    for text in ["", "# only a comment\n", "MeshVersionFormatted 2\nDimension 2\nEnd\n"] {
        let e = read_alone(text.as_bytes(), "mesh").unwrap_err();
        assert!(e.to_string().contains("Vertices"), "{text:?}: {e}");
        assert!(e.is_input_error());
    }
    // A mesh of 0 vertices that says so is one.
    assert!(read_alone(b"MeshVersionFormatted 2\nDimension 2\nVertices\n0\nEnd\n", "mesh").is_ok());
}

#[test]
fn an_empty_solution_beside_a_mesh_is_an_error() {
    let mesh = format!("{HEAD}{SQUARE}End\n");
    let e = read_with_sol(mesh.as_bytes(), "mesh", "sol", b"").unwrap_err();
    assert!(e.to_string().starts_with("<memory>.sol: "), "{e}");
    assert!(e.to_string().contains("empty"), "{e}");
}

#[test]
fn a_cr_only_file_reads_as_its_lines() {
    let text = format!("# written on an old Mac\n{HEAD}{SQUARE}Triangles\n1\n1 2 3 7\nEnd\n")
        .replace('\n', "\r");
    let m = read_alone(text.as_bytes(), "mesh").unwrap();
    assert_eq!(m.points.len(), 4);
    assert_eq!(m.blocks[0].physical, vec![7]);
}

#[test]
fn numbers_below_one_say_that_medit_counts_from_one() {
    let (b, _, triangles) = strip_meshb(4);
    let mut bad = b.clone();
    bad[triangles..triangles + 4].copy_from_slice(&(-4i32).to_le_bytes());
    let s = read_alone(&bad, "meshb").unwrap_err().to_string();
    assert!(s.contains("numbered from 1") && s.contains("-4, a negative number"), "{s}");
    assert!(!s.contains("only 0 exist"), "{s}");
    let s = ascii_err(&format!("{SQUARE}Edges\n1\n0 1 0\nEnd\n")).to_string();
    assert!(s.contains("numbered from 1") && s.contains("refers to 0"), "{s}");
    assert!(!s.contains("only"), "{s}");
}

#[test]
fn point_cells_are_written_as_corners_and_required_vertices() {
    let mut m = full_mesh();
    m.blocks.push(CellBlock {
        kind: CellKind::Vertex,
        nodes: vec![4, 1],
        physical: vec![0, 0],
        geometrical: vec![0, 0],
    });
    m.point_sets.insert("Corners".into(), vec![2, 4]);
    for main in ["c.mesh", "c.meshb"] {
        let ext = main.rsplit('.').next().unwrap();
        let (w, back) = roundtrip(Format::Medit, ext, &m, &opts(main));
        // Said, with what it does to the count of cells.
        assert_eq!(
            w.report.dropped,
            vec!["2 point cells: written as Corners and RequiredVertices entries, which are not cells (the file has 2 cells fewer)"],
            "{main}"
        );
        assert_eq!(back.num_cells(), m.num_cells() - 2, "{main}");
        assert_eq!(back.point_sets["Corners"], vec![1, 2, 4], "{main}");
        // full_mesh lists vertex 5 as required already.
        assert_eq!(back.point_sets["RequiredVertices"], vec![1, 4, 5], "{main}");
    }
}
