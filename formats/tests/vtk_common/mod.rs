//! What the VTK test files share: the fixtures, the reader call, two meshes.

#![allow(dead_code)]

use smartmesh_formats::{
    read_bytes, CellKind, DataArray, Format, ReadContext, TaggedMesh, WriteOptions,
};
use smartmesh_test_support::formats as common;

pub const FIXTURES: [&str; 6] = [
    "vtk/naca0012_ascii.vtu",
    "vtk/naca0012_binary_zlib.vtu",
    "vtk/naca0012_appended_raw.vtu",
    "vtk/naca0012_legacy_binary.vtk",
    "vtk/naca0012_legacy_ascii.vtk",
    "vtk/naca0012_legacy51_ascii.vtk",
];

pub fn read(format: Format, bytes: &[u8]) -> smartmesh_formats::Result<TaggedMesh> {
    read_bytes(
        format,
        bytes,
        &ReadContext::alone(if format == Format::Vtu { "vtu" } else { "vtk" }),
    )
}

/// The naca0012 mesh with everything the writers must keep: names, cell data,
/// vectors, 2- and 4-component arrays, boundary lines and a vertex.
pub fn rich_mesh() -> TaggedMesh {
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

/// Four points, two triangles, two lines: in the order `blocks` gives.
pub fn mixed_mesh(order: &[CellKind]) -> TaggedMesh {
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

/// Every variant the writers offer: (label, format, options).
pub fn variants() -> Vec<(String, Format, WriteOptions)> {
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

pub fn bits(v: &[f64]) -> Vec<u64> {
    v.iter().map(|x| x.to_bits()).collect()
}

pub fn flat(m: &TaggedMesh) -> Vec<f64> {
    m.points.iter().flatten().copied().collect()
}

pub const NPOINTS: usize = 1904;

pub const NTRIANGLES: usize = 3640;

pub const FLUID: i32 = 3;
