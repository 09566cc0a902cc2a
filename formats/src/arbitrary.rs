//! Random tagged meshes for property tests (feature `proptest`), as nalgebra keeps its
//! strategies behind a feature.
//!
//! The meshes are structurally valid (indices in range, data of the right length) but
//! not geometrically meaningful: round trips must not care.

use proptest::prelude::*;

use crate::{sym2_to_tensor9, CellBlock, CellKind, DataArray, TaggedMesh};

/// What a random mesh may contain; formats that cannot hold a feature turn it off.
#[derive(Debug, Clone, Copy)]
pub struct MeshFeatures {
    /// Quadrilateral cells.
    pub quads: bool,
    /// Line cells (boundary edges).
    pub lines: bool,
    /// Vertex cells.
    pub vertices: bool,
    /// Distinct geometrical tags (otherwise equal to the physical ones).
    pub geometrical: bool,
    /// Names for physical tags.
    pub names: bool,
    /// A scalar point array `size`.
    pub point_scalar: bool,
    /// A tensor point array `metric` (symmetric, 2D, zz = 1).
    pub point_tensor: bool,
    /// Negative tags.
    pub negative_tags: bool,
}

impl MeshFeatures {
    /// Everything on.
    pub const ALL: MeshFeatures = MeshFeatures {
        quads: true,
        lines: true,
        vertices: true,
        geometrical: true,
        names: true,
        point_scalar: true,
        point_tensor: true,
        negative_tags: false,
    };
}

fn coordinate() -> impl Strategy<Value = f64> {
    prop_oneof![
        -1.0e3..1.0e3f64,
        (-1000i32..1000).prop_map(|i| i as f64 / 8.0),
        (-1.0e-6..1.0e-6f64),
    ]
}

/// A random mesh with the given features: 3 to 40 points, a few blocks.
pub fn arb_tagged_mesh(f: MeshFeatures) -> impl Strategy<Value = TaggedMesh> {
    let tag = if f.negative_tags { (-5i32..20).boxed() } else { (1i32..20).boxed() };
    (3u32..40).prop_flat_map(move |n| {
        let points = prop::collection::vec((coordinate(), coordinate()), n as usize);
        let tri = prop::collection::vec(((0..n, 0..n, 0..n), tag.clone(), 1i32..9), 1..30);
        let quad = prop::collection::vec(
            ((0..n, 0..n, 0..n, 0..n), tag.clone(), 1i32..9),
            0..(if f.quads { 10 } else { 1 }),
        );
        let line = prop::collection::vec(
            ((0..n, 0..n), tag.clone(), 1i32..9),
            0..(if f.lines { 10 } else { 1 }),
        );
        let vert = prop::collection::vec(
            (0..n, tag.clone(), 1i32..9),
            0..(if f.vertices { 4 } else { 1 }),
        );
        let scal = prop::collection::vec(0.001..10.0f64, n as usize);
        let tens =
            prop::collection::vec((0.01..100.0f64, -0.5..0.5f64, 0.01..100.0f64), n as usize);
        (points, tri, quad, line, vert, scal, tens).prop_map(
            move |(points, tri, quad, line, vert, scal, tens)| {
                let mut m = TaggedMesh::new();
                m.points = points.into_iter().map(|(x, y)| [x, y, 0.0]).collect();
                let g = |p: i32, g: i32| if f.geometrical { g } else { p };
                if f.vertices {
                    let mut b = CellBlock::new(CellKind::Vertex);
                    for (v, p, e) in &vert {
                        b.push(&[*v], *p, g(*p, *e));
                    }
                    if !b.is_empty() {
                        m.blocks.push(b);
                    }
                }
                if f.lines {
                    let mut b = CellBlock::new(CellKind::Line);
                    for ((a, c), p, e) in &line {
                        b.push(&[*a, *c], *p, g(*p, *e));
                    }
                    if !b.is_empty() {
                        m.blocks.push(b);
                    }
                }
                let mut b = CellBlock::new(CellKind::Triangle);
                for ((a, c, d), p, e) in &tri {
                    b.push(&[*a, *c, *d], *p, g(*p, *e));
                }
                m.blocks.push(b);
                if f.quads {
                    let mut b = CellBlock::new(CellKind::Quad);
                    for ((a, c, d, e4), p, e) in &quad {
                        b.push(&[*a, *c, *d, *e4], *p, g(*p, *e));
                    }
                    if !b.is_empty() {
                        m.blocks.push(b);
                    }
                }
                if f.names {
                    let mut dims: Vec<(u8, i32)> = m
                        .blocks
                        .iter()
                        .flat_map(|b| b.physical.iter().map(move |&p| (b.kind.dim(), p)))
                        .collect();
                    dims.sort_unstable();
                    dims.dedup();
                    for (d, p) in dims {
                        if p != 0 {
                            m.tag_names.insert((d, p), format!("Group_{d}_{p}"));
                        }
                    }
                }
                if f.point_scalar {
                    m.point_data.insert("size".into(), DataArray::new(1, scal));
                }
                if f.point_tensor {
                    // A random SPD 2D tensor: diagonal dominance guarantees it.
                    let v: Vec<f64> = tens
                        .iter()
                        .flat_map(|&(a, s, c)| {
                            let b = s * (a * c).sqrt();
                            sym2_to_tensor9(a, b, c, 1.0)
                        })
                        .collect();
                    m.point_data.insert("metric".into(), DataArray::new(9, v));
                }
                m
            },
        )
    })
}
