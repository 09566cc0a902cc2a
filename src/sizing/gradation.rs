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
//! Cost: each visit is one metric length, one power and one intersection per edge; in
//! practice a few visits per vertex.

use std::collections::VecDeque;

use crate::mesh_graph::MeshGraph;
use crate::metric::SizeTensor;

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
    let [h1, h2] = t.sizes();
    SizeTensor::from_parts(t.axis(), [h1 * factor, h2 * factor])
}

/// The growth factor η = g^ℓ allowed from a vertex with tensor `from` along the edge
/// vector `edge`.
pub fn growth_factor(from: &SizeTensor, edge: [f64; 2], gradation: f64) -> f64 {
    gradation.powf(from.metric_length(edge))
}

/// Runs the gradation pass on `tensors` (one per vertex of `graph`) with gradation
/// `gradation` (>= 1; 1 allows no growth at all).
pub fn apply_gradation(
    graph: &MeshGraph,
    tensors: &mut [SizeTensor],
    gradation: f64,
) -> GradationReport {
    let n = graph.num_vertices().min(tensors.len());
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
        let xp = graph.point(p);
        for &q in graph.neighbours(p) {
            let q = q as usize;
            if q >= n {
                continue;
            }
            let xq = graph.point(q);
            let eta = growth_factor(&tp, [xq[0] - xp[0], xq[1] - xp[1]], gradation);
            let tq = tensors[q];
            // Infinite or NaN: no bound; a grown disc that holds T_q: nothing to do.
            if !eta.is_finite() || tp.h_min() * eta >= tq.h_max() {
                continue;
            }
            let loose = grow(&tp, eta * (1.0 + SLACK));
            if tq.intersection(&loose) == tq {
                continue;
            }
            tensors[q] = tq.intersection(&grow(&tp, eta));
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
