//! VTK legacy and XML: empty and mixed meshes, tensors kept packed only when nothing
//! is lost, a partial Gmsh view through VTK.

mod vtk_common;
use vtk_common::*;

use smartmesh_test_support::formats as common;

use smartmesh_formats::{
    sym2_to_tensor9, write_bytes, CellKind, DataArray, Format, Layout, ReadContext, TaggedMesh,
    VtuEncoding, WriteOptions,
};

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
