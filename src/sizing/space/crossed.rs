//! The coarse-mesh rule of a free source in space: the corners of every cell that a piece
//! of an imaginary polyline (a segment) or sheet (a triangle) meets, whatever their
//! distance to it, the 3D meaning of the 2D propagation's seeds (the corners of every
//! cell an imaginary polyline touches, `sizing::propagation`): a source thinner than the
//! cells still marks the cells it passes through.
//!
//! The cells: the volume cells of the mesh (tetrahedra, hexahedra, prisms, pyramids) when
//! it has any; else its surface cells (triangles and quadrilaterals of a surface mesh in
//! space); else its line cells — as in 2D, where the cells are the triangles and quads,
//! and the edges only for a mesh without cells. On a volume mesh the boundary triangles
//! are faces of volume cells: a piece meeting one meets a volume cell already. A second-
//! order cell is taken by its corners.
//!
//! What "meets" means for each cell: the piece meets the convex hull of the cell's
//! corners, decided exactly (`geometry::space::meets::piece_meets_hull`: signs of the
//! exact orientation predicates; touching counts). For a tetrahedron, a triangle and a
//! line that is the cell itself. For a hexahedron, prism, pyramid or quadrilateral with
//! planar faces (and convex, as a valid cell is) the hull is the cell too. For a warped
//! cell (a face whose four corners are not coplanar) the cell — the image of its
//! trilinear map, whose weights are non-negative and sum to one — lies inside the hull,
//! so no cell the piece meets is missed; a piece may mark a warped cell it only passes
//! near, within the hull. The hull is tested as the union of the tetrahedra of every four
//! corners (70 for a hexahedron, 15 for a prism, 5 for a pyramid) rather than through one
//! fixed split into tetrahedra: a fixed split follows one diagonal of each warped face,
//! the neighbour's split may follow the other, and a piece crossing between the two would
//! mark neither cell.
//!
//! Candidates are found without missing one: a point X of the hull lies within the
//! hull's diameter L (the longest distance between two corners) of each corner, so a
//! cell a piece meets has every corner within L of the source; one exact closest-point
//! query per mesh vertex (in fixed chunks, each seeded by the last: the answer does not
//! depend on the seed) rules out every cell with a corner farther than L (with a relative
//! margin of 1e-9 for rounding), and the others are tested against every piece whose
//! box overlaps theirs. Cost: one query per vertex, then the pieces scanned for the cells
//! along the source. [`crossed_corners_brute`] is the twin: every piece against every
//! cell.

use rayon::prelude::*;
use smartmesh_formats::TaggedMesh;

use super::source::SpaceSource;
use crate::geometry::space::meets::piece_meets_hull;
use crate::geometry::space::Point3;

/// The most corners a cell has (a hexahedron).
const MAX_CORNERS: usize = 8;

/// A cell by its corners: the first `len` of `corners`.
#[derive(Clone, Copy)]
struct Cell {
    corners: [usize; MAX_CORNERS],
    len: usize,
}

impl Cell {
    fn vertices(&self) -> &[usize] {
        &self.corners[..self.len]
    }
}

/// The cells of `mesh` the rule tests (see the module header); a cell naming a vertex the
/// mesh does not have is left out.
fn cells(mesh: &TaggedMesh) -> Vec<Cell> {
    let dim = mesh.blocks.iter().map(|b| b.kind.dim()).filter(|&d| d >= 1).max();
    let mut out = Vec::new();
    for block in &mesh.blocks {
        if Some(block.kind.dim()) != dim {
            continue;
        }
        let len = block.kind.linear().nodes_per_cell().min(MAX_CORNERS);
        for c in block.cells() {
            let mut cell = Cell { corners: [0; MAX_CORNERS], len };
            for (slot, &v) in cell.corners.iter_mut().zip(&c[..len]) {
                *slot = v as usize;
            }
            if cell.vertices().iter().all(|&v| v < mesh.points.len()) {
                out.push(cell);
            }
        }
    }
    out
}

fn boxes_overlap(a: (Point3, Point3), b: (Point3, Point3)) -> bool {
    (0..3).all(|k| a.0[k] <= b.1[k] && b.0[k] <= a.1[k])
}

fn box_of(points: &[Point3]) -> (Point3, Point3) {
    let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    for p in points {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    (lo, hi)
}

/// Whether every corner of `mesh` belongs to a cell `hit` says a piece meets (`hit` is
/// given the cell's vertices and corners).
fn mark(mesh: &TaggedMesh, hit: impl Fn(&[usize], &[Point3]) -> bool + Sync) -> Vec<bool> {
    let cells = cells(mesh);
    let met: Vec<bool> = cells
        .par_iter()
        .map(|c| {
            let mut corners = [[0.0; 3]; MAX_CORNERS];
            for (p, &v) in corners.iter_mut().zip(c.vertices()) {
                *p = mesh.points[v];
            }
            hit(c.vertices(), &corners[..c.len])
        })
        .collect();
    let mut out = vec![false; mesh.points.len()];
    for (c, m) in cells.iter().zip(met) {
        if m {
            c.vertices().iter().for_each(|&v| out[v] = true);
        }
    }
    out
}

/// Vertices per chunk of the distance queries (fixed: the same on every thread count).
const CHUNK: usize = 1024;

/// The corners of the tetrahedra that `source`'s pieces meet (see the module header).
pub(crate) fn crossed_corners(mesh: &TaggedMesh, source: &SpaceSource) -> Vec<bool> {
    let source_box = source.bounds();
    let pieces: Vec<([Point3; 3], (Point3, Point3))> = (0..source.len())
        .map(|i| {
            let c = source.piece_corners(i);
            (c, box_of(&c))
        })
        .collect();
    // Each vertex's squared distance to the source (infinite where not finite).
    let distance2: Vec<f64> = mesh
        .points
        .par_chunks(CHUNK)
        .map(|chunk| {
            let mut seed = u32::MAX;
            chunk
                .iter()
                .map(|&p| match source.closest_from(p, seed) {
                    Some(c) => {
                        seed = c.piece;
                        c.distance_squared
                    }
                    None => f64::INFINITY,
                })
                .collect::<Vec<f64>>()
        })
        .collect::<Vec<Vec<f64>>>()
        .concat();
    mark(mesh, |vertices, corners| {
        let cbox = box_of(corners);
        if !boxes_overlap(cbox, source_box) {
            return false;
        }
        let mut diameter2: f64 = 0.0;
        for (i, a) in corners.iter().enumerate() {
            for b in &corners[i + 1..] {
                let d2 = (0..3).map(|k| (a[k] - b[k]) * (a[k] - b[k])).sum::<f64>();
                diameter2 = diameter2.max(d2);
            }
        }
        let bound = diameter2 * (1.0 + 1e-9) + f64::MIN_POSITIVE;
        // NaN (a non-finite corner) is ruled out too.
        if !vertices.iter().all(|&v| distance2[v] <= bound) {
            return false;
        }
        pieces.iter().any(|(c, b)| boxes_overlap(cbox, *b) && piece_meets_hull(c, corners))
    })
}

/// The twin of [`crossed_corners`]: every piece against every cell.
#[cfg(test)]
pub(crate) fn crossed_corners_brute(mesh: &TaggedMesh, source: &SpaceSource) -> Vec<bool> {
    mark(mesh, |_, corners| {
        (0..source.len()).any(|i| piece_meets_hull(&source.piece_corners(i), corners))
    })
}
