//! The first half of the `l2-projection` recovery in every dimension: a gradient at each
//! vertex that is exact on quadratic fields, recovered from the P1 gradient where the P1
//! gradient itself is exact.
//!
//! Why edges: the P1 gradient of a field is constant on each cell, and on an irregular
//! cell it is the field's gradient at no one point, even for a quadratic (its error is a
//! linear function of the Hessian that depends on the cell's shape), so no weighted mean
//! of cell gradients around a vertex is exact on quadratics in general (J. Dalík proves
//! it for the triangles around an inner vertex). Its component along an edge ab is
//! another matter: it is (u_b − u_a)/|b − a| in every cell that holds the edge, and for
//! a quadratic it equals the exact derivative along the edge at the edge's midpoint (the
//! mean value theorem, exact for a quadratic at the midpoint).
//!
//! The fit: at vertex v, the linear vector field g(x) = g_v + B (x − x_v) (B any d × d
//! matrix: d + d² unknowns, 6 in the plane, 12 in space) whose component along each edge
//! of the patch, at the edge's midpoint, is closest in the least-squares sense to the P1
//! gradient's: Σ over the edges ab of (t·g(m) − (u_b − u_a)/|b − a|)², t the edge's unit
//! tangent, m its midpoint. That is the discrete L2 projection of the P1 gradient onto
//! linear vector fields over the patch, sampled where it is exact (a patch recovery in
//! the manner of Zienkiewicz and Zhu, whose samples, cell gradients at centroids, are
//! exact only on symmetric patches). The gradient of a quadratic is such a linear field
//! and matches every sample, so the fit returns it exactly whenever it is determined.
//! The recovered gradient at v is g_v.
//!
//! The patch: the edges between the vertices within k edges of v (its star's edges for
//! k = 1: the edges to v and those joining two neighbours), k = 1 first, grown one ring
//! at a time until the fit is determined, at most [`MAX_RINGS`] rings. The fit is solved
//! in the patch's own frame, y = L⁻¹ (x − x_v) with L Lᵀ the second moment of its edge
//! vectors, where the edges are of unit mean square length in every direction: a
//! linear field is linear in any affine frame, so exactness is kept, and a stretched
//! patch (an anisotropic mesh, the kind this recovery sizes) is as well conditioned as an
//! isotropic one (without the frame, every vertex of the tests' grid stretched 100:1 at
//! an angle fell back to the plain projection). Determined: the triangular factor of the system with unit
//! columns has no diagonal entry below [`DETERMINED`] times its largest. Interior vertices
//! take their star; boundary vertices, whose one-sided star leaves B undetermined (on a
//! flat side, always), take two rings or more. A vertex whose connected part runs out,
//! or that needs more than [`MAX_RINGS`] rings (a degenerate patch: cells of zero area or
//! volume), keeps the lumped projection of its cells' gradients, exact on linear fields
//! only.
//!
//! Cost: one QR of an m × (d + d²) system per vertex, m the patch's edges (about 12 for
//! an inner vertex of a triangle mesh, 50 of a tetrahedral one, three times that for a
//! boundary vertex's two rings), where the quadratic fit solves m × (d + d(d+1)/2) on
//! the patch's vertices (about 6 and 14): more flops than the quadratic fit (BENCHMARKS.md
//! has the times), linear in the values, local, run in parallel over the vertices, the
//! result a function of the mesh and values only.

use rayon::prelude::*;

use nalgebra::{SMatrix, SVector};

use super::patch::{least_squares, Adjacency, Patch};

/// Smallest ratio of the triangular factor's diagonal entries (unit columns, the patch's
/// frame) for a determined fit. Measured on jittered and mapped grids, Delaunay meshes
/// and Gmsh's (a cube, a ball, a disk): inner vertices' stars 0.6 to 0.99 (but for the
/// singular stars of three triangles), boundary vertices' two rings 0.24 to 0.76, their
/// one-sided stars mostly singular (1e-16) but up to 0.27 on a jittered grid's flat side.
/// Such stars, accepted at a threshold of 1e-2, gave a smooth field's Hessian errors of
/// 20 (the field's Hessian is about 5) at the boundary of a jittered 10³ grid; at 0.25
/// the worst error falls at first order with h (the tests).
const DETERMINED: f64 = 0.25;

/// Most rings a patch grows: the boundary vertices of the tests' meshes (grids,
/// jittered grids, Delaunay and Gmsh meshes, corners included) take two or three.
const MAX_RINGS: usize = 4;

/// What each thread keeps between vertices.
struct Scratch<const C: usize> {
    patch: Patch,
    edges: Vec<[u32; 2]>,
    rows: Vec<[f64; C]>,
    rhs: Vec<f64>,
}

/// The recovered gradient at each vertex of the mesh of `points` whose cell edges are
/// `adjacency`, for the P1 field `values`: the edge fit, or `fallback[v]` where no patch
/// within [`MAX_RINGS`] determines it, or zero at a vertex no cell uses. `C` is the
/// number of unknowns, d + d².
pub(super) fn recovered_gradients<const D: usize, const C: usize>(
    points: &[[f64; D]],
    adjacency: &Adjacency,
    values: &[f64],
    fallback: &[[f64; D]],
) -> Vec<[f64; D]> {
    const { assert!(C == D + D * D) };
    let n = points.len();
    (0..n)
        .into_par_iter()
        .map_init(
            || Scratch::<C> {
                patch: Patch::new(n),
                edges: Vec::new(),
                rows: Vec::new(),
                rhs: Vec::new(),
            },
            |s, v| {
                if !adjacency.is_used(v) {
                    return [0.0; D];
                }
                let Scratch { patch, edges, rows, rhs } = s;
                patch
                    .grow_within(adjacency, v, 1, MAX_RINGS, |p| {
                        edges.clear();
                        for &a in std::iter::once(&(v as u32)).chain(p.others) {
                            let ends = adjacency.of(a as usize).iter();
                            edges
                                .extend(ends.filter(|&&b| b > a && p.contains(b)).map(|&b| [a, b]));
                        }
                        fit::<D, C>(points, values, v, edges, rows, rhs)
                    })
                    .unwrap_or(fallback[v])
            },
        )
        .collect()
}

/// The edge fit at `v` on the patch's `edges`, `None` when it is not determined.
fn fit<const D: usize, const C: usize>(
    points: &[[f64; D]],
    values: &[f64],
    v: usize,
    edges: &[[u32; 2]],
    rows: &mut Vec<[f64; C]>,
    rhs: &mut Vec<f64>,
) -> Option<[f64; D]> {
    if edges.len() < C {
        return None;
    }
    let x = points[v];
    let offset = |w: u32| SVector::<f64, D>::from_fn(|k, _| points[w as usize][k] - x[k]);
    // The patch's frame: y = L⁻¹ (x − x_v), L L^T the edges' second moment, in which the
    // edges are of unit mean square length in every direction.
    let mut moment = SMatrix::<f64, D, D>::zeros();
    for &[a, b] in edges {
        let e = offset(b) - offset(a);
        moment += e * e.transpose();
    }
    let l = (moment / edges.len() as f64).cholesky()?.unpack();
    let w = l.solve_lower_triangular(&SMatrix::<f64, D, D>::identity())?;
    rows.clear();
    rhs.clear();
    for &[a, b] in edges {
        let (ya, yb) = (w * offset(a), w * offset(b));
        let e = yb - ya;
        let len = e.norm();
        if !(len > 0.0 && len.is_finite()) {
            return None;
        }
        // The unit tangent and the midpoint in the patch's frame.
        let t = e / len;
        let m = (ya + yb) * 0.5;
        let mut row = [0.0; C];
        for i in 0..D {
            row[i] = t[i];
            for j in 0..D {
                row[D + i * D + j] = t[i] * m[j];
            }
        }
        rows.push(row);
        rhs.push((values[b as usize] - values[a as usize]) / len);
    }
    // Unit columns, so that the determinacy test reads angles between them.
    let mut norms = [0.0; C];
    for row in rows.iter() {
        for (n, r) in norms.iter_mut().zip(row) {
            *n += r * r;
        }
    }
    let norms = norms.map(f64::sqrt);
    if norms.iter().any(|&n| n <= 0.0 || !n.is_finite()) {
        return None;
    }
    for row in rows.iter_mut() {
        for (r, n) in row.iter_mut().zip(&norms) {
            *r /= n;
        }
    }
    let c = least_squares::<C>(rows, rhs, DETERMINED)?;
    // The gradient in the frame is L^T g: back to x by L^-T = W^T.
    let gy = SVector::<f64, D>::from_fn(|k, _| c[k] / norms[k]);
    let g = w.transpose() * gy;
    Some(std::array::from_fn(|k| g[k]))
}
