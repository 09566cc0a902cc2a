//! What the 3D Gmsh tests share: Gmsh's reference element of every volume and surface
//! kind (its node coordinates in Gmsh's node order, as `gmsh.model.mesh.
//! getElementProperties` gives them: the interop test checks this table against Gmsh),
//! a mesh holding one element of each kind as an affine image of its reference element,
//! and element volumes computed here apart from the library, by splitting into
//! tetrahedra.

#![allow(dead_code)]

use smartmesh_formats::{CellBlock, CellKind, TaggedMesh};

/// The reference coordinates of the nodes of `kind` in Gmsh's order (Gmsh's reference
/// elements: the unit simplex for tetrahedra and triangles, [-1, 1]^d for hexahedra and
/// quadrangles, the unit triangle × [-1, 1] for prisms, the base [-1, 1]^2 at z = 0 with
/// its apex at (0, 0, 1) for pyramids).
pub fn reference(kind: CellKind) -> Vec<[f64; 3]> {
    const TET: [[f64; 3]; 10] = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
        [0.5, 0.0, 0.0],
        [0.5, 0.5, 0.0],
        [0.0, 0.5, 0.0],
        [0.0, 0.0, 0.5],
        [0.0, 0.5, 0.5],
        [0.5, 0.0, 0.5],
    ];
    const HEX: [[f64; 3]; 27] = [
        [-1.0, -1.0, -1.0],
        [1.0, -1.0, -1.0],
        [1.0, 1.0, -1.0],
        [-1.0, 1.0, -1.0],
        [-1.0, -1.0, 1.0],
        [1.0, -1.0, 1.0],
        [1.0, 1.0, 1.0],
        [-1.0, 1.0, 1.0],
        [0.0, -1.0, -1.0],
        [-1.0, 0.0, -1.0],
        [-1.0, -1.0, 0.0],
        [1.0, 0.0, -1.0],
        [1.0, -1.0, 0.0],
        [0.0, 1.0, -1.0],
        [1.0, 1.0, 0.0],
        [-1.0, 1.0, 0.0],
        [0.0, -1.0, 1.0],
        [-1.0, 0.0, 1.0],
        [1.0, 0.0, 1.0],
        [0.0, 1.0, 1.0],
        [0.0, 0.0, -1.0],
        [0.0, -1.0, 0.0],
        [-1.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
        [0.0, 0.0, 0.0],
    ];
    const PRISM: [[f64; 3]; 18] = [
        [0.0, 0.0, -1.0],
        [1.0, 0.0, -1.0],
        [0.0, 1.0, -1.0],
        [0.0, 0.0, 1.0],
        [1.0, 0.0, 1.0],
        [0.0, 1.0, 1.0],
        [0.5, 0.0, -1.0],
        [0.0, 0.5, -1.0],
        [0.0, 0.0, 0.0],
        [0.5, 0.5, -1.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.5, 0.0, 1.0],
        [0.0, 0.5, 1.0],
        [0.5, 0.5, 1.0],
        [0.5, 0.0, 0.0],
        [0.0, 0.5, 0.0],
        [0.5, 0.5, 0.0],
    ];
    const PYRAMID: [[f64; 3]; 14] = [
        [-1.0, -1.0, 0.0],
        [1.0, -1.0, 0.0],
        [1.0, 1.0, 0.0],
        [-1.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
        [0.0, -1.0, 0.0],
        [-1.0, 0.0, 0.0],
        [-0.5, -0.5, 0.5],
        [1.0, 0.0, 0.0],
        [0.5, -0.5, 0.5],
        [0.0, 1.0, 0.0],
        [0.5, 0.5, 0.5],
        [-0.5, 0.5, 0.5],
        [0.0, 0.0, 0.0],
    ];
    const TRI: [[f64; 3]; 6] = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.5, 0.0, 0.0],
        [0.5, 0.5, 0.0],
        [0.0, 0.5, 0.0],
    ];
    const QUAD: [[f64; 3]; 9] = [
        [-1.0, -1.0, 0.0],
        [1.0, -1.0, 0.0],
        [1.0, 1.0, 0.0],
        [-1.0, 1.0, 0.0],
        [0.0, -1.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [-1.0, 0.0, 0.0],
        [0.0, 0.0, 0.0],
    ];
    let n = kind.nodes_per_cell();
    let table: &[[f64; 3]] = match kind.linear() {
        CellKind::Tetra => &TET,
        CellKind::Hexa => &HEX,
        CellKind::Wedge => &PRISM,
        CellKind::Pyramid => &PYRAMID,
        CellKind::Triangle => &TRI,
        CellKind::Quad => &QUAD,
        k => panic!("no reference element here for {k:?}"),
    };
    table[..n].to_vec()
}

/// The volume (area for surface kinds) of the reference element of `kind`.
pub fn reference_measure(kind: CellKind) -> f64 {
    match kind.linear() {
        CellKind::Tetra => 1.0 / 6.0,
        CellKind::Hexa => 8.0,
        CellKind::Wedge => 1.0,
        CellKind::Pyramid => 4.0 / 3.0,
        CellKind::Triangle => 0.5,
        CellKind::Quad => 4.0,
        k => panic!("no reference element here for {k:?}"),
    }
}

/// The volume kinds, first then second order.
pub const VOLUME_KINDS: [CellKind; 11] = [
    CellKind::Tetra,
    CellKind::Hexa,
    CellKind::Wedge,
    CellKind::Pyramid,
    CellKind::Tetra10,
    CellKind::Hexa20,
    CellKind::Hexa27,
    CellKind::Wedge15,
    CellKind::Wedge18,
    CellKind::Pyramid13,
    CellKind::Pyramid14,
];

/// The surface kinds, first then second order.
pub const SURFACE_KINDS: [CellKind; 5] =
    [CellKind::Triangle, CellKind::Quad, CellKind::Triangle6, CellKind::Quad8, CellKind::Quad9];

/// An affine map x = A ξ + b.
#[derive(Clone, Copy, Debug)]
pub struct Affine {
    pub a: [[f64; 3]; 3],
    pub b: [f64; 3],
}

impl Affine {
    pub fn apply(&self, p: [f64; 3]) -> [f64; 3] {
        let mut x = self.b;
        for (xi, row) in x.iter_mut().zip(&self.a) {
            *xi += row.iter().zip(&p).map(|(a, c)| a * c).sum::<f64>();
        }
        x
    }

    pub fn det(&self) -> f64 {
        det3(self.a[0], self.a[1], self.a[2])
    }
}

pub fn det3(r0: [f64; 3], r1: [f64; 3], r2: [f64; 3]) -> f64 {
    r0[0] * (r1[1] * r2[2] - r1[2] * r2[1]) - r0[1] * (r1[0] * r2[2] - r1[2] * r2[0])
        + r0[2] * (r1[0] * r2[1] - r1[1] * r2[0])
}

/// The map of element `i`: a sheared, scaled rotation (positive determinant, different
/// for each element), moved 4 units along x per element so that no two overlap.
pub fn element_map(i: usize) -> Affine {
    let s = 0.5 + 0.05 * i as f64;
    let m = [[1.0, 0.2, 0.1], [-0.1, 0.9, 0.3], [0.05, -0.15, 1.1]];
    let a = m.map(|row| row.map(|v| s * v));
    Affine { a, b: [4.0 * i as f64, 0.25 * i as f64, -0.125 * i as f64] }
}

/// One element of every volume kind (physical volume and entity `i + 1`, named after
/// the kind) and of every surface kind (physical surfaces 101 `skin` for the first-order
/// ones, 102 `skin2` for the second-order ones, each on an entity of its own), each the
/// image by [`element_map`] of its reference element, with nodes of its own. Returns
/// the mesh and the map of each cell, in cell order.
pub fn every_kind() -> (TaggedMesh, Vec<Affine>) {
    let mut m = TaggedMesh::new();
    m.coordinate_dim = 3;
    let mut maps = Vec::new();
    let kinds = SURFACE_KINDS.iter().chain(&VOLUME_KINDS);
    for (i, &kind) in kinds.enumerate() {
        let map = element_map(i);
        let first = m.points.len() as u32;
        for p in reference(kind) {
            m.points.push(map.apply(p));
        }
        let nodes: Vec<u32> = (first..m.points.len() as u32).collect();
        let (phys, geom) = if kind.dim() == 3 {
            let t = VOLUME_KINDS.iter().position(|&k| k == kind).unwrap() as i32 + 1;
            m.tag_names.insert((3, t), kind.name().to_string());
            (t, t)
        } else {
            let t = if kind.is_second_order() { 102 } else { 101 };
            (t, 1 + i as i32)
        };
        let mut b = CellBlock::new(kind);
        b.push(&nodes, phys, geom);
        m.blocks.push(b);
        maps.push(map);
    }
    m.tag_names.insert((2, 101), "skin".into());
    m.tag_names.insert((2, 102), "skin2".into());
    (m, maps)
}

fn tet(p: &[[f64; 3]], a: usize, b: usize, c: usize, d: usize) -> f64 {
    let e = |i: usize| [p[i][0] - p[a][0], p[i][1] - p[a][1], p[i][2] - p[a][2]];
    det3(e(b), e(c), e(d)) / 6.0
}

/// The signed volume of a volume cell from its corners (`pts` in Gmsh's node order),
/// split into tetrahedra: exact for cells with planar faces (any affine image of the
/// reference element); positive when the cell is oriented as Gmsh's reference.
pub fn corner_volume(kind: CellKind, pts: &[[f64; 3]]) -> f64 {
    match kind.linear() {
        CellKind::Tetra => tet(pts, 0, 1, 2, 3),
        // Six tetrahedra around the diagonal 0-6.
        CellKind::Hexa => [(1, 2), (2, 3), (3, 7), (7, 4), (4, 5), (5, 1)]
            .iter()
            .map(|&(a, b)| tet(pts, 0, a, b, 6))
            .sum(),
        CellKind::Wedge => tet(pts, 0, 1, 2, 5) + tet(pts, 0, 1, 5, 4) + tet(pts, 0, 4, 5, 3),
        CellKind::Pyramid => tet(pts, 0, 1, 2, 4) + tet(pts, 0, 2, 3, 4),
        k => panic!("{k:?} is no volume kind"),
    }
}

/// The corners of cell `cell` of `m` as points.
pub fn points_of(m: &TaggedMesh, cell: &[u32]) -> Vec<[f64; 3]> {
    cell.iter().map(|&v| m.points[v as usize]).collect()
}
