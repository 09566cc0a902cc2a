//! The coarse-mesh rule of a free source in space: the corners of every tetrahedron that
//! a piece of an imaginary polyline (a segment) or sheet (a triangle) meets, whatever
//! their distance to it, the 3D meaning of the 2D propagation's seeds (the corners of
//! every triangle an imaginary polyline crosses, `sizing::propagation`): a source thinner
//! than the cells still marks the cells it passes through.
//!
//! Each tetrahedron is tested exactly (`geometry::space::meets`, signs of the exact
//! orientation predicates; touching counts). Candidates are found without missing one:
//! a point X of a tetrahedron lies within the tetrahedron's longest edge L of each of
//! its corners (convexity), so a tetrahedron a piece meets has every corner within L of
//! the source; one exact closest-point query per mesh vertex (in fixed chunks, each
//! seeded by the last: the answer does not depend on the seed) rules out every
//! tetrahedron with a corner farther than L (with a relative margin of 1e-9 for
//! rounding), and the others are tested against every piece whose box overlaps theirs.
//! Cost: one query per vertex near the source's box, then the pieces scanned for the
//! tetrahedra along the source.
//! [`crossed_corners_brute`] is the twin: every piece against every tetrahedron.
//!
//! Other volume cells (hexahedra, prisms, pyramids) and a surface mesh's triangles are
//! not tested: only tetrahedra.

use rayon::prelude::*;
use smartmesh_formats::{CellKind, TaggedMesh};

use super::source::SpaceSource;
use crate::geometry::space::meets::piece_meets_tet;
use crate::geometry::space::Point3;

/// The tetrahedra of `mesh`, by their corners (second order by their first four).
fn tets(mesh: &TaggedMesh) -> Vec<[usize; 4]> {
    let mut out = Vec::new();
    for block in &mesh.blocks {
        if block.kind.linear() != CellKind::Tetra {
            continue;
        }
        for c in block.cells() {
            let t = [c[0] as usize, c[1] as usize, c[2] as usize, c[3] as usize];
            if t.iter().all(|&v| v < mesh.points.len()) {
                out.push(t);
            }
        }
    }
    out
}

fn corners(mesh: &TaggedMesh, t: [usize; 4]) -> [Point3; 4] {
    t.map(|v| mesh.points[v])
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

/// Whether every corner of `mesh` belongs to a tetrahedron `hit` says a piece meets
/// (`hit` is given the tetrahedron's vertices and corners).
fn mark(mesh: &TaggedMesh, hit: impl Fn([usize; 4], &[Point3; 4]) -> bool + Sync) -> Vec<bool> {
    let tets = tets(mesh);
    let met: Vec<bool> = tets.par_iter().map(|&t| hit(t, &corners(mesh, t))).collect();
    let mut out = vec![false; mesh.points.len()];
    for (t, m) in tets.iter().zip(met) {
        if m {
            t.iter().for_each(|&v| out[v] = true);
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
    mark(mesh, |vertices, t| {
        let tbox = box_of(t);
        if !boxes_overlap(tbox, source_box) {
            return false;
        }
        let longest2 = EDGES
            .iter()
            .map(|&[i, j]| (0..3).map(|k| (t[i][k] - t[j][k]) * (t[i][k] - t[j][k])).sum::<f64>())
            .fold(0.0, f64::max);
        let bound = longest2 * (1.0 + 1e-9) + f64::MIN_POSITIVE;
        // NaN (a non-finite corner) is ruled out too.
        if !vertices.iter().all(|&v| distance2[v] <= bound) {
            return false;
        }
        pieces.iter().any(|(c, b)| boxes_overlap(tbox, *b) && piece_meets_tet(c, t))
    })
}

const EDGES: [[usize; 2]; 6] = [[0, 1], [0, 2], [0, 3], [1, 2], [1, 3], [2, 3]];

/// The twin of [`crossed_corners`]: every piece against every tetrahedron.
#[cfg(test)]
pub(crate) fn crossed_corners_brute(mesh: &TaggedMesh, source: &SpaceSource) -> Vec<bool> {
    mark(mesh, |_, t| (0..source.len()).any(|i| piece_meets_tet(&source.piece_corners(i), t)))
}
