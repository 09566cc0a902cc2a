//! Size gradation (thesis 7.4.1, issue item 6): bounds how fast sizes may grow from a
//! vertex to its neighbours, so that a remesher never has to jump from a fine tensor to
//! a coarse one across one edge (the jump that appears at the maximum distance of an
//! algorithm whose largest size is far below the default size).
//!
//! Method: Alauzet's anisotropic metric gradation in its metric-space form ("Size
//! gradation control of anisotropic meshes", Finite Elem. Anal. Des. 46, 2010), with
//! the exponential growth law. For every mesh edge pq, with ℓ = ℓ_{M_p}(pq) the length
//! of the edge measured in the tensor at p, the tensor at q must lie inside the tensor
//! at p grown by
//!
//!   η(p, q) = g^ℓ   (g the plan's gradation, g >= 1),
//!
//! i.e. `T_q ⊆ η T_p` (same axes, both sizes times η). Where it does not, T_q is replaced
//! by its intersection with η T_p (thesis 3.2.2's robust intersection, as thesis 7.4.1
//! proposes): sizes only ever shrink. The exponential law is the one whose factors
//! compose along a path (g per unit of metric length, whatever the edges); its first
//! order is Alauzet's linear law 1 + ℓ ln g.
//!
//! Fixed point: a FIFO worklist holding every vertex once, in index order; a vertex
//! whose tensor shrinks queues again (if not queued). The pass ends when the queue is
//! empty: then the bound holds on every edge, both ways. Sequential, so deterministic.
//! To stop on rounding noise, a tensor is left alone when it lies inside η T_p grown by
//! a further relative [`SLACK`]; the bound then holds to that relative tolerance. As a
//! guard against a pathological slow convergence the pass stops after
//! [`MAX_UPDATES_PER_VERTEX`] × n updates and says so in its report.
//!
//! One driver for both dimensions: the worklist is `propagate_bounds`, generic over the
//! tensor type and given the one-edge rule as a closure; this file's 2D pass gives it
//! [`gradate_edge`] on a [`MeshGraph`], `sizing::gradation3` gives it
//! [`crate::metric::gradate_edge3`] on a mesh in space. So the order of visits, the
//! update guard and the report are the same code in 2D and 3D, and a fix to one is a fix
//! to both.
//!
//! Cost: each visit is one metric length, one power and one intersection per edge; in
//! practice a few visits per vertex.

use std::collections::VecDeque;

use crate::mesh_graph::MeshGraph;
use crate::metric::{gradate_edge_generic, GradedTensor, SizeTensor};

/// Relative tolerance of the gradation bound (see the module header).
pub const SLACK: f64 = 1e-9;

/// The pass gives up after this many updates per vertex on average.
pub const MAX_UPDATES_PER_VERTEX: usize = 64;

/// What a gradation pass did.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize)]
pub struct GradationReport {
    /// Vertices taken from the worklist.
    pub visits: usize,
    /// Tensors shrunk.
    pub updates: usize,
    /// Distinct vertices whose tensor shrunk at least once.
    pub vertices_changed: usize,
    /// Whether the fixed point was reached (false only when the update guard stopped it).
    pub converged: bool,
}

/// `t` with both sizes multiplied by `factor` (kept within [`SizeTensor::MAX_SIZE`]).
pub fn grow(t: &SizeTensor, factor: f64) -> SizeTensor {
    t.grown(factor)
}

/// The growth factor η = g^ℓ allowed from a vertex with tensor `from` along the edge
/// vector `edge`.
pub fn growth_factor(from: &SizeTensor, edge: [f64; 2], gradation: f64) -> f64 {
    gradation.powf(from.metric_length(edge))
}

/// The 2D edge rule: the tensor at q after bounding it by the one at p across the edge
/// vector `edge` = q − p with gradation `gradation` (>= 1): `Some(T_q ∩ η T_p)` when T_q
/// is not already inside η T_p (to [`SLACK`]), `None` when nothing changes. The twin of
/// [`crate::metric::gradate_edge3`].
pub fn gradate_edge(
    tp: &SizeTensor,
    tq: &SizeTensor,
    edge: [f64; 2],
    gradation: f64,
) -> Option<SizeTensor> {
    gradate_edge_generic(tp, tq, edge, gradation, SLACK)
}

/// Runs the gradation pass on `tensors` (one per vertex of `graph`) with gradation
/// `gradation` (>= 1; 1 allows no growth at all).
pub fn apply_gradation(
    graph: &MeshGraph,
    tensors: &mut [SizeTensor],
    gradation: f64,
) -> GradationReport {
    let n = graph.num_vertices().min(tensors.len());
    propagate_bounds(
        n,
        |p| graph.neighbours(p),
        tensors,
        |p, q, tp, tq| {
            let (xp, xq) = (graph.point(p), graph.point(q));
            gradate_edge(tp, tq, [xq[0] - xp[0], xq[1] - xp[1]], gradation)
        },
    )
}

/// The fixed point of the module header, whatever the dimension: `n` vertices whose
/// neighbours are `neighbours(p)`, one tensor of type `T` each (`tensors[..n]`), and the
/// one-edge rule `edge(p, q, T_p, T_q)`, which returns the shrunk T_q or `None` when T_q
/// already satisfies the bound. The 2D pass ([`apply_gradation`]) and the pass in space
/// (`sizing::gradation3`) differ only in their points, tensors and rule.
///
/// Invariants: vertices are visited in FIFO order from 0..n, neighbours in the order
/// given, so the result depends on nothing but the inputs (no threads, no hashing);
/// neighbours at or above `n` are skipped; at most [`MAX_UPDATES_PER_VERTEX`] × n + 1024
/// updates, after which the report says `converged: false`.
pub(crate) fn propagate_bounds<'g, T: Copy>(
    n: usize,
    neighbours: impl Fn(usize) -> &'g [u32],
    tensors: &mut [T],
    mut edge: impl FnMut(usize, usize, &T, &T) -> Option<T>,
) -> GradationReport {
    let mut report = GradationReport { converged: true, ..GradationReport::default() };
    let mut queued = vec![true; n];
    let mut changed = vec![false; n];
    let mut queue: VecDeque<u32> = (0..n as u32).collect();
    let max_updates = MAX_UPDATES_PER_VERTEX.saturating_mul(n).saturating_add(1024);
    while let Some(p) = queue.pop_front() {
        let p = p as usize;
        queued[p] = false;
        report.visits += 1;
        let tp = tensors[p];
        for &q in neighbours(p) {
            let q = q as usize;
            if q >= n {
                continue;
            }
            let Some(t) = edge(p, q, &tp, &tensors[q]) else { continue };
            tensors[q] = t;
            report.updates += 1;
            if !changed[q] {
                changed[q] = true;
                report.vertices_changed += 1;
            }
            if report.updates >= max_updates {
                report.converged = false;
                return report;
            }
            if !queued[q] {
                queued[q] = true;
                queue.push_back(q as u32);
            }
        }
    }
    report
}
