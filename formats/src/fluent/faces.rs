//! The faces of a Fluent mesh: every side of every cell once, with the cell on each
//! side, oriented so that the right-hand-rule normal points out of `c0` (the cell the
//! face was first met from), and the boundary cells of the tagged mesh laid on them.
//!
//! Orientation is decided geometrically, not from the cells' node order: a face's
//! normal (Newell's formula in 3D, the edge turned clockwise in 2D) is compared with
//! the vector from the cell's centroid to the face's centroid, and the face reversed
//! when they disagree. A mesh with some cells numbered clockwise (or inverted tetrahedra
//! in node order) is thus still written with consistent faces; this holds for convex
//! cells, which every first-order cell of a valid mesh is for its centroid test.
//!
//! Invariant of [`Faces`]: `nodes` holds `len * 4` entries, a triangle's or a line's
//! unused slots are [`NONE`]; `c1 == NONE` for a face on the boundary.

use std::collections::HashMap;

/// An unused node slot, or no cell on that side.
pub const NONE: u32 = u32::MAX;

/// The local faces of each linear cell kind, in Gmsh's node numbering: triangles and
/// quads list their edges, volume cells their faces (as cycles; orientation is fixed
/// later from the geometry).
pub fn local_faces(kind: crate::CellKind) -> &'static [&'static [usize]] {
    use crate::CellKind as K;
    match kind.linear() {
        K::Triangle => &[&[0, 1], &[1, 2], &[2, 0]],
        K::Quad => &[&[0, 1], &[1, 2], &[2, 3], &[3, 0]],
        _ if kind.dim() == 3 => kind.faces(),
        _ => &[],
    }
}

/// Every face once: its nodes (oriented out of `c0`), `c0` and `c1` (0-based cells).
#[derive(Debug, Default)]
pub struct Faces {
    /// Four slots per face, unused ones [`NONE`].
    pub nodes: Vec<u32>,
    /// The cell the face was first met from; its normal points out of it.
    pub c0: Vec<u32>,
    /// The cell on the other side, [`NONE`] on the boundary.
    pub c1: Vec<u32>,
    /// Face index by its sorted node slots.
    index: HashMap<[u32; 4], u32>,
}

impl Faces {
    /// Number of faces.
    pub fn len(&self) -> usize {
        self.c0.len()
    }

    /// The nodes of face `f` (2, 3 or 4).
    pub fn face(&self, f: usize) -> &[u32] {
        let s = &self.nodes[4 * f..4 * f + 4];
        let n = s.iter().position(|&v| v == NONE).unwrap_or(4);
        &s[..n]
    }

    /// The face with these nodes, in any order.
    pub fn find(&self, nodes: &[u32]) -> Option<usize> {
        self.index.get(&key(nodes)).map(|&f| f as usize)
    }

    /// Adds the side `nodes` (already oriented out of `cell`) of `cell`. Returns
    /// `false` when a third cell claims the face (a non-manifold mesh).
    pub fn add(&mut self, nodes: &[u32], cell: u32) -> bool {
        let k = key(nodes);
        match self.index.get(&k) {
            Some(&f) => {
                let f = f as usize;
                if self.c1[f] != NONE {
                    return false;
                }
                self.c1[f] = cell;
                true
            }
            None => {
                self.index.insert(k, self.c0.len() as u32);
                let mut slots = [NONE; 4];
                slots[..nodes.len()].copy_from_slice(nodes);
                self.nodes.extend_from_slice(&slots);
                self.c0.push(cell);
                self.c1.push(NONE);
                true
            }
        }
    }
}

fn key(nodes: &[u32]) -> [u32; 4] {
    let mut k = [NONE; 4];
    k[..nodes.len()].copy_from_slice(nodes);
    k.sort_unstable();
    k
}

/// `face` reordered, if need be, so that its right-hand normal points away from
/// `centre` (the cell's centroid). In 2D (two nodes) the normal of `a → b` is
/// `(dy, -dx)`, the edge's right side.
pub fn orient_outward(face: &mut [u32], points: &[[f64; 3]], centre: [f64; 3]) {
    let p = |i: u32| points[i as usize];
    let n = face.len();
    let mut mid = [0.0; 3];
    for &v in face.iter() {
        for (m, c) in mid.iter_mut().zip(p(v)) {
            *m += c / n as f64;
        }
    }
    let out = [mid[0] - centre[0], mid[1] - centre[1], mid[2] - centre[2]];
    let dot = if n == 2 {
        let (a, b) = (p(face[0]), p(face[1]));
        (b[1] - a[1]) * out[0] - (b[0] - a[0]) * out[1]
    } else {
        // Newell's normal: exact for planar polygons, the mean plane's for warped quads.
        let mut nrm = [0.0; 3];
        for i in 0..n {
            let (a, b) = (p(face[i]), p(face[(i + 1) % n]));
            nrm[0] += (a[1] - b[1]) * (a[2] + b[2]);
            nrm[1] += (a[2] - b[2]) * (a[0] + b[0]);
            nrm[2] += (a[0] - b[0]) * (a[1] + b[1]);
        }
        nrm[0] * out[0] + nrm[1] * out[1] + nrm[2] * out[2]
    };
    if dot < 0.0 {
        face.reverse();
    }
}

/// The centroid of the points `nodes`.
pub fn centroid(nodes: &[u32], points: &[[f64; 3]]) -> [f64; 3] {
    let mut c = [0.0; 3];
    for &v in nodes {
        for (m, x) in c.iter_mut().zip(points[v as usize]) {
            *m += x / nodes.len() as f64;
        }
    }
    c
}
