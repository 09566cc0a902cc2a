//! VTK legacy and XML: malformed and extreme inputs, each refused with what is wrong and
//! where (a line in ASCII legacy files, a byte elsewhere), nothing allocated for what a
//! header only announces.

mod vtk_common;
use vtk_common::*;

use smartmesh_test_support::formats as common;

use smartmesh_formats::{
    write_bytes, CellKind, ErrorKind, Format, Position, TaggedMesh, VtkWrite, VtuEncoding,
    WriteOptions,
};

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
