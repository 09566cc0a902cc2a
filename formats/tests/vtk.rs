//! VTK legacy and XML: the public fixtures, round trips in every variant, property
//! tests and malformed inputs.

use smartmesh_formats::VtkWrite;
mod vtk_common;
use vtk_common::*;

use smartmesh_test_support::formats as common;

use std::collections::BTreeMap;

use smartmesh_formats::{
    write_bytes, CellKind, DataArray, Format, Layout, TaggedMesh, VtuEncoding, WriteOptions,
};

/// Encodings that store doubles exactly (VTK's legacy ASCII writer rounds to 11
/// significant digits).
const EXACT: [&str; 4] = [
    "vtk/naca0012_ascii.vtu",
    "vtk/naca0012_binary_zlib.vtu",
    "vtk/naca0012_appended_raw.vtu",
    "vtk/naca0012_legacy_binary.vtk",
];

// The expected counts were found independently of this crate: VTK 9.7.2's own readers
// (vtkXMLUnstructuredGridReader, vtkUnstructuredGridReader, from Python) give 1904
// points and 3640 cells, all of VTK type 5 with `gmsh:physical` = 3, in all six files;
// `grep -c` on the legacy ASCII file agrees (3640 lines `3 a b c` after `CELLS 3640
// 14560`, and `gmsh:physical` RangeMin = RangeMax = 3 in the .vtu files).

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
