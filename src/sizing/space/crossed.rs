//! The coarse-mesh rule of a free source in space: the corners of every tetrahedron that
//! a piece of an imaginary polyline (a segment) or sheet (a triangle) meets, whatever
//! their distance to it, the 3D meaning of the 2D propagation's seeds (the corners of
//! every triangle an imaginary polyline crosses, `sizing::propagation`): a source thinner
//! than the cells still marks the cells it passes through.
//!
//! Each tetrahedron is tested exactly (`geometry::space::meets`, signs of the exact
//! orientation predicates; touching counts). Candidates are found without missing one:
//! a piece meeting a tetrahedron is within its circumradius-like bound r (the largest
//! distance from its centroid to a corner) of the centroid, so a tetrahedron whose
//! centroid's exact distance to the source exceeds r (with a relative margin of 1e-9
//! for rounding) meets no piece; the others are tested against every piece whose box
//! overlaps theirs. Cost: one closest-point query per tetrahedron near the source's box,
//! then the pieces scanned for the few tetrahedra the source passes through.
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

/// Whether every corner of `mesh` belongs to a tetrahedron some piece of `source` meets.
fn mark(mesh: &TaggedMesh, hit: impl Fn(&[Point3; 4]) -> bool + Sync) -> Vec<bool> {
    let tets = tets(mesh);
    let met: Vec<bool> = tets.par_iter().map(|&t| hit(&corners(mesh, t))).collect();
    let mut out = vec![false; mesh.points.len()];
    for (t, m) in tets.iter().zip(met) {
        if m {
            t.iter().for_each(|&v| out[v] = true);
        }
    }
    out
}

/// The corners of the tetrahedra that `source`'s pieces meet (see the module header).
pub(crate) fn crossed_corners(mesh: &TaggedMesh, source: &SpaceSource) -> Vec<bool> {
    let source_box = source.bounds();
    let pieces: Vec<([Point3; 3], (Point3, Point3))> = (0..source.len())
        .map(|i| {
            let c = source.piece_corners(i);
            (c, box_of(&c))
        })
        .collect();
    mark(mesh, |t| {
        let tbox = box_of(t);
        if !boxes_overlap(tbox, source_box) {
            return false;
        }
        let g: Point3 = std::array::from_fn(|k| (t[0][k] + t[1][k] + t[2][k] + t[3][k]) / 4.0);
        let r2 = t
            .iter()
            .map(|p| (0..3).map(|k| (p[k] - g[k]) * (p[k] - g[k])).sum::<f64>())
            .fold(0.0, f64::max);
        match source.closest_from(g, u32::MAX) {
            Some(c) if c.distance_squared > r2 * (1.0 + 1e-9) + f64::MIN_POSITIVE => return false,
            None => return false,
            _ => {}
        }
        pieces.iter().any(|(c, b)| boxes_overlap(tbox, *b) && piece_meets_tet(c, t))
    })
}

/// The twin of [`crossed_corners`]: every piece against every tetrahedron.
#[cfg(test)]
pub(crate) fn crossed_corners_brute(mesh: &TaggedMesh, source: &SpaceSource) -> Vec<bool> {
    mark(mesh, |t| (0..source.len()).any(|i| piece_meets_tet(&source.piece_corners(i), t)))
}
