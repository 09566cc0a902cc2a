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
//! The fit: at vertex v, the linear vector field g(x) = g_v + B (x − x_v) (B any
//! symmetric d × d matrix, as a quadratic's Hessian is, which the patch's frame below
//! keeps symmetric: d + d(d+1)/2 unknowns, 5 in the plane, 9 in space; a general B, 6
//! and 12, gave errors within 1% of these for twice the work) whose component along
//! each edge of the patch, at the edge's midpoint, is closest in the least-squares sense to the P1
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
//! Cost: the normal equations of an m × (d + d(d+1)/2) system per vertex, m the patch's edges
//! (about 12 for an inner vertex of a triangle mesh, 50 of a tetrahedral one, three times
//! that for a boundary vertex's two rings), accumulated edge by edge (no row is stored)
//! and solved by a 9 × 9 (5 × 5) Cholesky whose factor is the QR's up to signs, so the
//! determinacy test is the QR's: half the flops of the QR it replaced (a jittered cube
//! of 10⁵ vertices: 16.7 against 8.9 µs/vertex, same run), the stretched grids as exact
//! (worst 4.3e-10 at 100:1 in the plane, 9.4e-11 at 100:5:1 in space). Where the
//! quadratic fit solves m × (d + d(d+1)/2) on the patch's vertices (about 6 and 14): more
//! flops than the quadratic fit (BENCHMARKS.md has the times), linear in the values,
//! local, run in parallel over the vertices, the
//! result a function of the mesh and values only.

use rayon::prelude::*;

use nalgebra::{SMatrix, SVector};

use super::patch::{Adjacency, Patch};

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
struct Scratch {
    patch: Patch,
    edges: Vec<[u32; 2]>,
}

/// The recovered gradient at each vertex of the mesh of `points` whose cell edges are
/// `adjacency`, for the P1 field `values`: the edge fit, or `fallback[v]` where no patch
/// within [`MAX_RINGS`] determines it, or zero at a vertex no cell uses. `C` is the
/// number of unknowns, d + d(d+1)/2.
pub(super) fn recovered_gradients<const D: usize, const C: usize>(
    points: &[[f64; D]],
    adjacency: &Adjacency,
    values: &[f64],
    fallback: &[[f64; D]],
) -> Vec<[f64; D]> {
    const { assert!(C == D + D * (D + 1) / 2) };
    let n = points.len();
    (0..n)
        .into_par_iter()
        .map_init(
            || Scratch { patch: Patch::new(n), edges: Vec::new() },
            |s, v| {
                if !adjacency.is_used(v) {
                    return [0.0; D];
                }
                let Scratch { patch, edges } = s;
                patch
                    .grow_within(adjacency, v, 1, MAX_RINGS, |p| {
                        edges.clear();
                        for &a in std::iter::once(&(v as u32)).chain(p.others) {
                            let ends = adjacency.of(a as usize).iter();
                            edges
                                .extend(ends.filter(|&&b| b > a && p.contains(b)).map(|&b| [a, b]));
                        }
                        fit::<D, C>(points, values, v, edges)
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
    // The normal equations N c = r, N = Aᵀ A (upper triangle) and r = Aᵀ b, A the rows
    // t ⊗ (1, m): the patch's frame keeps N well conditioned (see `cholesky_solve`).
    let mut n = [[0.0; C]; C];
    let mut r = [0.0; C];
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
        // (t_i) for g, then (t_i m_i) for B_ii and (t_i m_j + t_j m_i) for B_ij, i < j.
        let mut row = [0.0; C];
        let mut k = D;
        for i in 0..D {
            row[i] = t[i];
            row[k] = t[i] * m[i];
            k += 1;
            for j in i + 1..D {
                row[k] = t[i] * m[j] + t[j] * m[i];
                k += 1;
            }
        }
        let rhs = (values[b as usize] - values[a as usize]) / len;
        for i in 0..C {
            for j in i..C {
                n[i][j] += row[i] * row[j];
            }
            r[i] += row[i] * rhs;
        }
    }
    // Unit columns, so that the determinacy test reads angles between them.
    let norms: [f64; C] = std::array::from_fn(|k| n[k][k].sqrt());
    if norms.iter().any(|&x| x <= 0.0 || !x.is_finite()) {
        return None;
    }
    for i in 0..C {
        for j in i..C {
            n[i][j] /= norms[i] * norms[j];
        }
        r[i] /= norms[i];
    }
    let c = cholesky_solve::<C>(&mut n, &r, DETERMINED)?;
    // The gradient in the frame is L^T g: back to x by L^-T = W^T.
    let gy = SVector::<f64, D>::from_fn(|k, _| c[k] / norms[k]);
    let g = w.transpose() * gy;
    Some(std::array::from_fn(|k| g[k]))
}

/// The solution of `n x = r`, `n` symmetric (its upper triangle read, overwritten by the
/// Cholesky factor Rᵀ R) with a unit diagonal; `None` when a diagonal entry of R is
/// below `determined` times the largest. R is the QR factor of the fit's rows up to
/// signs, so the test is the QR's; forming N squares the condition number, which the
/// patch's frame and the unit columns keep small (`determined` bounds it too): the
/// stretched grids of the tests stay exact to the same tolerance as by QR.
fn cholesky_solve<const C: usize>(
    n: &mut [[f64; C]; C],
    r: &[f64; C],
    determined: f64,
) -> Option<[f64; C]> {
    let mut largest = 0.0f64;
    for k in 0..C {
        let pivot = n[k][k] - (0..k).map(|i| n[i][k] * n[i][k]).sum::<f64>();
        // Not NaN and not below the test's bound so far (the largest only grows).
        if pivot.is_nan() || pivot <= 0.0 {
            return None;
        }
        let d = pivot.sqrt();
        largest = largest.max(d);
        if d < determined * largest {
            return None;
        }
        n[k][k] = d;
        for j in k + 1..C {
            let s = n[k][j] - (0..k).map(|i| n[i][k] * n[i][j]).sum::<f64>();
            n[k][j] = s / d;
        }
    }
    if (0..C).any(|k| n[k][k] < determined * largest) {
        return None;
    }
    // Rᵀ z = r, then R x = z.
    let mut z = [0.0; C];
    for k in 0..C {
        z[k] = (r[k] - (0..k).map(|i| n[i][k] * z[i]).sum::<f64>()) / n[k][k];
    }
    let mut x = [0.0; C];
    for k in (0..C).rev() {
        x[k] = (z[k] - (k + 1..C).map(|j| n[k][j] * x[j]).sum::<f64>()) / n[k][k];
    }
    Some(x)
}
