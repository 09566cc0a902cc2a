//! VTK legacy and XML: the public fixtures, round trips in every variant, property
//! tests and malformed inputs.

use smartmesh_formats::VtkWrite;
use smartmesh_test_support::formats as common;

use std::collections::BTreeMap;

use smartmesh_formats::{
    read_bytes, sym2_to_tensor9, write_bytes, CellKind, DataArray, ErrorKind, Format, Layout,
    Position, ReadContext, TaggedMesh, VtuEncoding, WriteOptions,
};

const FIXTURES: [&str; 6] = [
    "vtk/naca0012_ascii.vtu",
    "vtk/naca0012_binary_zlib.vtu",
    "vtk/naca0012_appended_raw.vtu",
    "vtk/naca0012_legacy_binary.vtk",
    "vtk/naca0012_legacy_ascii.vtk",
    "vtk/naca0012_legacy51_ascii.vtk",
];

/// Encodings that store doubles exactly (VTK's legacy ASCII writer rounds to 11
/// significant digits).
const EXACT: [&str; 4] = [
    "vtk/naca0012_ascii.vtu",
    "vtk/naca0012_binary_zlib.vtu",
    "vtk/naca0012_appended_raw.vtu",
    "vtk/naca0012_legacy_binary.vtk",
];

fn read(format: Format, bytes: &[u8]) -> smartmesh_formats::Result<TaggedMesh> {
    read_bytes(
        format,
        bytes,
        &ReadContext::alone(if format == Format::Vtu { "vtu" } else { "vtk" }),
    )
}

/// Every variant the writers offer: (label, format, options).
fn variants() -> Vec<(String, Format, WriteOptions)> {
    common::vtk_variants()
        .into_iter()
        .map(|(format, vtk)| {
            let label = if format == Format::VtkLegacy {
                let (major, minor) = vtk.legacy_version;
                format!(
                    "legacy {major}.{minor} {}",
                    if vtk.legacy_binary { "binary" } else { "ascii" }
                )
            } else {
                format!("vtu {:?}{}", vtk.vtu_encoding, if vtk.compress { " zlib" } else { "" })
            };
            (label, format, WriteOptions { vtk, ..WriteOptions::default() })
        })
        .collect()
}

// The expected counts were found independently of this crate: VTK 9.7.2's own readers
// (vtkXMLUnstructuredGridReader, vtkUnstructuredGridReader, from Python) give 1904
// points and 3640 cells, all of VTK type 5 with `gmsh:physical` = 3, in all six files;
// `grep -c` on the legacy ASCII file agrees (3640 lines `3 a b c` after `CELLS 3640
// 14560`, and `gmsh:physical` RangeMin = RangeMax = 3 in the .vtu files).
const NPOINTS: usize = 1904;
const NTRIANGLES: usize = 3640;
const FLUID: i32 = 3;

#[test]
fn every_public_fixture_reads_with_the_expected_counts() {
    smartmesh_test_support::require_public_fixtures!();
    for rel in FIXTURES {
        let m = common::read_file(rel);
        assert_eq!(m.points.len(), NPOINTS, "{rel}");
        assert_eq!(m.coordinate_dim, 2, "{rel}: every z is 0");
        let expected: BTreeMap<(String, i32), usize> =
            [(("triangle".to_string(), FLUID), NTRIANGLES)].into();
        assert_eq!(common::counts_per_tag(&m), expected, "{rel}");
        // No `gmsh:geometrical` in the files: the physical tag stands for both.
        assert!(m.blocks.iter().all(|b| b.physical == b.geometrical), "{rel}");
        // A 2D metric (zz = 1, zero off the xy block): kept packed, whatever the
        // encoding, and 9 components once expanded.
        assert_eq!(m.point_data["metric"].layout, Layout::Symmetric2, "{rel}");
        assert_eq!(m.point_data["metric"].expanded().components, 9, "{rel}");
        assert_eq!(m.point_data["metric"].len(), NPOINTS, "{rel}");
        assert_eq!(m.point_data["hmin"].components, 1, "{rel}");
        assert!(m.cell_data.is_empty(), "{rel}: the tags are not cell data");
        // The metric is a 2D tensor with zz = 1: symmetric, zero off the xy block.
        for t in m.point_data["metric"].expanded().values.chunks(9) {
            assert_eq!(t[1], t[3], "{rel}");
            assert_eq!([t[2], t[5], t[6], t[7], t[8]], [0.0, 0.0, 0.0, 0.0, 1.0], "{rel}");
        }
    }
}

fn bits(v: &[f64]) -> Vec<u64> {
    v.iter().map(|x| x.to_bits()).collect()
}

fn flat(m: &TaggedMesh) -> Vec<f64> {
    m.points.iter().flatten().copied().collect()
}

#[test]
fn all_six_fixtures_hold_the_same_mesh() {
    smartmesh_test_support::require_public_fixtures!();
    let reference = common::read_file(EXACT[0]);
    for rel in FIXTURES {
        let m = common::read_file(rel);
        assert_eq!(m.blocks, reference.blocks, "{rel}: cells and tags");
        if EXACT.contains(&rel) {
            assert_eq!(bits(&flat(&m)), bits(&flat(&reference)), "{rel}: points bitwise");
            for name in ["metric", "hmin"] {
                assert_eq!(
                    bits(&m.point_data[name].values),
                    bits(&reference.point_data[name].values),
                    "{rel}: {name} bitwise"
                );
                assert_eq!(
                    m.point_data[name].layout, reference.point_data[name].layout,
                    "{rel}: {name}"
                );
            }
        } else {
            // Legacy ASCII as VTK writes it: 11 significant digits.
            let close = |a: &[f64], b: &[f64]| {
                a.len() == b.len()
                    && a.iter().zip(b).all(|(x, y)| (x - y).abs() <= 1e-10 * x.abs().max(y.abs()))
            };
            assert!(close(&flat(&m), &flat(&reference)), "{rel}: points");
            for name in ["metric", "hmin"] {
                assert!(
                    close(&m.point_data[name].values, &reference.point_data[name].values),
                    "{rel}: {name}"
                );
            }
        }
    }
    // The two legacy ASCII files (4.2 and 5.1) agree with each other exactly.
    let a = common::read_file("vtk/naca0012_legacy_ascii.vtk");
    let b = common::read_file("vtk/naca0012_legacy51_ascii.vtk");
    assert_eq!(a, b);
}

/// The naca0012 mesh with everything the writers must keep: names, cell data,
/// vectors, 2- and 4-component arrays, boundary lines and a vertex.
fn rich_mesh() -> TaggedMesh {
    let mut m = common::read_file("vtk/naca0012_binary_zlib.vtu");
    m.tag_names.insert((2, FLUID), "Fluid".into());
    m.tag_names.insert((1, 7), "far field".into());
    m.tag_names.insert((0, 9), "Trailing<Edge>&\"".into());
    let mut lines = smartmesh_formats::CellBlock::new(CellKind::Line);
    lines.push(&[0, 1], 7, 70);
    lines.push(&[1, 2], 7, 71);
    let mut verts = smartmesh_formats::CellBlock::new(CellKind::Vertex);
    verts.push(&[5], 9, -9);
    m.blocks.insert(0, lines);
    m.blocks.push(verts);
    let nc = m.num_cells();
    let np = m.points.len();
    m.cell_data.insert(
        "quality".into(),
        DataArray::new(1, (0..nc).map(|i| 1.0 / (i as f64 + 3.0)).collect()),
    );
    m.cell_data.insert(
        "centroid".into(),
        DataArray::new(3, (0..3 * nc).map(|i| (i as f64).sqrt()).collect()),
    );
    m.point_data.insert(
        "velocity".into(),
        DataArray::new(3, (0..3 * np).map(|i| (i as f64 * 0.37).sin()).collect()),
    );
    m.point_data
        .insert("uv".into(), DataArray::new(2, (0..2 * np).map(|i| i as f64 * 1e-7).collect()));
    m.point_data
        .insert("four".into(), DataArray::new(4, (0..4 * np).map(|i| -(i as f64) / 7.0).collect()));
    m.point_data.insert(
        "size_tensor".into(),
        DataArray::new(
            9,
            m.point_data["metric"].expanded().values.iter().map(|v| v.sqrt()).collect(),
        ),
    );
    m
}

#[test]
fn every_variant_reads_back_identically() {
    smartmesh_test_support::require_public_fixtures!();
    let m = rich_mesh();
    for (label, format, opts) in variants() {
        let (written, back) =
            common::roundtrip(format, if format == Format::Vtu { "vtu" } else { "vtk" }, &m, &opts);
        assert!(written.report.dropped.is_empty(), "{label}: {:?}", written.report.dropped);
        assert_eq!(bits(&flat(&back)), bits(&flat(&m)), "{label}: points");
        assert_eq!(back, m, "{label}");
    }
}

#[test]
fn output_is_deterministic() {
    smartmesh_test_support::require_public_fixtures!();
    let m = rich_mesh();
    for (label, format, opts) in variants() {
        let a = write_bytes(format, &m, &opts).unwrap().main;
        let b = write_bytes(format, &m, &opts).unwrap().main;
        assert!(a == b, "{label}");
    }
}

#[test]
fn quadratic_cells_round_trip() {
    let mut m = TaggedMesh::new();
    m.points = (0..9).map(|i| [(i % 3) as f64, (i / 3) as f64, 0.0]).collect();
    for (kind, nodes) in [
        (CellKind::Line3, vec![0, 2, 1]),
        (CellKind::Triangle6, vec![0, 2, 8, 1, 5, 4]),
        (CellKind::Quad8, vec![0, 2, 8, 6, 1, 5, 7, 3]),
        (CellKind::Quad9, vec![0, 2, 8, 6, 1, 5, 7, 3, 4]),
        (CellKind::Quad, vec![0, 2, 8, 6]),
    ] {
        let mut b = smartmesh_formats::CellBlock::new(kind);
        b.push(&nodes, 4, 5);
        m.blocks.push(b);
    }
    for (label, format, opts) in variants() {
        let (_, back) = common::roundtrip(format, "vtk", &m, &opts);
        assert_eq!(back, m, "{label}");
    }
}

#[test]
fn what_vtk_cannot_hold_is_reported() {
    smartmesh_test_support::require_public_fixtures!();
    let mut m = rich_mesh();
    m.point_sets.insert("Corners".into(), vec![1, 2]);
    m.entities.insert((2, 1), vec![3]);
    m.cell_data.insert("gmsh:physical".into(), DataArray::new(1, vec![0.0; m.num_cells()]));
    m.tag_names.insert((2, 99), "Fluid".into());
    for (label, format, opts) in variants() {
        let w = write_bytes(format, &m, &opts).unwrap();
        let d = w.report.dropped.join("\n");
        for needle in [
            "point set `Corners`",
            "entity table",
            "cell data `gmsh:physical`",
            "tag name `Fluid` of (2, 99)",
        ] {
            assert!(d.contains(needle), "{label}: {needle} not in\n{d}");
        }
    }
}

#[test]
fn legacy_files_put_the_tensor_where_paraview_looks() {
    smartmesh_test_support::require_public_fixtures!();
    let m = rich_mesh();
    let w = write_bytes(Format::VtkLegacy, &m, &WriteOptions::default()).unwrap();
    let text = String::from_utf8(w.main).unwrap();
    // `size_tensor` glyphs at scale 1, so it is the active tensor.
    assert!(text.contains("\nTENSORS size_tensor double\n"));
    assert!(text.contains("\nmetric 9 1904 double\n"));
    assert!(text.contains("\ngmsh:physical 1 3643 int\n"));
    assert!(text.contains("\ngmsh:geometrical 1 3643 int\n"));
    assert!(text.contains("\nfar%20field 1 2 int\n7 1\n"));
    let w = write_bytes(
        Format::Vtu,
        &m,
        &WriteOptions {
            vtk: VtkWrite {
                compress: false,
                vtu_encoding: VtuEncoding::Ascii,
                ..Default::default()
            },
            ..Default::default()
        },
    )
    .unwrap();
    let text = String::from_utf8(w.main).unwrap();
    assert!(text.contains("<PointData Tensors=\"size_tensor\">"));
    assert!(text.contains("Name=\"metric\" NumberOfComponents=\"9\""));
    assert!(text.contains("type=\"Int32\" Name=\"gmsh:geometrical\""));
}

#[test]
fn cell_entity_ids_become_both_tags() {
    let text = "# vtk DataFile Version 4.2\nx\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 3 float\n0 0 0 1 0 0 0 1 0\nCELLS 1 4\n3 0 1 2\nCELL_TYPES 1\n5\nCELL_DATA 1\nSCALARS CellEntityIds int 1\nLOOKUP_TABLE default\n12\n";
    let m = read(Format::VtkLegacy, text.as_bytes()).unwrap();
    assert_eq!((m.blocks[0].physical[0], m.blocks[0].geometrical[0]), (12, 12));
    assert!(m.cell_data.is_empty());
}

#[test]
fn legacy_attributes_of_every_kind_are_read() {
    let text = "# vtk DataFile Version 3.0\nattributes\nASCII\n\nDATASET UNSTRUCTURED_GRID\nPOINTS 3 double\n0 0 0\n1 0 0\n0 1 0\n\nCELLS 1 4\n3 0 1 2\nCELL_TYPES 1\n5\n\
POINT_DATA 3\nSCALARS s float\nLOOKUP_TABLE default\n1 2 3\nSCALARS two%20words double 2\nLOOKUP_TABLE default\n1 2 3 4 5 6\nVECTORS v double\n1 2 3 4 5 6 7 8 9\n\
NORMALS n float\n0 0 1 0 0 1 0 0 1\nTENSORS6 t6 double\n1 2 3 4 5 6 1 2 3 4 5 6 1 2 3 4 5 6\nTEXTURE_COORDINATES tc 2 float\n0 0 1 0 0 1\n\
LOOKUP_TABLE my_table 2\n0 0 0 1 1 1 1 1\nCOLOR_SCALARS c 3\n0 0.5 1 0 0.5 1 0 0.5 1\nGLOBAL_IDS g int\n7 8 9\n\
CELL_DATA 1\nSCALARS gmsh:physical int\nLOOKUP_TABLE default\n4\nFIELD FieldData 1\nq 2 1 double\n0.5 0.25\n";
    let m = read(Format::VtkLegacy, text.as_bytes()).unwrap();
    assert_eq!(m.point_data["s"].values, [1.0, 2.0, 3.0]);
    assert_eq!(m.point_data["two words"].components, 2);
    assert_eq!(m.point_data["v"].components, 3);
    assert_eq!(m.point_data["n"].components, 3);
    // XX YY ZZ XY YZ XZ → row-major 3x3.
    assert_eq!(m.point_data["t6"].item(0), [1.0, 4.0, 6.0, 4.0, 2.0, 5.0, 6.0, 5.0, 3.0]);
    assert_eq!(m.point_data["tc"].components, 2);
    assert_eq!(m.point_data["c"].components, 3);
    assert_eq!(m.point_data["g"].values, [7.0, 8.0, 9.0]);
    assert_eq!(m.blocks[0].physical, [4]);
    assert_eq!(m.cell_data["q"].values, [0.5, 0.25]);
    assert!(!m.point_data.contains_key("my_table"));
}

/// A tiny .vtu with a big-endian UInt32 header in the given array format, written by
/// hand from the specification (the interop test covers VTK's own writer).
fn big_endian_vtu(appended_base64: bool, compress: bool) -> Vec<u8> {
    use base64::Engine;
    let b64 = |b: &[u8]| base64::engine::general_purpose::STANDARD.encode(b);
    let arrays: Vec<(&str, &str, usize, Vec<u8>, &str)> = vec![
        (
            "Points",
            "Float32",
            3,
            [0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0]
                .iter()
                .flat_map(|v| v.to_be_bytes())
                .collect(),
            "Points",
        ),
        (
            "connectivity",
            "Int32",
            1,
            [0i32, 1, 2].iter().flat_map(|v| v.to_be_bytes()).collect(),
            "Cells",
        ),
        ("offsets", "Int32", 1, 3i32.to_be_bytes().to_vec(), "Cells"),
        ("types", "UInt8", 1, vec![5u8], "Cells"),
        ("gmsh:physical", "Int16", 1, 6i16.to_be_bytes().to_vec(), "CellData"),
        (
            "h",
            "Float64",
            1,
            [0.5f64, 0.25, 0.125].iter().flat_map(|v| v.to_be_bytes()).collect(),
            "PointData",
        ),
    ];
    let encode = |raw: &[u8]| -> (Vec<u8>, Vec<u8>) {
        if compress {
            let mut z = flate2::write::ZlibEncoder::new(Vec::new(), flate2::Compression::default());
            std::io::Write::write_all(&mut z, raw).unwrap();
            let c = z.finish().unwrap();
            let mut h = Vec::new();
            for w in [1u32, 32768, raw.len() as u32, c.len() as u32] {
                h.extend_from_slice(&w.to_be_bytes());
            }
            (h, c)
        } else {
            ((raw.len() as u32).to_be_bytes().to_vec(), raw.to_vec())
        }
    };
    let mut xml = String::from(
        "<?xml version=\"1.0\"?>\n<!-- hand-made -->\n<VTKFile type='UnstructuredGrid' version=\"0.1\" byte_order=\"BigEndian\" header_type=\"UInt32\"",
    );
    if compress {
        xml.push_str(" compressor=\"vtkZLibDataCompressor\"");
    }
    xml.push_str(">\n<UnstructuredGrid>\n<Piece NumberOfPoints=\"3\" NumberOfCells=\"1\">\n");
    let mut appended = String::new();
    for section in ["PointData", "CellData", "Points", "Cells"] {
        xml.push_str(&format!("<{section}>\n"));
        for (name, ty, comps, raw, s) in &arrays {
            if s != &section {
                continue;
            }
            let (h, d) = encode(raw);
            if appended_base64 {
                xml.push_str(&format!(
                    "<DataArray type=\"{ty}\" Name=\"{name}\" NumberOfComponents=\"{comps}\" format=\"appended\" offset=\"{}\"/>\n",
                    appended.len()
                ));
                appended.push_str(&b64(&h));
                appended.push_str(&b64(&d));
            } else {
                xml.push_str(&format!(
                    "<DataArray type=\"{ty}\" Name=\"{name}\" NumberOfComponents=\"{comps}\" format=\"binary\">\n  {}{}\n</DataArray>\n",
                    b64(&h),
                    b64(&d)
                ));
            }
        }
        xml.push_str(&format!("</{section}>\n"));
    }
    xml.push_str("</Piece>\n</UnstructuredGrid>\n");
    if appended_base64 {
        xml.push_str(&format!(
            "<AppendedData encoding=\"base64\">\n  _{appended}\n</AppendedData>\n"
        ));
    }
    xml.push_str("</VTKFile>\n");
    xml.into_bytes()
}

#[test]
fn big_endian_uint32_vtu_in_binary_and_appended_base64() {
    for appended in [false, true] {
        for compress in [false, true] {
            let m = read(Format::Vtu, &big_endian_vtu(appended, compress))
                .unwrap_or_else(|e| panic!("appended {appended} zlib {compress}: {e}"));
            assert_eq!(m.points, [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
            assert_eq!(m.blocks[0].nodes, [0, 1, 2]);
            assert_eq!(m.blocks[0].physical, [6]);
            assert_eq!(m.point_data["h"].values, [0.5, 0.25, 0.125]);
        }
    }
}

/// Property tests need the `proptest` feature (on in `cargo test --workspace`).
#[cfg(feature = "proptest")]
mod properties {
    use super::*;
    use proptest::prelude::*;
    use smartmesh_formats::arbitrary::{arb_tagged_mesh, MeshFeatures};

    fn arb_features() -> MeshFeatures {
        MeshFeatures { negative_tags: true, ..MeshFeatures::ALL }
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(48))]
        #[test]
        fn random_meshes_round_trip(m in arb_tagged_mesh(arb_features()), k in 0usize..9) {
            let (label, format, opts) = variants().swap_remove(k);
            let (_, back) = common::roundtrip(format, "vtk", &m, &opts);
            prop_assert_eq!(bits(&flat(&back)), bits(&flat(&m)), "{}", label);
            prop_assert_eq!(back, m, "{}", label);
        }

        #[test]
        fn truncated_or_corrupted_files_never_panic(m in arb_tagged_mesh(MeshFeatures::ALL), k in 0usize..9, cut in 0.0..1.0f64, flip in any::<(usize, u8)>()) {
            let (_, format, opts) = variants().swap_remove(k);
            let bytes = write_bytes(format, &m, &opts).unwrap().main;
            let n = (bytes.len() as f64 * cut) as usize;
            let _ = read(format, &bytes[..n]);
            let mut bad = bytes.clone();
            let i = flip.0 % bad.len();
            bad[i] ^= flip.1 | 1;
            let _ = read(format, &bad);
        }
    }
}

// ---------------------------------------------------------------------------------
// Malformed inputs: each names what is wrong and where.

const TRI: &str =
    "# vtk DataFile Version 4.2\nt\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 3 double\n0 0 0\n1 0 0\n0 1 0\nCELLS 1 4\n3 0 1 2\nCELL_TYPES 1\n5\n";

fn legacy_err(text: &str) -> smartmesh_formats::Error {
    read(Format::VtkLegacy, text.as_bytes()).expect_err("must fail")
}

#[test]
fn legacy_truncated_points() {
    let e = legacy_err("# vtk DataFile Version 4.2\nt\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 3 double\n0 0 0\n1 0");
    assert!(
        matches!(e.kind, ErrorKind::UnexpectedEof { .. } | ErrorKind::ImplausibleCount { .. }),
        "{e}"
    );
    assert!(matches!(e.at, Some(Position::Line(5..=7))), "{e}");
}

#[test]
fn legacy_truncated_binary() {
    smartmesh_test_support::require_public_fixtures!();
    let m = common::read_file("vtk/naca0012_legacy_binary.vtk");
    let bytes = write_bytes(
        Format::VtkLegacy,
        &m,
        &WriteOptions {
            vtk: VtkWrite { legacy_binary: true, ..Default::default() },
            ..Default::default()
        },
    )
    .unwrap()
    .main;
    let e = read(Format::VtkLegacy, &bytes[..bytes.len() / 2]).unwrap_err();
    assert!(matches!(e.at, Some(Position::Byte(_))), "{e}");
    assert!(e.to_string().contains("byte"), "{e}");
}

#[test]
fn legacy_bad_cell_list_size() {
    let e = legacy_err(&TRI.replace("CELLS 1 4", "CELLS 1 5"));
    assert!(matches!(e.kind, ErrorKind::Inconsistent(_) | ErrorKind::UnexpectedEof { .. }), "{e}");
    let e = legacy_err(&TRI.replace("CELLS 1 4\n3 0 1 2", "CELLS 1 4\n4 0 1 2"));
    assert!(e.to_string().contains("node count for cell 0"), "{e}");
}

#[test]
fn legacy_cell_list_runs_out() {
    // Two cells announced, the first uses the whole list.
    let e = legacy_err(&TRI.replace("CELLS 1 4\n3 0 1 2", "CELLS 2 4\n3 0 1 2\n3 0 1 2"));
    assert!(e.to_string().contains("the list ends before cell 1"), "{e}");
    let mut m = TaggedMesh::new();
    m.points = vec![[0.0; 3]; 3];
    m.blocks.push(smartmesh_formats::CellBlock::new(CellKind::Triangle));
    m.blocks[0].push(&[0, 1, 2], 1, 1);
    let bytes = write_bytes(
        Format::VtkLegacy,
        &m,
        &WriteOptions {
            vtk: VtkWrite { legacy_binary: true, ..Default::default() },
            ..Default::default()
        },
    )
    .unwrap()
    .main;
    let i = memchr::memmem::find(&bytes, b"CELLS 1 4").unwrap();
    let mut bad = bytes.clone();
    bad[i..i + 9].copy_from_slice(b"CELLS 2 4");
    let e = read(Format::VtkLegacy, &bad).unwrap_err();
    assert!(e.to_string().contains("the list ends before cell 1"), "{e}");
    assert!(matches!(e.at, Some(Position::Byte(_))), "{e}");
}

#[test]
fn vtu_string_field_data_is_skipped() {
    let text = VTU.replace(
        "<UnstructuredGrid>\n",
        "<UnstructuredGrid>\n<FieldData><DataArray type=\"String\" Name=\"note\" NumberOfTuples=\"1\" format=\"ascii\">104 105 0</DataArray></FieldData>\n",
    );
    assert!(read(Format::Vtu, text.as_bytes()).is_ok());
    let e =
        vtu_err(&VTU.replace(
            "type=\"Int64\" Name=\"connectivity\"",
            "type=\"String\" Name=\"connectivity\"",
        ));
    assert!(matches!(e.kind, ErrorKind::Unsupported(_)), "{e}");
}

#[test]
fn vtu_huge_component_count() {
    let e = vtu_err(&VTU.replace("</Points>", "</Points><PointData><DataArray type=\"Float64\" Name=\"x\" NumberOfComponents=\"9000000000000000000\" format=\"ascii\">1</DataArray></PointData>"));
    assert!(matches!(e.kind, ErrorKind::ImplausibleCount { .. }), "{e}");
}

#[test]
fn legacy_cell_types_count_differs() {
    let e = legacy_err(&TRI.replace("CELL_TYPES 1\n5", "CELL_TYPES 2\n5 5"));
    assert!(e.to_string().contains("CELL_TYPES 2 after CELLS with 1 cells"), "{e}");
    assert_eq!(e.at, Some(Position::Line(11)));
}

#[test]
fn legacy_index_out_of_range() {
    let e = legacy_err(&TRI.replace("3 0 1 2", "3 0 1 3"));
    assert!(matches!(e.kind, ErrorKind::IndexOutOfRange { index: 3, available: 3, .. }), "{e}");
    assert_eq!(e.at, Some(Position::Line(10)));
    let e = legacy_err(&TRI.replace("3 0 1 2", "3 0 -1 2"));
    assert!(matches!(e.kind, ErrorKind::IndexOutOfRange { index: -1, .. }), "{e}");
}

#[test]
fn legacy_nan_coordinate() {
    let e = legacy_err(&TRI.replace("1 0 0\n", "1 nan 0\n"));
    assert!(matches!(e.kind, ErrorKind::NonFinite { .. }), "{e}");
    assert_eq!(e.at, Some(Position::Line(7)));
}

/// NaN in a data array is kept (VTK and meshio read such a file); only coordinates
/// refuse it.
#[test]
fn legacy_nan_in_binary_data_is_kept() {
    smartmesh_test_support::require_public_fixtures!();
    let mut m = common::read_file("vtk/naca0012_legacy_binary.vtk");
    m.point_data.get_mut("hmin").unwrap().values[5] = f64::NAN;
    let bytes = write_bytes(
        Format::VtkLegacy,
        &m,
        &WriteOptions {
            vtk: VtkWrite { legacy_binary: true, ..Default::default() },
            ..Default::default()
        },
    )
    .unwrap()
    .main;
    let back = read(Format::VtkLegacy, &bytes).unwrap();
    let hmin = &back.point_data["hmin"].values;
    assert!(hmin[5].is_nan());
    assert_eq!(hmin[4], m.point_data["hmin"].values[4]);
}

#[test]
fn legacy_huge_counts() {
    let e = legacy_err("# vtk DataFile Version 4.2\nt\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 1000000000000000 double\n0 0 0\n");
    assert!(matches!(e.kind, ErrorKind::ImplausibleCount { .. }), "{e}");
    let e = legacy_err(&TRI.replace("CELLS 1 4", "CELLS 99999999999 99999999999"));
    assert!(matches!(e.kind, ErrorKind::ImplausibleCount { .. }), "{e}");
    let e = legacy_err(&format!("{TRI}POINT_DATA 3\nFIELD f 1\nx 99999999999 3 double\n1 2 3\n"));
    assert!(matches!(e.kind, ErrorKind::ImplausibleCount { .. }), "{e}");
}

#[test]
fn legacy_unsupported_cell_type() {
    let e = legacy_err(&TRI.replace("CELL_TYPES 1\n5", "CELL_TYPES 1\n42"));
    assert!(e.to_string().contains("cell 0 is a VTK polyhedron (type 42)"), "{e}");
    assert_eq!(e.at, Some(Position::Line(11)));
    let e = legacy_err(&TRI.replace("CELL_TYPES 1\n5", "CELL_TYPES 1\n9"));
    assert!(e.to_string().contains("4 nodes for cell 0"), "{e}");
}

#[test]
fn legacy_unsupported_dataset() {
    let e = legacy_err("# vtk DataFile Version 4.2\nt\nASCII\nDATASET FIELD\nPOINTS 0 float\n");
    assert!(matches!(e.kind, ErrorKind::Unsupported(_)), "{e}");
    assert_eq!(e.at, Some(Position::Line(4)));
}

#[test]
fn legacy_bad_header() {
    let e = legacy_err("# not vtk\n");
    assert_eq!(e.at, Some(Position::Line(1)));
    let e = legacy_err("# vtk DataFile Version 4.2\nt\nUTF16\n");
    assert_eq!(e.at, Some(Position::Line(3)));
    let e = legacy_err(&TRI.replace("CELL_TYPES", "CELL_KINDS"));
    assert!(e.to_string().contains("a VTK legacy keyword"), "{e}");
}

#[test]
fn legacy_51_offsets_must_rise() {
    let text = "# vtk DataFile Version 5.1\nt\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 3 double\n0 0 0 1 0 0 0 1 0\nCELLS 2 3\nOFFSETS vtktypeint64\n0 4\nCONNECTIVITY vtktypeint64\n0 1 2\nCELL_TYPES 1\n5\n";
    let e = legacy_err(text);
    assert!(matches!(e.kind, ErrorKind::Inconsistent(_)), "{e}");
    assert!(read(Format::VtkLegacy, text.replace("0 4", "0 3").as_bytes()).is_ok());
}

#[test]
fn legacy_data_count_differs() {
    let e = legacy_err(&format!("{TRI}POINT_DATA 4\n"));
    assert!(e.to_string().contains("POINT_DATA 4, but the dataset has 3"), "{e}");
    let e = legacy_err(&format!("{TRI}SCALARS s double\n1 2 3\n"));
    assert!(e.to_string().contains("POINT_DATA or CELL_DATA"), "{e}");
}

const VTU: &str = r#"<?xml version="1.0"?>
<VTKFile type="UnstructuredGrid" version="0.1" byte_order="LittleEndian">
  <UnstructuredGrid>
    <Piece NumberOfPoints="3" NumberOfCells="1">
      <Points>
        <DataArray type="Float64" NumberOfComponents="3" format="ascii">0 0 0 1 0 0 0 1 0</DataArray>
      </Points>
      <Cells>
        <DataArray type="Int64" Name="connectivity" format="ascii">0 1 2</DataArray>
        <DataArray type="Int64" Name="offsets" format="ascii">3</DataArray>
        <DataArray type="UInt8" Name="types" format="ascii">5</DataArray>
      </Cells>
    </Piece>
  </UnstructuredGrid>
</VTKFile>
"#;

fn vtu_err(text: &str) -> smartmesh_formats::Error {
    let e = read(Format::Vtu, text.as_bytes()).expect_err("must fail");
    assert!(matches!(e.at, Some(Position::Byte(_))), "{e}: no byte offset");
    e
}

#[test]
fn vtu_minimal_file_reads() {
    let m = read(Format::Vtu, VTU.as_bytes()).unwrap();
    assert_eq!(m.num_cells_of(CellKind::Triangle), 1);
}

#[test]
fn vtu_truncated() {
    smartmesh_test_support::require_public_fixtures!();
    let e = vtu_err(&VTU[..VTU.find("<Cells>").unwrap() + 20]);
    assert!(matches!(e.kind, ErrorKind::UnexpectedEof { .. } | ErrorKind::Expected { .. }), "{e}");
    let m = rich_mesh();
    let bytes = write_bytes(
        Format::Vtu,
        &m,
        &WriteOptions {
            vtk: VtkWrite {
                vtu_encoding: VtuEncoding::Appended,
                compress: false,
                ..Default::default()
            },
            ..Default::default()
        },
    )
    .unwrap()
    .main;
    let e = read(Format::Vtu, &bytes[..bytes.len() - 5000]).unwrap_err();
    assert!(matches!(e.kind, ErrorKind::UnexpectedEof { .. }), "{e}");
}

#[test]
fn vtu_bad_counts() {
    let e = vtu_err(&VTU.replace("NumberOfPoints=\"3\"", "NumberOfPoints=\"4\""));
    assert!(e.to_string().contains("DataArray `Points` announces 12 items"), "{e}");
    let e = vtu_err(&VTU.replace("NumberOfPoints=\"3\"", "NumberOfPoints=\"2\""));
    assert!(e.to_string().contains("has 9 values, expected 6"), "{e}");
    let e = vtu_err(&VTU.replace(">3</DataArray>", ">4</DataArray>"));
    assert!(e.to_string().contains("DataArray `connectivity` announces 4 items"), "{e}");
    let e = vtu_err(&VTU.replace(">3</DataArray>", ">2</DataArray>"));
    assert!(e.to_string().contains("`connectivity` has 3 values, expected 2"), "{e}");
}

#[test]
fn vtu_huge_counts() {
    let e = vtu_err(&VTU.replace("NumberOfPoints=\"3\"", "NumberOfPoints=\"100000000000000\""));
    assert!(matches!(e.kind, ErrorKind::ImplausibleCount { .. }), "{e}");
    let e = vtu_err(&VTU.replace("NumberOfCells=\"1\"", "NumberOfCells=\"100000000000000\""));
    assert!(matches!(e.kind, ErrorKind::ImplausibleCount { .. }), "{e}");
}

#[test]
fn vtu_index_out_of_range() {
    let e = vtu_err(&VTU.replace(">0 1 2<", ">0 1 7<"));
    assert!(matches!(e.kind, ErrorKind::IndexOutOfRange { index: 7, available: 3, .. }), "{e}");
}

#[test]
fn vtu_nan() {
    let e = vtu_err(&VTU.replace("0 0 0 1 0 0", "0 0 0 1 NaN 0"));
    assert!(matches!(e.kind, ErrorKind::NonFinite { .. }), "{e}");
    assert_eq!(e.at, Some(Position::Byte(VTU.find("0 0 0 1 0 0").unwrap() as u64 + 8)));
}

#[test]
fn vtu_bad_base64() {
    smartmesh_test_support::require_public_fixtures!();
    let m = rich_mesh();
    let bytes = write_bytes(
        Format::Vtu,
        &m,
        &WriteOptions {
            vtk: VtkWrite {
                vtu_encoding: VtuEncoding::Binary,
                compress: false,
                ..Default::default()
            },
            ..Default::default()
        },
    )
    .unwrap()
    .main;
    let text = String::from_utf8(bytes).unwrap();
    let i = text.find("format=\"binary\">").unwrap() + 40;
    let mut bad = text.into_bytes();
    bad[i] = b'!';
    let e = read(Format::Vtu, &bad).unwrap_err();
    assert!(e.to_string().contains("base64"), "{e}");
    assert!(matches!(e.at, Some(Position::Byte(_))));
}

#[test]
fn vtu_bad_zlib() {
    smartmesh_test_support::require_public_fixtures!();
    let m = rich_mesh();
    let bytes = write_bytes(
        Format::Vtu,
        &m,
        &WriteOptions {
            vtk: VtkWrite {
                vtu_encoding: VtuEncoding::Appended,
                compress: true,
                ..Default::default()
            },
            ..Default::default()
        },
    )
    .unwrap()
    .main;
    let base = memchr::memmem::find(&bytes, b"   _").unwrap() + 4;
    let mut bad = bytes.clone();
    // Inside the first array's first compressed block (after a 4-block header at most).
    for b in &mut bad[base + 80..base + 120] {
        *b ^= 0x5a;
    }
    let e = read(Format::Vtu, &bad).unwrap_err();
    assert!(e.to_string().contains("zlib"), "{e}");
}

#[test]
fn vtu_zlib_header_claims_too_much() {
    // One block of 2^40 bytes from 10 compressed bytes: refused before allocation.
    let mut h = Vec::new();
    for w in [1u64, 1 << 40, 1 << 40, 10] {
        h.extend_from_slice(&w.to_le_bytes());
    }
    h.extend_from_slice(&[0u8; 10]);
    use base64::Engine;
    let b = base64::engine::general_purpose::STANDARD.encode(&h);
    let text = VTU
        .replace(
            "version=\"0.1\"",
            "version=\"1.0\" header_type=\"UInt64\" compressor=\"vtkZLibDataCompressor\"",
        )
        .replace("format=\"ascii\">0 0 0 1 0 0 0 1 0<", &format!("format=\"binary\">{b}<"));
    let e = vtu_err(&text);
    assert!(matches!(e.kind, ErrorKind::ImplausibleCount { .. }), "{e}");
}

#[test]
fn vtu_unsupported_compressor_and_type() {
    let e = vtu_err(&VTU.replace("version=\"0.1\"", "compressor=\"vtkLZ4DataCompressor\""));
    assert!(e.to_string().contains("vtkLZ4DataCompressor"), "{e}");
    let e = vtu_err(&VTU.replace("UnstructuredGrid\" version", "ImageData\" version"));
    assert!(matches!(e.kind, ErrorKind::Unsupported(_)), "{e}");
    let e = vtu_err(&VTU.replace(
        "UInt8\" Name=\"types\" format=\"ascii\">5",
        "UInt8\" Name=\"types\" format=\"ascii\">10",
    ));
    assert!(e.to_string().contains("tetra"), "{e}");
    let e = vtu_err(&VTU.replace("LittleEndian", "MiddleEndian"));
    assert!(e.to_string().contains("byte_order"), "{e}");
}

#[test]
fn vtu_missing_appended_data() {
    let e = vtu_err(&VTU.replace(
        "format=\"ascii\">0 0 0 1 0 0 0 1 0</DataArray>",
        "format=\"appended\" offset=\"0\"/>",
    ));
    assert!(e.to_string().contains("AppendedData"), "{e}");
}

#[test]
fn vtu_malformed_xml() {
    let e = vtu_err(&VTU.replace("<Points>", "<Points"));
    assert!(matches!(e.kind, ErrorKind::Expected { .. } | ErrorKind::UnexpectedEof { .. }), "{e}");
    let e = vtu_err(&VTU.replace("NumberOfCells=\"1\"", "NumberOfCells=1"));
    assert!(e.to_string().contains("quoted value"), "{e}");
    let e = vtu_err(
        "<VTKFile type=\"UnstructuredGrid\"><UnstructuredGrid></UnstructuredGrid></VTKFile>",
    );
    assert!(e.to_string().contains("Piece"), "{e}");
}

#[test]
fn writer_refuses_other_legacy_versions() {
    smartmesh_test_support::require_public_fixtures!();
    let m = rich_mesh();
    let e = write_bytes(
        Format::VtkLegacy,
        &m,
        &WriteOptions {
            vtk: VtkWrite { legacy_version: (3, 0), ..Default::default() },
            ..Default::default()
        },
    )
    .unwrap_err();
    assert!(e.to_string().contains("4.2 and 5.1"), "{e}");
}

#[test]
fn damaged_fixtures_fail_with_a_position() {
    smartmesh_test_support::require_public_fixtures!();
    // Deterministic damage (a fixed xorshift): truncations and flipped bytes. Every
    // read returns a mesh or an error that says where; none panics.
    let mut state = 0x9e37_79b9_7f4a_7c15u64;
    let mut next = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state
    };
    for rel in FIXTURES {
        let bytes = std::fs::read(common::public_fixture(rel)).unwrap();
        let format = if rel.ends_with(".vtu") { Format::Vtu } else { Format::VtkLegacy };
        for _ in 0..60 {
            let cut = (next() % bytes.len() as u64) as usize;
            if let Err(e) = read(format, &bytes[..cut]) {
                assert!(e.at.is_some(), "{rel} cut at {cut}: {e}");
            }
            let mut bad = bytes.clone();
            for _ in 0..3 {
                let i = (next() % bytes.len() as u64) as usize;
                bad[i] = (next() & 0xff) as u8;
            }
            if let Err(e) = read(format, &bad) {
                assert!(e.at.is_some(), "{rel} damaged: {e}");
            }
        }
    }
}

#[test]
fn empty_meshes_round_trip() {
    let mut points_only = TaggedMesh::new();
    points_only.points = vec![[1.0, 2.0, 0.0], [3.0, 4.0, 0.0]];
    for m in [TaggedMesh::new(), points_only] {
        for (label, format, opts) in variants() {
            let (_, back) = common::roundtrip(format, "vtk", &m, &opts);
            assert_eq!(back, m, "{label}");
        }
    }
}

/// Four points, two triangles, two lines: in the order `blocks` gives.
fn mixed_mesh(order: &[CellKind]) -> TaggedMesh {
    let mut m = TaggedMesh::new();
    m.points = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]];
    for (i, &kind) in order.iter().enumerate() {
        let mut b = smartmesh_formats::CellBlock::new(kind);
        let t = i as i32 + 1;
        match kind {
            CellKind::Triangle => {
                b.push(&[0, 1, 2], t, 10 + t);
                b.push(&[0, 2, 3], t, 10 + t);
            }
            _ => {
                b.push(&[0, 1], t, 10 + t);
                b.push(&[1, 2], t, 10 + t);
                b.push(&[2, 3], t, 10 + t);
            }
        }
        m.blocks.push(b);
    }
    m
}

/// The binary readers convert the largest block in place and the others by copy, and
/// read a cell list whose node counts all agree in one pass: whichever block is the
/// largest, and wherever it sits, blocks, order and tags come back as written.
#[test]
fn binary_blocks_come_back_in_order_whichever_is_largest() {
    use CellKind::{Line, Triangle};
    for order in [
        &[Triangle][..],
        &[Line],
        &[Line, Triangle],
        &[Triangle, Line],
        &[Triangle, Line, Triangle],
        &[Line, Triangle, Line],
    ] {
        let m = mixed_mesh(order);
        for (label, format, opts) in variants()
            .into_iter()
            .filter(|v| v.2.vtk.legacy_binary || v.2.vtk.vtu_encoding != VtuEncoding::Ascii)
        {
            let bytes = write_bytes(format, &m, &opts).unwrap().main;
            let back = read(format, &bytes).unwrap_or_else(|e| panic!("{label} {order:?}: {e}"));
            assert_eq!(back.blocks, m.blocks, "{label} {order:?}");
        }
    }
}

/// Big-endian 32-bit words of a legacy binary file.
fn put_be(bytes: &mut [u8], at: usize, v: i32) {
    bytes[at..at + 4].copy_from_slice(&v.to_be_bytes());
}

/// A legacy binary triangle mesh whose cell list is altered: each error names the
/// byte of the bad word.
#[test]
fn legacy_binary_cell_list_errors_name_the_byte() {
    let m = mixed_mesh(&[CellKind::Triangle]);
    let bytes = write_bytes(
        Format::VtkLegacy,
        &m,
        &WriteOptions {
            vtk: VtkWrite { legacy_binary: true, ..Default::default() },
            ..Default::default()
        },
    )
    .unwrap()
    .main;
    let list = memchr::memmem::find(&bytes, b"CELLS 2 8\n").unwrap() + b"CELLS 2 8\n".len();
    // Second triangle's last node: 3 -> 4 (out of range) and -> -1.
    for (v, shown) in [(4, 4), (-1, -1)] {
        let mut bad = bytes.clone();
        put_be(&mut bad, list + 4 * 7, v);
        let e = read(Format::VtkLegacy, &bad).unwrap_err();
        assert!(
            matches!(e.kind, ErrorKind::IndexOutOfRange { index, available: 4, .. } if index == shown),
            "{e}"
        );
        assert_eq!(e.at, Some(Position::Byte((list + 4 * 7) as u64)), "{e}");
        assert!(e.to_string().contains("cell 1"), "{e}");
    }
    // A node count that differs from the first one, which the list is too short for.
    let mut bad = bytes.clone();
    put_be(&mut bad, list + 4 * 4, 4);
    let e = read(Format::VtkLegacy, &bad).unwrap_err();
    assert!(e.to_string().contains("node count for cell 1, at most 3"), "{e}");
    assert_eq!(e.at, Some(Position::Byte((list + 16) as u64)), "{e}");
    // Counts 2 and 4 that fill the same list: read, then refused as triangles by type.
    let mut odd = bytes.clone();
    put_be(&mut odd, list, 2);
    put_be(&mut odd, list + 4 * 3, 4);
    let e = read(Format::VtkLegacy, &odd).unwrap_err();
    assert!(e.to_string().contains("3 nodes for cell 0"), "{e}");
    // A first count that takes more nodes than the counts leave room for (7 of 6): the
    // list then ends before the second cell.
    let mut long = bytes.clone();
    put_be(&mut long, list, 7);
    let e = read(Format::VtkLegacy, &long).unwrap_err();
    assert!(e.to_string().contains("the list ends before cell 1"), "{e}");
    assert_eq!(e.at, Some(Position::Byte((list + 32) as u64)), "{e}");
    // Lines then triangles (counts 2, then 3): a bad node in the last cell is named.
    let m = mixed_mesh(&[CellKind::Line, CellKind::Triangle]);
    let bytes = write_bytes(
        Format::VtkLegacy,
        &m,
        &WriteOptions {
            vtk: VtkWrite { legacy_binary: true, ..Default::default() },
            ..Default::default()
        },
    )
    .unwrap()
    .main;
    let cells = format!(
        "CELLS {} {}\n",
        m.num_cells(),
        m.num_cells() + m.blocks.iter().map(|b| b.nodes.len()).sum::<usize>()
    );
    let list = memchr::memmem::find(&bytes, cells.as_bytes()).unwrap() + cells.len();
    let last =
        list + 4 * (m.num_cells() + m.blocks.iter().map(|b| b.nodes.len()).sum::<usize>() - 1);
    let mut bad = bytes.clone();
    put_be(&mut bad, last, -7);
    let e = read(Format::VtkLegacy, &bad).unwrap_err();
    assert!(matches!(e.kind, ErrorKind::IndexOutOfRange { index: -7, .. }), "{e}");
    assert_eq!(e.at, Some(Position::Byte(last as u64)), "{e}");
    assert!(e.to_string().contains(&format!("cell {}", m.num_cells() - 1)), "{e}");
}

/// Cell types and offsets are decoded straight into their final arrays: a type that
/// does not fit a byte, a negative offset or one that does not rise is still refused,
/// with the array's byte offset, in text and in appended raw binary alike.
#[test]
fn vtu_types_and_offsets_are_checked_as_decoded() {
    let e = vtu_err(
        &VTU.replace("format=\"ascii\">5</DataArray>", "format=\"ascii\">300</DataArray>")
            .replace("UInt8", "Int32"),
    );
    assert!(
        e.to_string().contains("a VTK cell type (0 to 255)") && e.to_string().contains("300"),
        "{e}"
    );
    let e =
        vtu_err(&VTU.replace("format=\"ascii\">3</DataArray>", "format=\"ascii\">-3</DataArray>"));
    assert!(e.to_string().contains("cell end offset") && e.to_string().contains("-3"), "{e}");

    let m = mixed_mesh(&[CellKind::Line, CellKind::Triangle]);
    let opts = WriteOptions {
        vtk: VtkWrite {
            vtu_encoding: VtuEncoding::Appended,
            compress: false,
            ..Default::default()
        },
        ..Default::default()
    };
    let bytes = write_bytes(Format::Vtu, &m, &opts).unwrap().main;
    let back = read(Format::Vtu, &bytes).unwrap();
    assert_eq!(back.blocks, m.blocks);
    // The appended block holds the offsets as little-endian Int64 (3 lines, 2 triangles:
    // 2 4 6 9 12) and the types as UInt8 (3 3 3 5 5); patch them in place.
    let offsets: Vec<u8> = [2i64, 4, 6, 9, 12].iter().flat_map(|v| v.to_le_bytes()).collect();
    let at = memchr::memmem::find(&bytes, &offsets).expect("offsets in the appended data");
    let mut bad = bytes.clone();
    bad[at + 8..at + 16].copy_from_slice(&(-4i64).to_le_bytes());
    let e = read(Format::Vtu, &bad).unwrap_err();
    assert!(matches!(e.at, Some(Position::Byte(_))), "{e}");
    assert!(
        e.to_string().contains("cell end offset")
            && e.to_string().contains("value 1")
            && e.to_string().contains("-4"),
        "{e}"
    );
    let mut bad = bytes.clone();
    bad[at + 16..at + 24].copy_from_slice(&3i64.to_le_bytes());
    let e = read(Format::Vtu, &bad).unwrap_err();
    assert!(
        e.to_string().contains("offsets must rise")
            && e.to_string().contains("cell 2 ends at 3 after 4"),
        "{e}"
    );
    let types =
        memchr::memmem::find(&bytes, &[3u8, 3, 3, 5, 5]).expect("types in the appended data");
    let mut bad = bytes.clone();
    bad[types + 4] = 16;
    let e = read(Format::Vtu, &bad).unwrap_err();
    assert!(
        matches!(e.kind, ErrorKind::Unsupported(_))
            && e.to_string().contains("cell 4 has VTK type 16 (hexagonal prism)"),
        "{e}"
    );
}

/// Lines after the optional `OFFSETS` keyword are counted once: `take_word` looks for
/// it without consuming anything when it is absent (so a 4.2 binary cell list right
/// after its header's newline is read intact), and the tokenizer's `peek` no longer
/// counts the newlines before a peeked token twice (commit 7322f20).
#[test]
fn lines_after_the_optional_offsets_keyword_are_counted_once() {
    // 5.1 ASCII: node 7 on line 11.
    let v51 = "# vtk DataFile Version 5.1\nt\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 3 double\n0 0 0 1 0 0 0 1 0\nCELLS 2 3\nOFFSETS vtktypeint64\n0 3\nCONNECTIVITY vtktypeint64\n0 1 7\nCELL_TYPES 1\n5\n";
    let e = legacy_err(v51);
    assert!(matches!(e.kind, ErrorKind::IndexOutOfRange { index: 7, .. }), "{e}");
    assert_eq!(e.at, Some(Position::Line(11)), "{e}");
    // 4.2 ASCII with blank lines before the cell list: node 3 on line 12.
    let e = legacy_err(&TRI.replace("CELLS 1 4\n3 0 1 2", "CELLS 1 4\n\n\n3 0 1 3"));
    assert_eq!(e.at, Some(Position::Line(12)), "{e}");
    // The same, well formed, then an error further on: still the right line.
    let e = legacy_err(&format!(
        "{}POINT_DATA 3\nSCALARS s double\nLOOKUP_TABLE default\n1 2 x\n",
        TRI.replace("CELLS 1 4\n", "CELLS 1 4\n\n\n")
    ));
    assert_eq!(e.at, Some(Position::Line(18)), "{e}");
}

/// Cells index points with 32 bits: when CELLS comes before POINTS (so the point count
/// is not known yet), a node index past that range is refused as it is read, not
/// wrapped onto a point that exists (2^32 + 1 would be point 1).
#[test]
fn node_index_past_32_bits_is_refused_before_points() {
    let v51 = "# vtk DataFile Version 5.1\nt\nASCII\nDATASET UNSTRUCTURED_GRID\nCELLS 2 3\nOFFSETS vtktypeint64\n0 3\nCONNECTIVITY vtktypeint64\n0 4294967297 2\nCELL_TYPES 1\n5\nPOINTS 3 double\n0 0 0 1 0 0 0 1 0\n";
    let e = legacy_err(v51);
    assert!(matches!(e.kind, ErrorKind::IndexOutOfRange { index: 4_294_967_297, .. }), "{e}");
    // The same file with index 1 reads.
    let m = read(Format::VtkLegacy, v51.replace("4294967297", "1").as_bytes()).unwrap();
    assert_eq!(m.blocks[0].nodes, vec![0, 1, 2]);
}

/// 9-component arrays are read packed ([`Layout::Symmetric2`]) exactly when nothing is
/// lost: every item a finite 2D symmetric tensor with zz = 1 and zeros (positive, bit for
/// bit) off the xy block. Otherwise they stay plain, with every value as written; and a
/// non-finite value is refused as before, wherever it sits.
#[test]
fn tensors_are_packed_only_when_nothing_is_lost() {
    let metric2d =
        |i: usize| sym2_to_tensor9(1.0 + i as f64, -0.25 * i as f64, 3.0 / (1.0 + i as f64), 1.0);
    let with = |edit: &dyn Fn(usize, &mut [f64; 9])| {
        let mut m = mixed_mesh(&[CellKind::Triangle]);
        let values: Vec<f64> = (0..m.points.len())
            .flat_map(|i| {
                let mut t = metric2d(i);
                edit(i, &mut t);
                t
            })
            .collect();
        m.point_data.insert("metric".into(), DataArray::new(9, values.clone()));
        // A second tensor array (written as field data in legacy files).
        m.point_data.insert("other".into(), DataArray::new(9, values));
        m
    };
    let cases: Vec<(&str, TaggedMesh, Layout)> = vec![
        ("2D metrics", with(&|_, _| {}), Layout::Symmetric2),
        (
            "zz = 2 in the last item",
            with(&|i, t| {
                if i == 3 {
                    t[8] = 2.0
                }
            }),
            Layout::Plain,
        ),
        (
            "xz = -0.0",
            with(&|i, t| {
                if i == 2 {
                    t[2] = -0.0
                }
            }),
            Layout::Plain,
        ),
        (
            "yz = 1e-300",
            with(&|i, t| {
                if i == 1 {
                    t[5] = 1e-300
                }
            }),
            Layout::Plain,
        ),
        (
            "xy and yx differ by an ulp",
            with(&|i, t| {
                if i == 3 {
                    t[3] = f64::from_bits(t[1].to_bits() + 1)
                }
            }),
            Layout::Plain,
        ),
        (
            "a 3D tensor first",
            with(&|i, t| {
                if i == 0 {
                    t[8] = 0.5
                }
            }),
            Layout::Plain,
        ),
    ];
    for (label, format, opts) in variants() {
        for (what, m, layout) in &cases {
            let bytes = write_bytes(format, m, &opts).unwrap().main;
            let back = read(format, &bytes).unwrap_or_else(|e| panic!("{label}, {what}: {e}"));
            for name in ["metric", "other"] {
                let a = &back.point_data[name];
                assert_eq!(a.layout, *layout, "{label}, {what}: {name}");
                assert_eq!(
                    bits(&a.expanded().values),
                    bits(&m.point_data[name].values),
                    "{label}, {what}: {name}"
                );
            }
        }
        // A NaN in the last item, patched where the file's bytes can be found (raw
        // binary): kept, as by the plain decoder (NaN in data is refused where used).
        let patchable =
            (format == Format::VtkLegacy && label.ends_with("binary")) || label == "vtu Appended";
        if !patchable {
            continue;
        }
        let mut bytes = write_bytes(format, &with(&|_, _| {}), &opts).unwrap().main;
        let m22 = metric2d(3)[4];
        let (pattern, nan) = if format == Format::VtkLegacy {
            (m22.to_be_bytes(), f64::NAN.to_be_bytes())
        } else {
            (m22.to_le_bytes(), f64::NAN.to_le_bytes())
        };
        let at = memchr::memmem::find(&bytes, &pattern)
            .unwrap_or_else(|| panic!("{label}: m22 in the file"));
        bytes[at..at + 8].copy_from_slice(&nan);
        let back = read(format, &bytes).unwrap_or_else(|e| panic!("{label}: NaN: {e}"));
        let values = back.point_data["metric"].expanded().values.clone();
        assert_eq!(values.iter().filter(|v| v.is_nan()).count(), 1, "{label}");
    }
}

/// 32-bit float tensors pack too, and expand to the values a plain read gives.
#[test]
fn float32_tensors_pack() {
    let t = |m11: f32, m12: f32, m22: f32| [m11, m12, 0.0, m12, m22, 0.0, 0.0, 0.0, 1.0];
    let items = [t(1.5, -0.25, 2.0), t(0.1, 0.0, 7.0), t(3.0, 1e-3, 0.5)];
    let mut vtk =
        b"# vtk DataFile Version 4.2\nt\nBINARY\nDATASET UNSTRUCTURED_GRID\nPOINTS 3 double\n"
            .to_vec();
    for p in [[0.0f64, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]] {
        for c in p {
            vtk.extend_from_slice(&c.to_be_bytes());
        }
    }
    vtk.extend_from_slice(b"\nCELLS 1 4\n");
    for v in [3i32, 0, 1, 2] {
        vtk.extend_from_slice(&v.to_be_bytes());
    }
    vtk.extend_from_slice(b"\nCELL_TYPES 1\n");
    vtk.extend_from_slice(&5i32.to_be_bytes());
    vtk.extend_from_slice(b"\nPOINT_DATA 3\nTENSORS metric float\n");
    for item in &items {
        for v in item {
            vtk.extend_from_slice(&v.to_be_bytes());
        }
    }
    vtk.push(b'\n');
    let m = read(Format::VtkLegacy, &vtk).unwrap();
    let a = &m.point_data["metric"];
    assert_eq!(a.layout, Layout::Symmetric2);
    let expected: Vec<f64> = items.iter().flatten().map(|&v| v as f64).collect();
    assert_eq!(bits(&a.expanded().values), bits(&expected));
}

/// A zlib `.vtu` whose Points array is given by `header` (UInt64 words) and `data`.
fn zlib_points_vtu(points: usize, header: &[u64], data: &[u8]) -> String {
    use base64::Engine;
    let mut h = Vec::new();
    for w in header {
        h.extend_from_slice(&w.to_le_bytes());
    }
    h.extend_from_slice(data);
    let b = base64::engine::general_purpose::STANDARD.encode(&h);
    VTU.replace(
        "version=\"0.1\"",
        "version=\"1.0\" header_type=\"UInt64\" compressor=\"vtkZLibDataCompressor\"",
    )
    .replace("NumberOfPoints=\"3\"", &format!("NumberOfPoints=\"{points}\""))
    .replace("format=\"ascii\">0 0 0 1 0 0 0 1 0<", &format!("format=\"binary\">{b}<"))
}

#[test]
fn vtu_zlib_blocks_of_no_compressed_bytes_claim_nothing() {
    // 4096 blocks of 32 KiB (the Points of 2^22 points) from 0 compressed bytes each: a
    // 45 KB header that used to be inflated into 128 MiB before zlib said no.
    let nb = 4096u64;
    let mut header = vec![nb, 32768, 32768];
    header.extend(std::iter::repeat(0).take(nb as usize));
    let e = vtu_err(&zlib_points_vtu(1 << 22, &header, &[]));
    assert!(matches!(e.kind, ErrorKind::ImplausibleCount { .. }), "{e}");
    assert!(e.to_string().contains("block 1 of `Points`"), "{e}");
}

#[test]
fn vtu_piece_counts_are_refused_with_the_file_size() {
    let text = VTU.replace("NumberOfPoints=\"3\"", "NumberOfPoints=\"100000000000000\"");
    let e = vtu_err(&text);
    let s = e.to_string();
    assert!(s.contains(&format!("a file of {} bytes", text.len())), "{s}");
}

#[test]
fn vtu_uncounted_field_data_is_not_inflated() {
    use base64::Engine;
    // A FieldData array without NumberOfTuples claiming 2^30 bytes from one block: it
    // cannot name a tag, so it is skipped rather than inflated.
    let mut h = Vec::new();
    for w in [1u64, 1 << 30, 1 << 30, 1 << 20] {
        h.extend_from_slice(&w.to_le_bytes());
    }
    h.extend_from_slice(&vec![0u8; 1 << 20]);
    let b = base64::engine::general_purpose::STANDARD.encode(&h);
    let text = VTU
        .replace(
            "version=\"0.1\"",
            "version=\"1.0\" header_type=\"UInt64\" compressor=\"vtkZLibDataCompressor\"",
        )
        .replace(
            "<UnstructuredGrid>\n",
            &format!("<UnstructuredGrid>\n<FieldData><DataArray type=\"Float64\" Name=\"big\" format=\"binary\">{b}</DataArray></FieldData>\n"),
        );
    let m = read(Format::Vtu, text.as_bytes()).unwrap();
    assert_eq!(m.points.len(), 3);
}

#[test]
fn vtu_unnamed_points_are_named_in_messages() {
    let e = vtu_err(&VTU.replace("0 0 0 1 0 0", "0 0 0 1 NaN 0"));
    assert!(e.to_string().contains("`Points`"), "{e}");
    assert!(!e.to_string().contains("``"), "{e}");
}

#[test]
fn legacy_51_offsets_not_from_zero_are_named_plainly() {
    let text = "# vtk DataFile Version 5.1\nt\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 3 double\n0 0 0 1 0 0 0 1 0\nCELLS 2 3\nOFFSETS vtktypeint64\n3 3\nCONNECTIVITY vtktypeint64\n0 1 2\nCELL_TYPES 1\n5\n";
    let e = legacy_err(text);
    let s = e.to_string();
    assert!(s.contains("a first offset of 3"), "{s}");
    assert!(!s.contains("Some("), "{s}");
}

/// Three triangles with a Gmsh `$ElementData` view that covers one of them.
const PARTIAL_VIEW_MSH: &str = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n5\n1 0 0 0\n2 1 0 0\n3 1 1 0\n4 0 1 0\n5 2 0 0\n$EndNodes\n$Elements\n3\n1 2 2 1 1 1 2 3\n2 2 2 1 1 1 3 4\n3 2 2 1 1 2 5 3\n$EndElements\n$ElementData\n1\n\"err\"\n1\n0\n3\n0\n1\n1\n2 0.25\n$EndElementData\n";

/// A Gmsh view that covers part of the cells is read as it is, the other cells NaN,
/// which the read report says; every VTK variant writes the NaN (`nan` in ASCII, as VTK
/// writes it) and reads it back as NaN, and an infinity likewise.
#[test]
fn a_partial_gmsh_view_goes_through_vtk_as_nan() {
    let (mut m, report) = smartmesh_formats::gmsh::read_reported(
        PARTIAL_VIEW_MSH.as_bytes(),
        &ReadContext::alone("msh"),
    )
    .unwrap();
    assert_eq!(
        report.notes,
        vec!["view `err` gives values for 1 of 3 elements; the others are NaN"]
    );
    let err = &m.cell_data["err"].values;
    assert!(err[0].is_nan() && err[1] == 0.25 && err[2].is_nan(), "{err:?}");
    m.point_data.insert(
        "f".into(),
        DataArray::new(1, vec![1.0, f64::INFINITY, -1.0, f64::NEG_INFINITY, 0.5]),
    );
    for (format, vtk) in common::vtk_variants() {
        let label = format!("{format:?} {vtk:?}");
        let opts = WriteOptions { vtk, ..WriteOptions::default() };
        let bytes = write_bytes(format, &m, &opts).unwrap().main;
        let back = read(format, &bytes).unwrap_or_else(|e| panic!("{label}: {e}"));
        let err = &back.cell_data["err"].values;
        assert!(err[0].is_nan() && err[1] == 0.25 && err[2].is_nan(), "{label}: {err:?}");
        assert_eq!(back.point_data["f"].values, m.point_data["f"].values, "{label}");
    }
}
